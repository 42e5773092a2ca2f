/**
 * @file accusation_test.cpp
 * @brief Whom each event accuses and of what (fdir/accusation.hpp): the table's class, refined by the
 *        fields where one id says two things.
 */
#include "fdir/accusation.hpp"

#include <gtest/gtest.h>

namespace {

using fdir::Diagnosis;
using fdir::EventId;

fdir::Event ev(EventId id, bsp::TileId writer, std::uint32_t subject, std::uint32_t cause = 0U, std::uint32_t a = 0U,
               std::uint32_t b = 0U) {
  fdir::Event e{};
  e.id = id;
  e.tile = writer;
  e.subject = subject;
  e.cause = cause;
  e.a = a;
  e.b = b;
  return e;
}

TEST(Accusation, EveryDetectionOfATileSaysWhatItAccuses) {
  // Every event that is a detection of the table either accuses with a class or is a notice the
  // join reads otherwise (a delivery given up, a level not met): listed here so a new id must choose.
  for (const fdir::EventInfo& e : fdir::kEventTable) {
    if ((e.steps & fdir::kStepDetect) == 0U || e.diagnosis != Diagnosis::kNone) {
      continue;
    }
    const bool notice = e.id == EventId::kPacketGaveUp || e.id == EventId::kRouteUnreachable ||
                        e.id == EventId::kForwardUnreachable || e.id == EventId::kPacketSettled ||
                        e.id == EventId::kVisionSetUpFailed || e.id == EventId::kLandmarkProductRefused ||
                        e.id == EventId::kMonitorWarn || e.id == EventId::kMonitorFatal ||
                        e.id == EventId::kTileLost || e.id == EventId::kImuGap || e.id == EventId::kSupNotMet;
    EXPECT_TRUE(notice) << e.name << " detects, but accuses nothing";
  }
}

TEST(Accusation, TheFieldsRefineTheClass) {
  EXPECT_EQ(fdir::accusation_of(ev(EventId::kTmrOutvoted, 18U, 20U, 700U, 1U, 1U)).diagnosis, Diagnosis::kWrongResult);
  EXPECT_EQ(fdir::accusation_of(ev(EventId::kTmrOutvoted, 18U, 20U, 700U, 1U, 2U)).diagnosis, Diagnosis::kCoreSilent);
  EXPECT_EQ(fdir::accusation_of(ev(EventId::kTileRebooted, 0U, 12U, 3U)).diagnosis, Diagnosis::kCoreCrashed);
  EXPECT_EQ(fdir::accusation_of(ev(EventId::kTileRebooted, 0U, 12U, 2U)).diagnosis, Diagnosis::kCoreSilent);
  EXPECT_EQ(fdir::accusation_of(ev(EventId::kTileRebooted, 0U, 12U, 1U)).diagnosis, Diagnosis::kNone);
  EXPECT_EQ(fdir::accusation_of(ev(EventId::kCoarseBandRedone, 1U, 30U, 4U)).diagnosis, Diagnosis::kWrongResult);
  EXPECT_EQ(fdir::accusation_of(ev(EventId::kCoarseBandRedone, 1U, 30U, 2U)).diagnosis, Diagnosis::kSuspicion);
  EXPECT_EQ(fdir::accusation_of(ev(EventId::kCoarseBandRedone, 1U, 30U, 1U)).diagnosis, Diagnosis::kNone);
}

TEST(Accusation, TheTilesNamed) {
  const fdir::Accusation overdue = fdir::accusation_of(ev(EventId::kTaskOverdue, 35U, 2U, 35U));
  ASSERT_EQ(overdue.count, 1U);
  EXPECT_EQ(overdue.tiles[0], 35U) << "the task's tile (cause), not its id";
  const fdir::Accusation link = fdir::accusation_of(ev(EventId::kLinkFailed, 0U, 51U, 52U));
  EXPECT_EQ(link.count, 2U);
  EXPECT_TRUE(link.names(51U) && link.names(52U));
  const fdir::Accusation own = fdir::accusation_of(ev(EventId::kFilterStateBad, 18U, 300U, 6U));
  EXPECT_TRUE(own.names(18U) && own.count == 1U) << "the writer, about itself";
  // Replicas 0 and 2 different: tiles 19 and 21 named, 20 not.
  const std::uint32_t tiles = (19U << 8U) | (20U << 16U) | (21U << 24U);
  const fdir::Accusation vote = fdir::accusation_of(ev(EventId::kTmrNoMajority, 18U, 700U, 0U, 5U, tiles));
  EXPECT_EQ(vote.count, 2U);
  EXPECT_TRUE(vote.names(19U) && vote.names(21U) && !vote.names(20U));
  EXPECT_EQ(fdir::accusation_of(ev(EventId::kPacketDamaged, 1U, fdir::kUnknown)).count, 0U)
      << "a packet accuses no tile";
  EXPECT_EQ(fdir::accusation_of(ev(EventId::kWatchdogExpired, 0U, fdir::kUnknown)).count, 0U);
  EXPECT_FALSE(fdir::is_diagnosis(fdir::accusation_of(ev(EventId::kNeighbourSuspect, 31U, 30U)).diagnosis));
  EXPECT_STREQ(fdir::diagnosis_name(Diagnosis::kSwitchOrLink), "switch_or_link");
}

}  // namespace
