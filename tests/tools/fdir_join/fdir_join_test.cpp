/**
 * @file fdir_join_test.cpp
 * @brief The host's join of flight events to the injector's ground truth (docs/FDIR.md, "The join"):
 *        each injection is credited only to an event that names what it did.
 */
#include "tools/common/fdir_join.hpp"

#include "trn/tasks/filter_core.hpp"

#include <gtest/gtest.h>

#include <array>
#include <vector>

namespace {

constexpr double kHz = 1.0e6;  // one cycle per microsecond keeps the times readable

bsp::FaultRecord record(bsp::FaultKind kind, bsp::TileId tile, bsp::Cycles at) {
  bsp::FaultRecord r{};
  r.spec.kind = kind;
  r.spec.tile = tile;
  r.spec.cycle = at;
  r.status = bsp::FaultStatus::kApplied;
  r.applied_cycle = at;
  return r;
}

/** An upset in the EKF's carve of @p tile, @p offset bytes from its start (its settings come first). */
bsp::FaultRecord settings_upset(bsp::TileId tile, bsp::Cycles at, std::uint64_t offset) {
  bsp::FaultRecord r = record(bsp::FaultKind::kSeu, tile, at);
  r.carve = trn::tasks::kEkfCarve;
  r.carve_offset = offset;
  return r;
}

fdir::Event event(fdir::EventId id, bsp::TileId writer, std::uint32_t subject, bsp::Cycles at,
                  std::uint32_t cause = 0U) {
  fdir::Event e{};
  e.id = id;
  e.tile = writer;
  e.subject = subject;
  e.cause = cause;
  e.cycle = at;
  const fdir::EventInfo* info = fdir::event_info(id);
  e.steps = info != nullptr ? info->steps : 0U;
  return e;
}

// FDIR-AB-05: a product's check reports in the job the product was corrupted in; an sdc below the
// round-off is never seen, and the check of a later corrupted product is not credited to it.
TEST(FdirJoin, AProductCheckIsCreditedOnlyToTheSdcOfItsOwnJob) {
  const std::array<bsp::FaultRecord, 2> faults{record(bsp::FaultKind::kSdc, 18U, 3'001'000U),
                                               record(bsp::FaultKind::kSdc, 18U, 4'001'000U)};
  const std::vector<fdir::Event> events{event(fdir::EventId::kAbftCorrected, 18U, 1U, 4'001'000U)};
  const tools::FaultAccount a = tools::join_faults(faults, events, kHz);
  EXPECT_EQ(a.injected, 2U);
  EXPECT_EQ(a.detected, 1U);
  EXPECT_EQ(a.recovered, 1U);
  ASSERT_EQ(a.outcomes.size(), 2U);
  EXPECT_FALSE(a.outcomes[0].detected) << "the first flip was below the round-off: nothing saw it";
  EXPECT_TRUE(a.outcomes[1].detected);
  // Another tile's check is not this tile's.
  const std::vector<fdir::Event> other{event(fdir::EventId::kAbftCorrected, 20U, 1U, 4'001'000U)};
  EXPECT_EQ(tools::join_faults(faults, other, kHz).detected, 0U);
}

// FDIR-CC-06: a correlation check is credited to an sdc on a correlation point of its own tile, in
// the landmark it was injected in: not to another point's sdc, nor to an older one.
TEST(FdirJoin, ACorrelationCheckIsCreditedOnlyToACorrelationSdcOfItsTile) {
  std::array<bsp::FaultRecord, 3> faults{record(bsp::FaultKind::kSdc, 24U, 3'001'000U),
                                         record(bsp::FaultKind::kSdc, 24U, 4'001'000U),
                                         record(bsp::FaultKind::kSdc, 25U, 4'002'000U)};
  faults[0].spec.channel = 10U;  // correlation_dot, 1 s before the check: another landmark's
  faults[1].spec.channel = 10U;
  faults[2].spec.channel = 3U;   // vision_matches on another tile: no correlation of it
  const std::vector<fdir::Event> events{event(fdir::EventId::kCorrelationCorrected, 24U, 12U, 4'006'000U, 1U),
                                        event(fdir::EventId::kCorrelationCorrected, 25U, 7U, 4'006'000U, 1U)};
  const tools::FaultAccount a = tools::join_faults(faults, events, kHz);
  ASSERT_EQ(a.outcomes.size(), 3U);
  EXPECT_FALSE(a.outcomes[0].detected);
  EXPECT_TRUE(a.outcomes[1].detected);
  EXPECT_TRUE(a.outcomes[1].recovered) << "correlation_corrected detects and recovers";
  EXPECT_FALSE(a.outcomes[2].detected) << "a correlation check says nothing of the tile's sent matches";
  faults[1].spec.channel = 9U;  // correlation_surface
  EXPECT_EQ(tools::join_faults(faults, events, kHz).detected, 1U);
}

// FDIR-JN-02: an upset on one tile is not credited to a neighbour's report about another tile, nor to
// a watchdog of the same tile (a tile with wrong data still answers); only a self-test naming it.
TEST(FdirJoin, AnUpsetIsCreditedOnlyToASelfTestThatNamesItsTile) {
  const std::array<bsp::FaultRecord, 1> faults{record(bsp::FaultKind::kSeu, 35U, 1'000'000U)};
  const std::vector<fdir::Event> unrelated{
      event(fdir::EventId::kLinkFailed, 0U, 43U, 1'100'000U, 35U),
      event(fdir::EventId::kNeighbourSuspect, 36U, 35U, 1'200'000U),
      event(fdir::EventId::kSelfTestMismatch, 0U, 36U, 1'300'000U),
  };
  const tools::FaultAccount none = tools::join_faults(faults, unrelated, kHz);
  EXPECT_EQ(none.injected, 1U);
  EXPECT_EQ(none.detected, 0U);

  std::vector<fdir::Event> named = unrelated;
  named.push_back(event(fdir::EventId::kSelfTestMismatch, 0U, 35U, 1'400'000U));
  named.push_back(event(fdir::EventId::kSelfTestAgree, 0U, 35U, 1'450'000U));
  const tools::FaultAccount hit = tools::join_faults(faults, named, kHz);
  ASSERT_EQ(hit.detected, 1U);
  EXPECT_EQ(hit.recovered, 1U);
  EXPECT_EQ(hit.outcomes[0].detected_by, fdir::EventId::kSelfTestMismatch);
  EXPECT_NEAR(hit.outcomes[0].detected_s - hit.outcomes[0].injected_s, 0.4, 1e-9);
}

// FDIR-FS-06: a settings check is credited to an upset of its tile (never to an sdc), and its
// recovery is the filter's resume. A resume holds unless the filter refuses a job again and resumes
// from the same checkpoint (its restart): then the recovery is that later resume. An independent
// refusal a second later, from a newer checkpoint, does not undo the first recovery (it did under a
// 1 s window before).
TEST(FdirJoin, AFilterResumeHoldsUnlessTheSameCheckpointIsGoneBackToAgain) {
  using fdir::EventId;
  const std::array<bsp::FaultRecord, 2> faults{settings_upset(18U, 3'000'000U, 71U),
                                               settings_upset(18U, 3'900'000U, 151U)};
  const std::vector<fdir::Event> apart{
      event(EventId::kFilterSettingsBad, 18U, 300U, 3'002'000U, 1U),
      event(EventId::kFilterResumed, 18U, 30U, 3'002'100U),
      event(EventId::kFilterSettingsBad, 18U, 390U, 3'901'000U, 2U),
      event(EventId::kFilterResumed, 18U, 39U, 3'901'100U),
  };
  const tools::FaultAccount a = tools::join_faults(faults, apart, kHz);
  ASSERT_EQ(a.detected, 2U);
  EXPECT_EQ(a.recovered, 2U);
  EXPECT_EQ(a.outcomes[0].detected_by, EventId::kFilterSettingsBad);
  EXPECT_NEAR(a.outcomes[0].recovered_s, 3.0021, 1e-9) << "its own resume: the next one is from checkpoint 39";

  const std::vector<fdir::Event> again{
      event(EventId::kFilterStateBad, 18U, 300U, 3'002'000U, 6U),
      event(EventId::kFilterResumed, 18U, 30U, 3'002'100U),
      event(EventId::kFilterStateBad, 18U, 301U, 3'012'000U, 6U),
      event(EventId::kAssertFailed, 18U, 0x0605U, 3'012'100U),
      event(EventId::kFilterResumed, 18U, 30U, 3'030'000U),  // after the tile's restart
  };
  const std::array<bsp::FaultRecord, 1> one{settings_upset(18U, 3'000'000U, 71U)};
  const tools::FaultAccount b = tools::join_faults(one, again, kHz);
  ASSERT_EQ(b.recovered, 1U);
  EXPECT_NEAR(b.outcomes[0].recovered_s, 3.030, 1e-9) << "the first resume did not hold";

  // No resume after the refusal before the flight ended: not recovered.
  const std::vector<fdir::Event> cut(again.begin(), again.begin() + 4);
  EXPECT_EQ(tools::join_faults(one, cut, kHz).recovered, 0U);

  // An sdc is never credited to the settings check.
  const std::array<bsp::FaultRecord, 1> sdc{record(bsp::FaultKind::kSdc, 18U, 3'000'000U)};
  const std::vector<fdir::Event> settings{event(EventId::kFilterSettingsBad, 18U, 300U, 3'002'000U, 1U)};
  EXPECT_EQ(tools::join_faults(sdc, settings, kHz).detected, 0U);
}

// FDIR-FS-07: only an upset in the settings' bytes takes the settings check. An upset deep in the
// EKF two seconds before one in its camera took that one's detection, and the camera's went unseen.
TEST(FdirJoin, TheSettingsCheckIsCreditedOnlyToAnUpsetInTheSettings) {
  using fdir::EventId;
  const std::array<bsp::FaultRecord, 3> faults{settings_upset(18U, 20'000'000U, 0x5000U),  // the EKF's history
                                               record(bsp::FaultKind::kSeu, 18U, 21'000'000U),  // uncarved RAM
                                               settings_upset(18U, 22'000'000U, 200U)};
  const std::vector<fdir::Event> events{event(EventId::kFilterSettingsBad, 18U, 2200U, 22'001'500U, 2U),
                                        event(EventId::kFilterResumed, 18U, 220U, 22'001'600U)};
  const tools::FaultAccount a = tools::join_faults(faults, events, kHz);
  ASSERT_EQ(a.detected, 1U);
  EXPECT_FALSE(a.outcomes[0].detected) << "outside the settings";
  EXPECT_FALSE(a.outcomes[1].detected) << "in no carve";
  ASSERT_TRUE(a.outcomes[2].detected);
  EXPECT_NEAR(a.outcomes[2].detected_s - a.outcomes[2].injected_s, 0.0015, 1e-9);
  EXPECT_TRUE(a.outcomes[2].recovered);
}

// A hang is still credited to the tile's watchdog and recovered by the tile's return.
TEST(FdirJoin, AHangIsCreditedToItsWatchdogAndRecoveredByTheTile) {
  const std::array<bsp::FaultRecord, 1> faults{record(bsp::FaultKind::kCoreHang, 18U, 2'000'000U)};
  const std::vector<fdir::Event> events{
      event(fdir::EventId::kWatchdogExpired, 0U, 19U, 2'010'000U),  // another tile: not this one
      event(fdir::EventId::kWatchdogExpired, 0U, 18U, 2'016'000U),
      event(fdir::EventId::kTileRecovered, 0U, 18U, 2'030'000U),
  };
  const tools::FaultAccount a = tools::join_faults(faults, events, kHz);
  ASSERT_EQ(a.detected, 1U);
  EXPECT_EQ(a.recovered, 1U);
  EXPECT_NEAR(a.outcomes[0].detected_s - a.outcomes[0].injected_s, 0.016, 1e-9);
  EXPECT_NEAR(a.outcomes[0].recovered_s, 2.030, 1e-9);
}

// A detection that comes before the fault, or after the 5 s window, is not the fault's.
TEST(FdirJoin, ADetectionOutsideTheWindowIsNotTheFaults) {
  const std::array<bsp::FaultRecord, 1> faults{record(bsp::FaultKind::kCoreHang, 18U, 2'000'000U)};
  const std::vector<fdir::Event> events{
      event(fdir::EventId::kWatchdogExpired, 0U, 18U, 1'900'000U),
      event(fdir::EventId::kWatchdogExpired, 0U, 18U, 7'100'000U),
  };
  EXPECT_EQ(tools::join_faults(faults, events, kHz).detected, 0U);
}

/** The outcome of one bit flip on tile 30's packet, dropped damaged by tile 1, against @p after. */
tools::FaultOutcome damaged_then(std::uint32_t named_source, const std::vector<fdir::Event>& after) {
  const std::array<bsp::FaultRecord, 1> faults{record(bsp::FaultKind::kPacketBitFlip, 30U, 1'000'000U)};
  std::vector<fdir::Event> events{event(fdir::EventId::kPacketDamaged, 1U, named_source, 1'000'100U)};
  events.insert(events.end(), after.begin(), after.end());
  const tools::FaultAccount a = tools::join_faults(faults, events, kHz);
  EXPECT_EQ(a.detected, 1U);
  return a.outcomes.at(0);
}

// FDIR-JN-03: a damaged packet is recovered only by a resend that brings it again, soon. Named source
// (the receiver NACKed it): that source's resend to the tile that dropped it. Source hidden by the
// damage (dropped at the receiver or at a forwarder): a resend by the flipped tile (its data), or to
// it (its lost ACK). A resend between other tiles, or seconds later, is another packet's.
TEST(FdirJoin, ADamagedPacketIsRecoveredOnlyByAResendThatBringsItAgain) {
  using fdir::EventId;
  const std::uint32_t unknown = fdir::kUnknown;
  tools::FaultOutcome o = damaged_then(unknown, {event(EventId::kPacketResent, 5U, 7U, 1'010'000U, 1U),
                                                 event(EventId::kPacketResent, 1U, 9U, 1'011'000U, 1U),
                                                 event(EventId::kPacketResent, 30U, 1U, 4'000'000U, 1U)});
  EXPECT_FALSE(o.recovered) << "nothing resent by or to tile 30 in time";
  o = damaged_then(unknown, {event(EventId::kPacketResent, 5U, 7U, 1'010'000U, 1U),
                             event(EventId::kPacketResent, 30U, 2U, 1'020'000U, 1U)});
  EXPECT_TRUE(o.recovered);
  EXPECT_NEAR(o.recovered_s, 1.020, 1e-9) << "tile 30's timeout resend (dropped on the way to tile 2)";
  o = damaged_then(unknown, {event(EventId::kPacketResent, 9U, 30U, 1'030'000U, 1U)});
  EXPECT_TRUE(o.recovered) << "tile 30's ACK lost: tile 9 resends its data to tile 30";
  o = damaged_then(30U, {event(EventId::kPacketResent, 30U, 4U, 1'005'000U, 0U),
                         event(EventId::kPacketResent, 1U, 30U, 1'006'000U, 1U)});
  EXPECT_FALSE(o.recovered) << "named source: its resend to another tile, or tile 1's own, is not this packet";
  o = damaged_then(30U, {event(EventId::kPacketResent, 30U, 1U, 1'002'000U, 0U)});
  EXPECT_TRUE(o.recovered);
  EXPECT_NEAR(o.recovered_s, 1.002, 1e-9);
}

// FDIR-JN-04: a damaged packet whose source the damage hid is credited only to a flip just before it.
// Flips at 3 s (seen by nobody) and 5 s (its packet dropped damaged at once): before, the first took
// the second's detection and the second went unseen; a late timeout resend is no detection either.
TEST(FdirJoin, ADamagedPacketOfHiddenSourceIsCreditedOnlyToAFlipJustBeforeIt) {
  using fdir::EventId;
  const std::array<bsp::FaultRecord, 2> faults{record(bsp::FaultKind::kPacketBitFlip, 1U, 3'002'000U),
                                               record(bsp::FaultKind::kPacketBitFlip, 18U, 5'002'000U)};
  const std::vector<fdir::Event> events{event(EventId::kPacketResent, 1U, 9U, 3'900'000U, 1U),
                                        event(EventId::kPacketDamaged, 19U, fdir::kUnknown, 5'002'000U)};
  const tools::FaultAccount a = tools::join_faults(faults, events, kHz);
  ASSERT_EQ(a.outcomes.size(), 2U);
  EXPECT_FALSE(a.outcomes[0].detected) << "nothing saw the first flip";
  EXPECT_TRUE(a.outcomes[1].detected);
  EXPECT_EQ(a.outcomes[1].detector, 19U);
  EXPECT_NEAR(a.outcomes[1].detected_s, 5.002, 1e-9);
}

}  // namespace
