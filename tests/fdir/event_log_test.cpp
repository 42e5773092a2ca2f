/**
 * @file event_log_test.cpp
 * @brief The flight event log: what a tile reports is read back whole, in order, with its
 *        table row; a full ring overwrites the oldest and says so; a bad id is not lost.
 */
#include "fdir/event_log.hpp"

#include "tests/fdir/fdir_fixture.hpp"

#include <gtest/gtest.h>

namespace {

// FDIR-EV-02: an event carries id, severity and steps from the table, tile, time, subject, cause.
TEST(EventLog, AReportIsReadBackWithItsTableRowTileAndTime) {
  fdir_test::run_on_tile0([] {
    k::sleep(2);
    fdir::report(fdir::EventId::kSwitchFailed, 44U, 36U, 2U, 7U);
  });
  const std::vector<fdir::Event> ev = fdir_test::events_of(0);
  ASSERT_EQ(ev.size(), 1U);
  EXPECT_EQ(ev[0].id, fdir::EventId::kSwitchFailed);
  EXPECT_EQ(ev[0].tile, 0U);
  EXPECT_EQ(ev[0].subject, 44U);
  EXPECT_EQ(ev[0].cause, 36U);
  EXPECT_EQ(ev[0].a, 2U);
  EXPECT_EQ(ev[0].b, 7U);
  EXPECT_EQ(ev[0].severity, fdir::Severity::kWarningHi);
  EXPECT_EQ(ev[0].steps, fdir::kStepDetect | fdir::kStepIsolate);
  EXPECT_GE(ev[0].cycle, 2U * fdir_test::kTick) << "written at the tile's time";
  EXPECT_EQ(fdir::event_log_written(1), 0U) << "other tiles' rings untouched";
}

// FDIR-EV-03: a full ring keeps the newest kRingEvents and counts every one written.
TEST(EventLog, AFullRingOverwritesTheOldestAndCountsEveryEvent) {
  fdir_test::run_on_tile0([] {
    for (std::uint32_t i = 0; i < fdir::kRingEvents + 10U; ++i) {
      fdir::report(fdir::EventId::kPacketCorrected, i, 0U);
    }
  });
  EXPECT_EQ(fdir::event_log_written(0), fdir::kRingEvents + 10U);
  fdir::Event e{};
  EXPECT_FALSE(fdir::event_log_read(0, 9U, &e)) << "overwritten";
  ASSERT_TRUE(fdir::event_log_read(0, 10U, &e));
  EXPECT_EQ(e.subject, 10U);
  ASSERT_TRUE(fdir::event_log_read(0, fdir::kRingEvents + 9U, &e));
  EXPECT_EQ(e.subject, fdir::kRingEvents + 9U);
  EXPECT_FALSE(fdir::event_log_read(0, fdir::kRingEvents + 10U, &e)) << "not written yet";
}

// FDIR-EV-04: an id outside the table is written as a failed assertion naming it.
TEST(EventLog, AnIdOutsideTheTableIsReportedAsAFailedAssertion) {
  fdir_test::run_on_tile0([] { fdir::report(static_cast<fdir::EventId>(0x0999), 5U, 6U); });
  const std::vector<fdir::Event> ev = fdir_test::events_of(0);
  ASSERT_EQ(ev.size(), 1U);
  EXPECT_EQ(ev[0].id, fdir::EventId::kAssertFailed);
  EXPECT_EQ(ev[0].cause, 0x0999U);
}

TEST(EventLog, EveryTableRowHasANameAndAStepOrIsInformation) {
  for (const fdir::EventInfo& e : fdir::kEventTable) {
    EXPECT_NE(e.name, nullptr);
    EXPECT_EQ(fdir::event_info(e.id), &e);
    if (e.steps == fdir::kStepNone) {
      EXPECT_NE(e.severity, fdir::Severity::kWarningHi) << e.name << ": a warning that is no step";
    }
  }
}

}  // namespace
