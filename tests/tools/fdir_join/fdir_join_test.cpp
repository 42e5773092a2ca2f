/**
 * @file fdir_join_test.cpp
 * @brief The host's join of flight events to the injector's ground truth (docs/FDIR.md, "The join"):
 *        each injection is credited only to an event that accuses its tile of what it did, within its
 *        kind's bound; recovery is its role's output stream back; every other accusation is a wrong
 *        diagnosis or a false alarm, and every action on a healthy tile is counted.
 */
#include "tools/common/accounting/fault_account.hpp"
#include "trn/events.hpp"
#include "tools/common/accounting/fdir_join.hpp"

#include "trn/filter/filter_core.hpp"
#include "trn/vision/correlator.hpp"

#include <gtest/gtest.h>

#include <algorithm>
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
                  std::uint32_t cause = 0U, std::uint32_t a = 0U, std::uint32_t b = 0U) {
  fdir::Event e{};
  e.id = id;
  e.tile = writer;
  e.subject = subject;
  e.cause = cause;
  e.a = a;
  e.b = b;
  e.cycle = at;
  const fdir::EventInfo* info = tools::event_info(id);
  e.steps = info != nullptr ? info->steps : 0U;
  return e;
}

/** Output times every @p step_s from @p from_s to @p to_s (inclusive), as a role's stream. */
std::vector<double> stream(double from_s, double to_s, double step_s = 0.010) {
  std::vector<double> v;
  for (double t = from_s; t <= to_s + 1e-9; t += step_s) {
    v.push_back(t);
  }
  return v;
}

/** The filter's stream with a hole from @p stop_s to @p back_s (outputs every 10 ms otherwise, 0-10 s). */
std::vector<double> filter_stream_with_hole(double stop_s, double back_s) {
  std::vector<double> v = stream(0.010, stop_s);
  const std::vector<double> rest = stream(back_s, 10.0);
  v.insert(v.end(), rest.begin(), rest.end());
  return v;
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
  const std::vector<fdir::Event> events{event(trn::ev::kCorrelationCorrected, 24U, 12U, 4'006'000U, 1U),
                                        event(trn::ev::kCorrelationCorrected, 25U, 7U, 4'006'000U, 1U)};
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

  // Neither detects it; the link accusation names its tile with the wrong class, the self-test the
  // wrong tile within its bound: both are charged to it as wrong diagnoses (the suspicion is none).
  EXPECT_EQ(none.misdiagnosed, 1U);
  EXPECT_EQ(none.outcomes[0].wrong_accusations, 2U);
  EXPECT_EQ(none.outcomes[0].diagnosis, tools::DiagnosisVerdict::kWrong);
  EXPECT_TRUE(none.false_alarms.empty());

  std::vector<fdir::Event> named = unrelated;
  named.push_back(event(fdir::EventId::kSelfTestMismatch, 0U, 35U, 1'400'000U));
  named.push_back(event(fdir::EventId::kSelfTestAgree, 0U, 35U, 1'450'000U));
  const tools::FaultAccount cleared = tools::join_faults(faults, named, kHz);
  ASSERT_EQ(cleared.detected, 1U);
  EXPECT_EQ(cleared.outcomes[0].detected_by, fdir::EventId::kSelfTestMismatch);
  EXPECT_NEAR(cleared.outcomes[0].detected_s - cleared.outcomes[0].injected_s, 0.4, 1e-9);
  EXPECT_EQ(cleared.outcomes[0].diagnosis, tools::DiagnosisVerdict::kRightAndWrong);
  EXPECT_EQ(cleared.recovered, 0U) << "cleared, but no frame of the vision service whole after it";
  // A vision tile's service: a frame with no unit lost after the tile was cleared.
  named.push_back(event(trn::ev::kFrameDone, 1U, 0U, 1'300'000U, 0U));  // before it was cleared
  named.push_back(event(trn::ev::kFrameDone, 1U, 0U, 1'900'000U, 2U));  // units lost
  named.push_back(event(trn::ev::kFrameDone, 1U, 0U, 2'100'000U, 0U));
  const tools::FaultAccount hit = tools::join_faults(faults, named, kHz);
  ASSERT_EQ(hit.recovered, 1U);
  EXPECT_NEAR(hit.outcomes[0].recovered_s, 2.1, 1e-9);
  EXPECT_EQ(hit.outcomes[0].role, trn::tasks::Role::kVision);
}

// FDIR-FS-06: a settings check is credited to an upset of its tile (never to an sdc); the filter's
// recovery is its output stream flowing again steadily after the refusal (half a second with no gap
// over 100 ms), whatever the flight says of its resume.
TEST(FdirJoin, TheFilterIsRecoveredWhenItsOutputsFlowAgainSteadily) {
  using fdir::EventId;
  const std::array<bsp::FaultRecord, 1> one{settings_upset(18U, 3'000'000U, 71U)};
  const std::vector<fdir::Event> refused{event(trn::ev::kFilterSettingsBad, 18U, 300U, 3'002'000U, 1U),
                                         event(trn::ev::kFilterResumed, 18U, 30U, 3'002'100U)};
  // One job skipped (3.00 -> 3.02): back at 3.02 with a 20 ms gap.
  std::vector<double> skipped = filter_stream_with_hole(3.0, 3.02);
  tools::ServiceStreams streams;
  streams.filter_outputs_s = skipped;
  const tools::FaultAccount a = tools::join_faults(one, refused, kHz, streams);
  ASSERT_EQ(a.detected, 1U);
  ASSERT_EQ(a.recovered, 1U);
  EXPECT_EQ(a.outcomes[0].role, trn::tasks::Role::kFilter);
  EXPECT_NEAR(a.outcomes[0].recovered_s, 3.02, 1e-9);
  EXPECT_NEAR(a.outcomes[0].service_gap_s, 0.02, 1e-9);
  EXPECT_STREQ(a.outcomes[0].recovered_by, "filter_outputs");

  // Refused again and restarted: outputs at 3.02 and 3.03, then nothing until 3.5. The first outputs
  // are not steady: the recovery is at 3.5, the gap 470 ms.
  std::vector<double> restarted = stream(0.010, 3.0);
  restarted.push_back(3.02);
  restarted.push_back(3.03);
  const std::vector<double> rest = stream(3.5, 10.0);
  restarted.insert(restarted.end(), rest.begin(), rest.end());
  streams.filter_outputs_s = restarted;
  const tools::FaultAccount b = tools::join_faults(one, refused, kHz, streams);
  ASSERT_EQ(b.recovered, 1U);
  EXPECT_NEAR(b.outcomes[0].recovered_s, 3.5, 1e-9);
  EXPECT_NEAR(b.outcomes[0].service_gap_s, 0.47, 1e-9);

  // No outputs after the refusal: not recovered, whatever the resume says.
  std::vector<double> stopped = stream(0.010, 3.0);
  streams.filter_outputs_s = stopped;
  EXPECT_EQ(tools::join_faults(one, refused, kHz, streams).recovered, 0U);

  // An sdc is never credited to the settings check.
  const std::array<bsp::FaultRecord, 1> sdc{record(bsp::FaultKind::kSdc, 18U, 3'000'000U)};
  EXPECT_EQ(tools::join_faults(sdc, refused, kHz, streams).detected, 0U);
}

// FDIR-FS-07: only an upset in the settings' bytes takes the settings check. An upset deep in the
// EKF two seconds before one in its camera took that one's detection, and the camera's went unseen.
TEST(FdirJoin, TheSettingsCheckIsCreditedOnlyToAnUpsetInTheSettings) {
  using fdir::EventId;
  const std::array<bsp::FaultRecord, 3> faults{settings_upset(18U, 20'000'000U, 0x5000U),  // the EKF's history
                                               record(bsp::FaultKind::kSeu, 18U, 21'000'000U),  // uncarved RAM
                                               settings_upset(18U, 22'000'000U, 200U)};
  const std::vector<fdir::Event> events{event(trn::ev::kFilterSettingsBad, 18U, 2200U, 22'001'500U, 2U),
                                        event(trn::ev::kFilterResumed, 18U, 220U, 22'001'600U)};
  const std::vector<double> outputs = stream(0.010, 30.0);
  tools::ServiceStreams streams;
  streams.filter_outputs_s = outputs;
  const tools::FaultAccount a = tools::join_faults(faults, events, kHz, streams);
  ASSERT_EQ(a.detected, 1U);
  EXPECT_FALSE(a.outcomes[0].detected) << "outside the settings";
  EXPECT_FALSE(a.outcomes[1].detected) << "in no carve";
  ASSERT_TRUE(a.outcomes[2].detected);
  EXPECT_NEAR(a.outcomes[2].detected_s - a.outcomes[2].injected_s, 0.0015, 1e-9);
  EXPECT_TRUE(a.outcomes[2].recovered);
}

// A hang is credited to its watchdog and recovered when the filter's outputs flow again.
TEST(FdirJoin, AHangIsCreditedToItsWatchdogAndRecoveredByTheOutputs) {
  const std::array<bsp::FaultRecord, 1> faults{record(bsp::FaultKind::kCoreHang, 18U, 2'000'000U)};
  const std::vector<fdir::Event> events{
      event(fdir::EventId::kWatchdogExpired, 0U, 19U, 2'010'000U),  // another tile: not this one
      event(fdir::EventId::kWatchdogExpired, 0U, 18U, 2'016'000U),
      event(fdir::EventId::kTileReset, 0U, 18U, 2'016'000U),
      event(fdir::EventId::kTileRecovered, 0U, 18U, 2'030'000U),
  };
  const std::vector<double> outputs = filter_stream_with_hole(2.0, 2.04);
  tools::ServiceStreams streams;
  streams.filter_outputs_s = outputs;
  const tools::FaultAccount a = tools::join_faults(faults, events, kHz, streams);
  ASSERT_EQ(a.detected, 1U);
  EXPECT_EQ(a.recovered, 1U);
  EXPECT_NEAR(a.outcomes[0].detected_s - a.outcomes[0].injected_s, 0.016, 1e-9);
  EXPECT_NEAR(a.outcomes[0].recovered_s, 2.04, 1e-9) << "the outputs, not tile_recovered";
  EXPECT_NEAR(a.outcomes[0].service_gap_s, 0.04, 1e-9);
  // The watchdog of tile 19 names a tile no fault hit, within the hang's bound: a wrong diagnosis of
  // the hang, not a false alarm; the reset acts on the hung tile: no healthy tile disturbed.
  EXPECT_EQ(a.outcomes[0].wrong_accusations, 1U);
  EXPECT_EQ(a.outcomes[0].first_wrong_tile, 19U);
  EXPECT_TRUE(a.false_alarms.empty());
  EXPECT_TRUE(a.healthy_disturbed.empty());
}

// A hang's bound is 3 s: a watchdog before the fault, or 3.5 s after it, is not its detection.
TEST(FdirJoin, ADetectionOutsideTheKindsBoundIsNotTheFaults) {
  const std::array<bsp::FaultRecord, 1> faults{record(bsp::FaultKind::kCoreHang, 18U, 2'000'000U)};
  const std::vector<fdir::Event> events{
      event(fdir::EventId::kWatchdogExpired, 0U, 18U, 1'900'000U),
      event(fdir::EventId::kWatchdogExpired, 0U, 18U, 5'500'000U),
  };
  const tools::FaultAccount a = tools::join_faults(faults, events, kHz);
  EXPECT_EQ(a.detected, 0U);
  ASSERT_EQ(a.false_alarms.size(), 1U) << "the one before the fault";
  EXPECT_EQ(a.false_alarms[0].event, 0U);
  EXPECT_EQ(a.outcomes[0].diagnosis, tools::DiagnosisVerdict::kNone) << "the late one: the hung tile, still hung";
  EXPECT_DOUBLE_EQ(tools::detect_bound_s(bsp::FaultKind::kCoreHang), 3.0);
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

namespace {

using fdir::EventId;

// A reboot alone recovers nothing: a crash of a spare is detected by its reboot (a crash) and stays
// not recovered until the flight says the tile runs its role again; a crash of the filter's tile is
// recovered only by the filter's outputs.
TEST(FdirJoinStrict, ARebootAloneRecoversNothing) {
  const std::array<bsp::FaultRecord, 1> spare{record(bsp::FaultKind::kCoreReset, 12U, 2'000'000U)};
  std::vector<fdir::Event> events{event(EventId::kTileRebooted, 0U, 12U, 2'050'000U, 3U)};
  tools::FaultAccount a = tools::join_faults(spare, events, kHz);
  ASSERT_EQ(a.detected, 1U);
  EXPECT_EQ(a.outcomes[0].role, trn::tasks::Role::kSpare);
  EXPECT_EQ(a.recovered, 0U);
  events.push_back(event(EventId::kTileRecovered, 0U, 12U, 2'060'000U));
  a = tools::join_faults(spare, events, kHz);
  EXPECT_EQ(a.recovered, 1U);
  EXPECT_STREQ(a.outcomes[0].recovered_by, "tile_recovered");

  const std::array<bsp::FaultRecord, 1> filter{record(bsp::FaultKind::kCoreReset, 18U, 2'000'000U)};
  const std::vector<fdir::Event> rebooted{event(EventId::kTileRebooted, 0U, 18U, 2'050'000U, 3U)};
  const std::vector<double> stopped = stream(0.010, 2.0);
  tools::ServiceStreams streams;
  streams.filter_outputs_s = stopped;
  EXPECT_EQ(tools::join_faults(filter, rebooted, kHz, streams).recovered, 0U);
  const std::vector<double> back = filter_stream_with_hole(2.0, 2.2);
  streams.filter_outputs_s = back;
  EXPECT_EQ(tools::join_faults(filter, rebooted, kHz, streams).recovered, 1U);
  // A commanded reboot accuses nobody: it is no detection of a crash.
  const std::vector<fdir::Event> commanded{event(EventId::kTileRebooted, 0U, 18U, 2'050'000U, 1U)};
  EXPECT_EQ(tools::join_faults(filter, commanded, kHz, streams).detected, 0U);
}

// The filter and vision supervisors have no output stream the host measures: a reboot alone recovers
// nothing; their node's own word that it runs again (a policy taken, written by its tile) does, and
// another tile's does not.
TEST(FdirJoinStrict, ASupervisorNodeRecoversWhenItTakesItsPolicyAgain) {
  const std::array<bsp::FaultRecord, 1> vision_sup{record(bsp::FaultKind::kCoreReset, 7U, 2'000'000U)};
  std::vector<fdir::Event> events{event(EventId::kTileRebooted, 0U, 7U, 2'050'000U, 3U)};
  tools::FaultAccount a = tools::join_faults(vision_sup, events, kHz);
  ASSERT_EQ(a.detected, 1U);
  EXPECT_EQ(a.outcomes[0].role, trn::tasks::Role::kVisionSupervisor);
  EXPECT_EQ(a.recovered, 0U);
  events.push_back(event(EventId::kSupPolicy, 6U, 1U, 2'100'000U));
  EXPECT_EQ(tools::join_faults(vision_sup, events, kHz).recovered, 0U) << "the filter supervisor's policy";
  events.push_back(event(EventId::kSupPolicy, 7U, 2U, 2'400'000U));
  a = tools::join_faults(vision_sup, events, kHz);
  EXPECT_EQ(a.recovered, 1U);
  EXPECT_STREQ(a.outcomes[0].recovered_by, "sup_policy");
}

// A hung core accused of a failed switch is misdiagnosed, not detected; a neighbour's suspicion is
// neither a detection nor a wrong diagnosis.
TEST(FdirJoinStrict, AHangAccusedOfAFailedSwitchIsMisdiagnosed) {
  const std::array<bsp::FaultRecord, 1> faults{record(bsp::FaultKind::kCoreHang, 30U, 2'000'000U)};
  const std::vector<fdir::Event> events{event(EventId::kNeighbourSuspect, 31U, 30U, 2'020'000U),
                                        event(EventId::kSwitchFailed, 0U, 30U, 2'040'000U, 0U, 2U, 1U)};
  const tools::FaultAccount a = tools::join_faults(faults, events, kHz);
  EXPECT_EQ(a.detected, 0U);
  EXPECT_EQ(a.misdiagnosed, 1U);
  EXPECT_EQ(a.outcomes[0].diagnosis, tools::DiagnosisVerdict::kWrong);
  EXPECT_EQ(a.outcomes[0].first_wrong, EventId::kSwitchFailed);
  EXPECT_EQ(a.outcomes[0].wrong_accusations, 1U) << "the suspicion is not counted";
  EXPECT_TRUE(a.false_alarms.empty());
  EXPECT_TRUE(a.healthy_disturbed.empty()) << "the switch taken out is the hung tile's";
}

// An accusation no fault explains is a false alarm, and the action it leads to on a healthy tile is
// counted; the same accusation within the bound of a fault on another tile is that fault's wrong
// diagnosis instead.
TEST(FdirJoinStrict, AnUnexplainedAccusationIsAFalseAlarm) {
  const std::vector<fdir::Event> events{event(EventId::kWatchdogExpired, 0U, 30U, 8'000'000U),
                                        event(EventId::kTileReset, 0U, 30U, 8'000'000U)};
  const std::array<bsp::FaultRecord, 1> far{record(bsp::FaultKind::kCoreHang, 40U, 2'000'000U)};
  const tools::FaultAccount a = tools::join_faults(far, events, kHz);
  ASSERT_EQ(a.false_alarms.size(), 1U);
  EXPECT_EQ(a.false_alarms[0].tile, 30U);
  ASSERT_EQ(a.healthy_disturbed.size(), 1U);
  EXPECT_EQ(a.healthy_disturbed[0].tile, 30U);
  EXPECT_EQ(a.misdiagnosed, 0U);

  const std::array<bsp::FaultRecord, 1> near{record(bsp::FaultKind::kCoreHang, 40U, 7'000'000U)};
  const tools::FaultAccount b = tools::join_faults(near, events, kHz);
  EXPECT_TRUE(b.false_alarms.empty());
  EXPECT_EQ(b.misdiagnosed, 1U);
  EXPECT_EQ(b.outcomes[0].first_wrong_tile, 30U);
  EXPECT_EQ(b.healthy_disturbed.size(), 1U) << "the reset of tile 30 is still a healthy tile disturbed";

  // No fault at all: the same two events.
  const tools::FaultAccount c = tools::join_faults({}, events, kHz);
  EXPECT_EQ(c.false_alarms.size(), 1U);
  EXPECT_EQ(c.healthy_disturbed.size(), 1U);
}

// Two replicas corrupted alike outvote the healthy third: the corruption is not detected, the
// outvote of the healthy replica is a wrong diagnosis and a healthy tile disturbed, and so is its
// exclusion.
TEST(FdirJoinStrict, AHealthyReplicaOutvotedByTwoAlikeIsCountedNotCredited) {
  std::array<bsp::FaultRecord, 2> faults{record(bsp::FaultKind::kSdc, 19U, 9'001'518U),
                                         record(bsp::FaultKind::kSdc, 21U, 9'001'518U)};
  faults[0].spec.channel = 1U;
  faults[1].spec.channel = 1U;
  const std::vector<fdir::Event> events{event(trn::ev::kTmrOutvoted, 18U, 20U, 9'021'000U, 900U, 1U, 1U),
                                        event(trn::ev::kTmrExcluded, 18U, 20U, 9'041'000U, 902U, 1U, 2U)};
  const tools::FaultAccount a = tools::join_faults(faults, events, kHz);
  EXPECT_EQ(a.detected, 0U);
  EXPECT_EQ(a.misdiagnosed, 1U);
  EXPECT_EQ(a.outcomes[1].first_wrong_tile, 20U);
  EXPECT_EQ(a.healthy_disturbed.size(), 2U);
  EXPECT_TRUE(a.false_alarms.empty());
}

// A vote without a majority credits each corrupted replica it names and charges the healthy one it
// names with them as a wrong diagnosis; a replica's service is back when it votes again, and TMR
// given up for simplex is a degraded recovery, accepted.
TEST(FdirJoinStrict, NoMajorityCreditsTheCorruptedAndChargesTheHealthy) {
  std::array<bsp::FaultRecord, 2> faults{record(bsp::FaultKind::kSdc, 19U, 7'001'500U),
                                         record(bsp::FaultKind::kSdc, 20U, 7'001'500U)};
  faults[0].spec.channel = 1U;
  faults[1].spec.channel = 1U;
  // Mask 0b111: all three different; tiles 19, 20, 21 in b's bytes 1-3.
  const std::uint32_t tiles = (19U << 8U) | (20U << 16U) | (21U << 24U);
  std::vector<fdir::Event> events{event(trn::ev::kTmrEstablished, 18U, 500U, 5'000'000U, 1U, 3U),
                                  event(trn::ev::kTmrNoMajority, 18U, 700U, 7'020'000U, 0U, 7U, tiles)};
  events.push_back(event(trn::ev::kTmrAgrees, 18U, 19U, 7'030'000U, 701U, 0U, 1U));
  events.push_back(event(trn::ev::kTmrSimplex, 18U, 705U, 7'070'000U, 2U));
  const tools::FaultAccount a = tools::join_faults(faults, events, kHz);
  EXPECT_EQ(a.detected, 2U);
  EXPECT_EQ(a.misdiagnosed, 1U);
  EXPECT_EQ(a.outcomes[0].recovery, tools::Recovery::kRecovered) << "replica 19 agrees again";
  EXPECT_EQ(a.outcomes[1].recovery, tools::Recovery::kDegradedAccepted) << "replica 20 never votes again: simplex";
  EXPECT_EQ(a.recovered, 1U);
  EXPECT_EQ(a.degraded_accepted, 1U);
}

// A replica's service is voting: while the filter is simplex it stands by, and the map that routes
// around its failed link is its recovery; in TMR, its role moved to a spare is back when the spare
// is seeded with three voting (the spare's outvotes before it was seeded are counted, not hidden).
TEST(FdirJoinStrict, AReplicaStandsByInSimplexAndVotesAgainInTmr) {
  std::array<bsp::FaultRecord, 1> link{record(bsp::FaultKind::kLinkFail, 21U, 19'510'000U)};
  link[0].spec.param = 3U;  // south: tile 29
  const std::vector<fdir::Event> standby{event(EventId::kLinkFailed, 0U, 21U, 19'545'000U, 29U, 0U, 1U),
                                         event(EventId::kMapPublished, 0U, 1U, 19'555'000U, 0U, 48U)};
  tools::FaultAccount a = tools::join_faults(link, standby, kHz);
  ASSERT_EQ(a.detected, 1U);
  EXPECT_EQ(a.recovered, 1U) << "standing by: the map is the service";
  EXPECT_STREQ(a.outcomes[0].recovered_by, "map_published");

  // A standby replica that crashed is back when the filter next goes TMR with three voting, however
  // late; its reboot alone is nothing.
  const std::array<bsp::FaultRecord, 1> crash{record(bsp::FaultKind::kCoreReset, 20U, 7'939'000U)};
  std::vector<fdir::Event> rebooted{event(EventId::kTileRebooted, 0U, 20U, 7'947'000U, 3U)};
  EXPECT_EQ(tools::join_faults(crash, rebooted, kHz).recovered, 0U);
  rebooted.push_back(event(trn::ev::kTmrStarting, 18U, 3003U, 30'031'000U, 1U));
  rebooted.push_back(event(trn::ev::kTmrEstablished, 18U, 3004U, 30'061'000U, 1U, 3U));
  a = tools::join_faults(crash, rebooted, kHz);
  EXPECT_EQ(a.recovered, 1U);
  EXPECT_NEAR(a.outcomes[0].recovered_s, 30.061, 1e-9);

  // In TMR, a replica whose self-test pattern was upset is cleared by its next self-test; no vote
  // missed or outvoted it, so it kept voting: recovered when cleared.
  const std::array<bsp::FaultRecord, 1> pattern{record(bsp::FaultKind::kSeu, 21U, 38'796'000U)};
  std::vector<fdir::Event> selftest{event(trn::ev::kTmrEstablished, 18U, 3004U, 30'061'000U, 1U, 3U),
                                    event(EventId::kSelfTestMismatch, 0U, 21U, 39'357'000U, 787U, 1U, 2U),
                                    event(EventId::kSelfTestAgree, 0U, 21U, 39'607'000U, 792U, 1U)};
  a = tools::join_faults(pattern, selftest, kHz);
  EXPECT_EQ(a.recovered, 1U);
  EXPECT_NEAR(a.outcomes[0].recovered_s, 39.607, 1e-9);
  // Outvoted meanwhile: it must vote again first.
  selftest.push_back(event(trn::ev::kTmrOutvoted, 18U, 21U, 39'000'000U, 3900U, 2U, 1U));
  EXPECT_EQ(tools::join_faults(pattern, selftest, kHz).recovered, 0U);

  const std::array<bsp::FaultRecord, 1> sw{record(bsp::FaultKind::kSwitchFail, 19U, 41'728'000U)};
  std::vector<fdir::Event> tmr{event(trn::ev::kTmrEstablished, 18U, 3004U, 30'061'000U, 1U, 3U),
                               event(EventId::kSwitchFailed, 0U, 19U, 41'765'000U, 0U, 2U, 1U),
                               event(EventId::kRoleMoved, 0U, 3U, 41'767'000U, 19U, 11U, 1U),
                               event(EventId::kRoleRestored, 0U, 3U, 41'775'000U, 19U, 11U, 8U),
                               event(EventId::kMapPublished, 0U, 1U, 41'776'000U, 0U, 47U),
                               event(trn::ev::kTmrOutvoted, 18U, 11U, 41'791'000U, 4177U, 0U, 2U),
                               event(trn::ev::kTmrExcluded, 18U, 11U, 41'811'000U, 4179U, 0U, 2U)};
  a = tools::join_faults(sw, tmr, kHz);
  EXPECT_EQ(a.recovered, 0U) << "the role restored on the spare votes nothing yet";
  EXPECT_EQ(a.misdiagnosed, 1U) << "the spare, outvoted for no output";
  EXPECT_EQ(a.healthy_disturbed.size(), 2U);
  tmr.push_back(event(trn::ev::kTmrResynced, 18U, 11U, 41'841'000U, 4182U, 0U, 3U));
  a = tools::join_faults(sw, tmr, kHz);
  EXPECT_EQ(a.recovered, 1U);
  EXPECT_STREQ(a.outcomes[0].recovered_by, "tmr_resynced");
}

// Corrected correlations are credited and recovered in place; a coarse band found wrong by the
// coordinator too. A switch is recovered once the map is out and the role's service flows.
TEST(FdirJoinStrict, InPlaceCorrectionsAndMapsRecover) {
  std::array<bsp::FaultRecord, 2> faults{record(bsp::FaultKind::kSdc, 27U, 12'037'000U),
                                         record(bsp::FaultKind::kSwitchFail, 9U, 20'000'000U)};
  faults[0].spec.channel = trn::vision::kCorrelationDotChannel;
  const std::vector<fdir::Event> events{
      event(trn::ev::kCorrelationCorrected, 27U, 12U, 12'042'000U, 1U, 12U, 1U),
      event(EventId::kTransitFailed, 0U, 9U, 20'098'000U, 0U, 7U, 1U),
      event(EventId::kMapPublished, 0U, 1U, 20'110'000U, 0U, 42U),
  };
  std::vector<double> io = stream(0.010, 20.0);
  tools::ServiceStreams streams;
  streams.io_samples_s = io;
  tools::FaultAccount a = tools::join_faults(faults, events, kHz, streams);
  EXPECT_EQ(a.detected, 2U);
  EXPECT_TRUE(a.outcomes[0].recovered);
  EXPECT_DOUBLE_EQ(a.outcomes[0].service_gap_s, 0.0);
  EXPECT_EQ(a.outcomes[1].role, trn::tasks::Role::kIo);
  EXPECT_FALSE(a.outcomes[1].recovered) << "the map is out, but no IMU sample flows from the I/O role";
  const std::vector<double> later = stream(20.2, 22.0);
  io.insert(io.end(), later.begin(), later.end());
  streams.io_samples_s = io;
  a = tools::join_faults(faults, events, kHz, streams);
  EXPECT_TRUE(a.outcomes[1].recovered);
  EXPECT_NEAR(a.outcomes[1].recovered_s, 20.2, 1e-9);
  EXPECT_STREQ(a.outcomes[1].recovered_by, "io_samples");
}

// The role of a tile is the one it held when the fault took effect: a spare that took the filter's
// role is the filter.
TEST(FdirJoinStrict, TheRoleFollowsTheDirectory) {
  const std::array<bsp::FaultRecord, 2> faults{record(bsp::FaultKind::kCoreHang, 10U, 3'000'000U),
                                               record(bsp::FaultKind::kCoreHang, 10U, 1'000'000U)};
  const std::vector<fdir::Event> events{event(EventId::kRoleMoved, 0U, 2U, 2'000'000U, 18U, 10U, 1U)};
  const tools::FaultAccount a = tools::join_faults(faults, events, kHz);
  EXPECT_EQ(a.outcomes[0].role, trn::tasks::Role::kFilter);
  EXPECT_EQ(a.outcomes[1].role, trn::tasks::Role::kSpare);
  ASSERT_EQ(a.healthy_disturbed.size(), 1U) << "the role moved from tile 18, which no fault hit";
  EXPECT_EQ(a.healthy_disturbed[0].tile, 18U);
}

// Faults not delivered are counted apart; without effect only when the stream matched the golden
// run's (mark_no_effect); faults.csv has one row per record.
TEST(FdirJoinStrict, NoEffectAndTheCsv) {
  std::array<bsp::FaultRecord, 3> faults{record(bsp::FaultKind::kSeu, 30U, 1'000'000U),
                                         record(bsp::FaultKind::kSdc, 31U, 2'000'000U),
                                         record(bsp::FaultKind::kCoreHang, 32U, 3'000'000U)};
  faults[1].status = bsp::FaultStatus::kArmed;
  const std::vector<fdir::Event> events{event(EventId::kWatchdogExpired, 0U, 32U, 3'016'000U)};
  tools::FaultAccount a = tools::join_faults(faults, events, kHz);
  EXPECT_EQ(a.injected, 2U);
  EXPECT_EQ(a.not_delivered, 1U);
  EXPECT_EQ(a.outcomes[0].effect, tools::Effect::kNotDetected);
  EXPECT_EQ(a.outcomes[1].effect, tools::Effect::kNotDelivered);
  tools::mark_no_effect(a);
  EXPECT_EQ(a.outcomes[0].effect, tools::Effect::kNoEffect);
  EXPECT_EQ(a.outcomes[2].effect, tools::Effect::kDetected);
  const std::string csv = tools::faults_csv(faults, a);
  EXPECT_EQ(std::count(csv.begin(), csv.end(), '\n'), 4);
  EXPECT_NE(csv.find("1.000000,seu,30,vision,1,,0,no_effect,"), std::string::npos) << csv;
  EXPECT_NE(csv.find(",sdc,31,,0,,0,not_delivered,"), std::string::npos) << csv;
  EXPECT_NE(csv.find("3.000000,core_hang,32,vision,1,,0,detected,watchdog_expired,0,16.000,right,0,,,none,,,"),
            std::string::npos)
      << csv;
}

}  // namespace
