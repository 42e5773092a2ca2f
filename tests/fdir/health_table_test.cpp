/**
 * @file health_table_test.cpp
 * @brief Table-driven monitors (FDIR-HT-xx): debounce, warn and fatal, the action, its cap.
 */
#include "fdir/health_table.hpp"

#include "fdir/assert.hpp"
#include "tests/fdir/fdir_fixture.hpp"

#include <gtest/gtest.h>

namespace {

constexpr fdir::MonitorSpec kSpec{"misses", 2U, 4U, 3U, fdir::MonitorAction::kRestart, 2U};
static_assert(fdir::monitor_spec_ok(kSpec));
static_assert(!fdir::monitor_spec_ok(fdir::MonitorSpec{"bad", 5U, 4U, 1U, fdir::MonitorAction::kReport, 1U}));

// FDIR-HT-01: a status changes only after `debounce` identical verdicts in a row.
TEST(HealthTable, AStatusChangesOnlyAfterTheDebounceCount) {
  fdir::MonitorState s{};
  EXPECT_FALSE(fdir::monitor_sample(kSpec, s, 0U, 9U).changed);
  EXPECT_FALSE(fdir::monitor_sample(kSpec, s, 0U, 9U).changed);
  EXPECT_FALSE(fdir::monitor_sample(kSpec, s, 0U, 0U).changed) << "an ok sample restarts the count";
  EXPECT_FALSE(fdir::monitor_sample(kSpec, s, 0U, 9U).changed);
  EXPECT_FALSE(fdir::monitor_sample(kSpec, s, 0U, 9U).changed);
  const fdir::MonitorResult r = fdir::monitor_sample(kSpec, s, 0U, 9U);
  EXPECT_TRUE(r.changed);
  EXPECT_EQ(r.status, fdir::MonitorStatus::kFatal);
  EXPECT_TRUE(r.act);
}

TEST(HealthTable, WarnBelowFatal) {
  fdir::MonitorState s{};
  fdir::MonitorResult r{};
  for (int i = 0; i < 3; ++i) {
    r = fdir::monitor_sample(kSpec, s, 0U, 2U);
  }
  EXPECT_EQ(r.status, fdir::MonitorStatus::kWarn);
  EXPECT_FALSE(r.act);
}

// FDIR-HT-02: the action is asked for at most max_actions times; then capped, said once.
TEST(HealthTable, TheActionIsCappedSoAFaultCannotCauseAResetLoop) {
  fdir_test::run_on_tile0([] {
    static fdir::MonitorState s{};
    static std::uint32_t acts = 0;
    for (int cycle = 0; cycle < 5; ++cycle) {
      for (int i = 0; i < 3; ++i) {
        acts += fdir::monitor_sample(kSpec, s, 7U, 9U).act ? 1U : 0U;
      }
      fdir::monitor_clear(s);  // the tile was restarted: its status starts afresh, the count does not
    }
    fdir::report(fdir::EventId::kMapPushed, acts, 0U);  // hands the count to the test
  });
  std::uint32_t fatal = 0;
  std::uint32_t capped = 0;
  std::uint32_t acts = 99;
  for (const fdir::Event& e : fdir_test::events_of(0)) {
    fatal += e.id == fdir::EventId::kMonitorFatal ? 1U : 0U;
    capped += e.id == fdir::EventId::kActionCapped ? 1U : 0U;
    acts = e.id == fdir::EventId::kMapPushed ? e.subject : acts;
  }
  EXPECT_EQ(fatal, 5U) << "every entry into fatal is an event";
  EXPECT_EQ(acts, 2U) << "the action twice, as the table allows";
  EXPECT_EQ(capped, 1U);
}

// FDIR-AS-01: a failed check returns false, writes the event and raises the recovery request.
TEST(Assert, AFailedCheckIsAnEventAndARecoveryRequestNeverAnAbort) {
  fdir_test::run_on_tile0([] {
    fdir::recovery_clear(0);
    const bool ok = fdir::check(1 + 1 == 3, 0x77U);
    fdir::report(fdir::EventId::kMapPushed, ok ? 1U : 0U, 0U);
  });
  const std::vector<fdir::Event> ev = fdir_test::events_of(0);
  ASSERT_EQ(ev.size(), 2U);
  EXPECT_EQ(ev[0].id, fdir::EventId::kAssertFailed);
  EXPECT_EQ(ev[0].subject, 0x77U);
  EXPECT_GT(ev[0].cause, 0U) << "the line";
  EXPECT_EQ(ev[1].subject, 0U) << "check returned false";
  EXPECT_EQ(fdir::recovery_requested(0), 1U);
}

}  // namespace
