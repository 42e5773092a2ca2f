/**
 * @file events.hpp
 * @brief The application's flight events: declared here, in the layer that raises them.
 *
 * Each event is declared once, as fdir's are (fdir/event_ids.hpp, whose
 * EventInfo this table uses): its id, severity, fault-management steps, what
 * it accuses, what its fields hold and its text. The ids are ones fdir's table
 * leaves free (checked below); trn code writes them with trn::report, which
 * takes each one's severity and steps from here. The host reads both tables
 * (tools/common/accounting/event_text.hpp).
 */
#pragma once

#include "fdir/event_ids.hpp"
#include "fdir/event_log.hpp"

#include <array>
#include <cstdint>

namespace trn {

/** The application's event ids. */
namespace ev {
// ---- vision frames (trn/tasks/vision_coord)
inline constexpr fdir::EventId kFrameDone{0x0303};
inline constexpr fdir::EventId kVisionSetUpFailed{0x0306};
inline constexpr fdir::EventId kCoarseBandRedone{0x0307};
inline constexpr fdir::EventId kLandmarkProductRefused{0x0308};
inline constexpr fdir::EventId kCoordStateBad{0x0309};
inline constexpr fdir::EventId kResultSealBroken{0x030A};
/** result_seal_broken's cause: which result (a vision tile's, a part of the coordinator's batch, the filter's solution). */
inline constexpr std::uint32_t kSealVisionResult = 1U;
inline constexpr std::uint32_t kSealBatchPart = 2U;
inline constexpr std::uint32_t kSealSolution = 3U;
inline constexpr fdir::EventId kTileSettingsBad{0x030B};
/** tile_settings_bad's cause: whose settings (trn/tasks/settings_copy.hpp). */
inline constexpr std::uint32_t kSettingsOfCoordinator = 1U;
inline constexpr std::uint32_t kSettingsOfVisionTile = 2U;
inline constexpr std::uint32_t kSettingsOfVoter = 3U;  ///< the filter's voter: its TMR thresholds, against the image's
inline constexpr std::uint32_t kSettingsOfSupervisor = 4U;  ///< a supervisor's: phases, thresholds, its wiring
/** tile_settings_bad's a: when they were found changed. */
inline constexpr std::uint32_t kSettingsAtStart = 1U;  ///< as a frame (a unit) starts: it runs with the rebuilt ones
inline constexpr std::uint32_t kSettingsAtBatch = 2U;  ///< before the frame's batch leaves (a unit's result): dropped (the unit run again)
// ---- navigation filter restarts (trn/tasks/filter_task)
inline constexpr fdir::EventId kFilterResumed{0x0601};
inline constexpr fdir::EventId kCheckpointBad{0x0602};
inline constexpr fdir::EventId kImuGap{0x0603};
inline constexpr fdir::EventId kCommandTaken{0x0604};
inline constexpr fdir::EventId kFilterStateBad{0x0605};
inline constexpr fdir::EventId kFilterSettingsBad{0x0606};
inline constexpr fdir::EventId kFilterInnovationsBad{0x0607};
inline constexpr fdir::EventId kFilterStateChanged{0x0608};
// ---- TMR of the filter (trn/tasks/filter_task, its voter fdir/tmr)
inline constexpr fdir::EventId kTmrStarting{0x0701};
inline constexpr fdir::EventId kTmrEstablished{0x0702};
inline constexpr fdir::EventId kTmrSimplex{0x0703};
inline constexpr fdir::EventId kTmrOutvoted{0x0704};
inline constexpr fdir::EventId kTmrAgrees{0x0705};
inline constexpr fdir::EventId kTmrExcluded{0x0706};
inline constexpr fdir::EventId kTmrResynced{0x0707};
inline constexpr fdir::EventId kTmrNoMajority{0x0708};
inline constexpr fdir::EventId kTmrVoterResumed{0x0709};
inline constexpr fdir::EventId kTmrFallback{0x070A};
/** tmr_simplex's cause when the TMR lost its majority and the filter fell back (tmr_fallback). */
inline constexpr std::uint32_t kTmrSimplexNoMajority = 4U;
// ---- checked correlation (trn/vision/correlator, logged by the vision tile)
inline constexpr fdir::EventId kCorrelationCorrected{0x0803};
inline constexpr fdir::EventId kCorrelationFailed{0x0804};
// ---- the I/O role (trn/tasks/io)
inline constexpr fdir::EventId kIoDevicesTaken{0x0A01};
// ---- mission phases and safe mode (trn/tasks/supervisors)
inline constexpr fdir::EventId kPhaseBegin{0x0906};
inline constexpr fdir::EventId kSafeMode{0x0909};
}  // namespace ev

/** The table: every application id once. */
inline constexpr std::array<fdir::EventInfo, 30> kEventTable{{
    {ev::kFrameDone, "frame_done", fdir::Severity::kInfo, fdir::kStepNone, fdir::Diagnosis::kNone, fdir::Accused::kNobody,
     "- / units lost / frame / matches",
     "frame {a} done: {b} matches, {c} units lost"},
    {ev::kVisionSetUpFailed, "vision_set_up_failed", fdir::Severity::kFatal, fdir::kStepDetect, fdir::Diagnosis::kNone, fdir::Accused::kNobody,
     "step (1 its lists, 2 map product, 3 DDR carves, 4 landmark selection, 5 relit coarse map) / - / the "
     "step's status. The coordinator plans no frame; nothing restarts it (a task that returns is not "
     "watched, and the same set-up would fail again), so this says why vision is gone",
     "the vision coordinator could not start: {s|?|its tile lists|the map product|its DDR carves|the "
     "landmark selection|the relit coarse map|?} failed (status {a}); no frame will be planned"},
    {ev::kCoarseBandRedone, "coarse_band_redone", fdir::Severity::kWarningLo, fdir::kStepDetect | fdir::kStepRecover, fdir::Diagnosis::kWrongResult, fdir::Accused::kSubject,
     "the tile the band was dealt to / why: 1 not sent, 2 no answer in time, 3 the tile's checks failed "
     "(or it could not compute it), 4 the coordinator's copy differs from the band's digest / the band's "
     "first row / frame. The coordinator computed the band itself: the coarse surface is whole and checked",
     "coarse band from row {a} of frame {b} dealt to tile {s}: {c|?|it could not be sent|no answer in "
     "time|its checks failed|its copy differs from its digest|?}; computed by the coordinator"},
    {ev::kCoordStateBad, "coord_state_bad", fdir::Severity::kWarningHi, fdir::kStepDetect | fdir::kStepRecover, fdir::Diagnosis::kMemoryUpset, fdir::Accused::kWriter,
     "part (1 image-rate divisor, 2 band count, 3 a band's rows, 4 unit count, 5 match count, 6 tile list, 7 "
     "liveness, 8 result trust, 9 the frame's size, 10 a match, 11 the prior's solution, 12 the frame's deadline, 13 the time the set-up ended; "
     "trn::tasks::CoordPart) / "
     "the part's index / the value found: a count, index, divisor or value of the vision coordinator's state "
     "that no valid state holds (an upset of its RAM); that part reset, from the coordinator's configuration "
     "and its tile list in DDR where they hold it, else dropped (a frame, its bands, its matches)",
     "vision coordinator state upset: {s|?|image-rate divisor|band count|band rows|unit count|match count|tile "
     "list|liveness|result trust|frame size|match|prior's solution|frame deadline|set-up end|?} {c} held {a}: "
     "reset"},
    {ev::kResultSealBroken, "result_seal_broken", fdir::Severity::kWarningLo, fdir::kStepDetect | fdir::kStepRecover, fdir::Diagnosis::kWrongResult, fdir::Accused::kSubject,
     "the tile that computed it / what (1 a vision tile's result, checked by the coordinator; 2 a part of "
     "the coordinator's batch, checked by the filter; 3 the filter's solution, checked as it is delivered) "
     "/ frame (1, 2: as the words say) or job (3) / matches lost (1, 2). The words no longer match the seal "
     "(CRC-32C) their tile took as it computed them: a result and a part are dropped unused (a result's unit "
     "counts as answered), a solution is copied again from what the filter computed and delivered whole",
     "{c|?|a vision tile's result|a part of the coordinator's batch|the filter's solution|?} from tile {s}, "
     "{c|?|frame|frame|job|?} {a}, changed after it was computed (its seal is broken): {c|?|dropped, {b} matches lost|dropped, {b} "
     "matches lost|copied again from the computed solution|?}"},
    {ev::kTileSettingsBad, "tile_settings_bad", fdir::Severity::kWarningLo, fdir::kStepDetect | fdir::kStepRecover, fdir::Diagnosis::kMemoryUpset, fdir::Accused::kWriter,
     "frame (job: the voter; node: a supervisor) / whose (1 the vision coordinator's, 2 a vision tile's, 4 a "
     "supervisor's: against their CRC-32C; 3 the filter voter's TMR thresholds: against the image, each TMR "
     "job) / when (1 as the frame, unit, job or pass starts, 2 before its batch or result leaves) / matches "
     "dropped (coordinator, 2)",
     "the {c|?|vision coordinator's|vision tile's|filter voter's|{s@node}'s|?} settings in RAM changed, found "
     "{a|?|as {c|?|frame {s}|frame {s}|job {s}|a pass|?} starts|before frame {s}'s {c|?|batch|result|?} "
     "leaves|?}: built again from the image{a|?||, {c|?|the batch dropped ({b} matches)|the unit run again|?}|?}"},
    {ev::kLandmarkProductRefused, "landmark_product_refused", fdir::Severity::kWarningLo, fdir::kStepDetect | fdir::kStepRecover, fdir::Diagnosis::kNone, fdir::Accused::kNobody,
     "- / why (trn::tasks::ProductCheck): 1 the block is too short, 2 its header (magic, version, its "
     "CRC-32C), 3 selected with other settings than the coordinator's, 4 selected on a layer of another "
     "size or geometry, 5 its records (their CRC-32C, a count above the table, a dense set starting past "
     "them, a landmark outside the layer) / the block's bytes / -. The ground's landmark table was not "
     "taken: the coordinator selects the landmarks itself (~1.4 s, so the frame captured at 1 s is "
     "skipped)",
     "the ground's landmark table ({a} bytes) refused: {c|?|the block is too short|its header is wrong|it "
     "was selected with other settings|it was selected on another map|its records are wrong|?}; the "
     "coordinator selects the landmarks itself"},
    {ev::kFilterResumed, "filter_resumed", fdir::Severity::kInfo, fdir::kStepRecover, fdir::Diagnosis::kNone, fdir::Accused::kNobody,
     "checkpoint / - / samples to replay / last sample held",
     "filter resumed from checkpoint {s} (IMU sample {b}), {a} samples to replay from the I/O record"},
    {ev::kCheckpointBad, "checkpoint_bad", fdir::Severity::kWarningHi, fdir::kStepDetect, fdir::Diagnosis::kMemoryUpset, fdir::Accused::kNobody,
     "slot / - / bad slots",
     "filter checkpoint slot {s} failed its checks: not used ({a} bad)"},
    {ev::kImuGap, "imu_gap", fdir::Severity::kWarningHi, fdir::kStepDetect, fdir::Diagnosis::kNone, fdir::Accused::kNobody,
     "first missing sample / - / samples",
     "{a} IMU samples from sample {s} neither received nor recorded"},
    {ev::kCommandTaken, "command_taken", fdir::Severity::kInfo, fdir::kStepNone, fdir::Diagnosis::kNone, fdir::Accused::kNobody,
     "code / sequence number / job",
     "{c.top|telecommand {c} (code {s}) taken by the filter at job {a}|the filter supervisor's command "
     "{c.rest} (code {s}: {s|simplex|TMR|simplex}) taken by the filter at job {a}}"},
    {ev::kFilterStateBad, "filter_state_bad", fdir::Severity::kWarningHi, fdir::kStepDetect | fdir::kStepIsolate, fdir::Diagnosis::kWrongResult, fdir::Accused::kWriter,
     "job / check (1 not finite, 2 attitude norm, 3 speed, 4 range, 5 IMU bias, 6 position step, 7 "
     "velocity step, 8 attitude step, 9 bias step) / value / limit (thousandths of the check's unit; the "
     "attitude norm's distance from 1 in millionths)",
     "the filter's state after job {s} {c|fails its {c@state_check} check ({a@state_value}, limit "
     "{b@state_value})|is not finite|fails its {c@state_check} check ({a@state_value}, limit "
     "{b@state_value})}: not delivered"},
    {ev::kFilterSettingsBad, "filter_settings_bad", fdir::Severity::kWarningHi, fdir::kStepDetect | fdir::kStepIsolate, fdir::Diagnosis::kMemoryUpset, fdir::Accused::kWriter,
     "job / parts changed (1 configuration, 2 camera, 4 process noise) / 1 when built again / -",
     "the filter's settings in RAM ({c&configuration|camera|process noise}) changed by the end of job "
     "{s}: not delivered, {a|NOT built again|built again from the image}"},
    {ev::kFilterStateChanged, "filter_state_changed", fdir::Severity::kWarningHi, fdir::kStepDetect | fdir::kStepIsolate, fdir::Diagnosis::kMemoryUpset, fdir::Accused::kWriter,
     "job / - / - / -",
     "the filter's state in RAM changed between the end of job {s} and the start of the next (its CRC-32C): "
     "back to the last checkpoint"},
    {ev::kFilterInnovationsBad, "filter_innovations_bad", fdir::Severity::kWarningHi, fdir::kStepDetect | fdir::kStepRecover, fdir::Diagnosis::kWrongResult, fdir::Accused::kWriter,
     "job / why (1 too many rejected, 2 normalised innovations too large; 3, 4 the same in the window after "
     "the covariance was widened) / measurements in the window (low 16 bits), rejected (high 16 bits) / "
     "their mean clipped d2, thousandths (2 expected)",
     "the filter's matches disagree with its covariance in the window ending at job {s} ({c|?|too many "
     "rejected|innovations too large|too many rejected again|innovations too large again|?}: {a@rejected_of}, "
     "mean d2 {b@mpx}): {c|?|covariance widened|covariance widened|the tile asks to be restarted|the tile asks to be "
     "restarted|?}"},
    {ev::kTmrStarting, "tmr_starting", fdir::Severity::kInfo, fdir::kStepNone, fdir::Diagnosis::kNone, fdir::Accused::kNobody,
     "job / epoch",
     "filter to TMR: replicas seeded with the state after job {s} (epoch {c})"},
    {ev::kTmrEstablished, "tmr_established", fdir::Severity::kInfo, fdir::kStepNone, fdir::Diagnosis::kNone, fdir::Accused::kNobody,
     "job / epoch / jobs since the command",
     "TMR established at job {s}: three replicas agree with the filter ({a} jobs after the command); the "
     "voter delivers"},
    {ev::kTmrSimplex, "tmr_simplex", fdir::Severity::kInfo, fdir::kStepNone, fdir::Diagnosis::kNone, fdir::Accused::kNobody,
     "job / 0 command, 2 not established in time, 3 the filter restarted, 4 no majority (tmr_fallback)",
     "filter simplex again at job {s} ({c|command|TMR not established in time|TMR not established in "
     "time|the filter restarted: TMR again once it has caught up|no majority: one filter from the last "
     "voted checkpoint|TMR not established in time})"},
    {ev::kTmrOutvoted, "tmr_outvoted", fdir::Severity::kWarningHi, fdir::kStepDetect, fdir::Diagnosis::kWrongResult, fdir::Accused::kSubject,
     "replica's tile / job / replica / 1 different, 2 missing, 3 its solution fails the CRC taken where it was "
     "computed, 4 missing: it refused its own state and said so",
     "replica {a} on tile {s} outvoted at job {c} ({b|no output|different output or state|no output|its "
     "solution changed after it was computed: it fails its CRC|no output: it refused its own state|no output})"},
    {ev::kTmrAgrees, "tmr_agrees", fdir::Severity::kInfo, fdir::kStepRecover, fdir::Diagnosis::kNone, fdir::Accused::kNobody,
     "replica's tile / job / replica / disagreements before",
     "replica {a} on tile {s} agrees again at job {c}"},
    {ev::kTmrExcluded, "tmr_excluded", fdir::Severity::kWarningHi, fdir::kStepIsolate, fdir::Diagnosis::kNone, fdir::Accused::kNobody,
     "replica's tile / job / replica / replicas voting",
     "replica {a} on tile {s} excluded at job {c}: it re-synchronises ({b} voting)"},
    {ev::kTmrResynced, "tmr_resynced", fdir::Severity::kInfo, fdir::kStepRecover, fdir::Diagnosis::kNone, fdir::Accused::kNobody,
     "replica's tile / job / replica / replicas voting",
     "replica {a} on tile {s} seeded with the voted state, votes again from job {c} ({b} voting)"},
    {ev::kTmrNoMajority, "tmr_no_majority", fdir::Severity::kFatal, fdir::kStepDetect, fdir::Diagnosis::kWrongResult, fdir::Accused::kReplicas,
     "job / voting mask / different / missing | tile of replica i << 8 (i + 1)",
     "no majority at job {s} (different {a:x}, missing {b.b0:x}; replicas on tiles {b.b1}, {b.b2}, "
     "{b.b3}): nothing delivered"},
    {ev::kTmrVoterResumed, "tmr_voter_resumed", fdir::Severity::kInfo, fdir::kStepRecover, fdir::Diagnosis::kNone, fdir::Accused::kNobody,
     "job / epoch / next job delivered / records of the outage written",
     "the voter restarted at job {s} goes on voting (epoch {c}): delivers from job {a}; records of its "
     "outage written: {b}"},
    {ev::kTmrFallback, "tmr_fallback", fdir::Severity::kWarningHi, fdir::kStepRecover, fdir::Diagnosis::kNone, fdir::Accused::kNobody,
     "job / votes without a majority in a row / checkpoint / its job",
     "no majority in {c} votes in a row up to job {s}: the filter goes on alone from checkpoint {a} (its "
     "state after job {b}, which the vote agreed on)"},
    {ev::kCorrelationCorrected, "correlation_corrected", fdir::Severity::kWarningLo, fdir::kStepDetect | fdir::kStepRecover, fdir::Diagnosis::kWrongResult, fdir::Accused::kWriter,
     "landmark / check that failed first (1 dot-product checksum, 2 surface digest, 3 peak score) / frame "
     "/ recomputations",
     "{s@landmark} at frame {a}: correlation wrong ({c|a score around its peak different when computed "
     "again|its dot products off the integral image's checksum|its surface changed before the peak search "
     "ended|a score around its peak different when computed again}), right after {b} recomputation(s)"},
    {ev::kCorrelationFailed, "correlation_failed", fdir::Severity::kWarningHi, fdir::kStepDetect, fdir::Diagnosis::kWrongResult, fdir::Accused::kWriter,
     "landmark / check that failed first / frame / recomputations, as correlation_corrected; the match is rejected",
     "{s@landmark} at frame {a}: correlation wrong ({c|a score around its peak different when computed "
     "again|its dot products off the integral image's checksum|its surface changed before the peak search "
     "ended|a score around its peak different when computed again}), still wrong, not matched after {b} "
     "recomputation(s)"},
    {ev::kPhaseBegin, "phase_begin", fdir::Severity::kInfo, fdir::kStepNone, fdir::Diagnosis::kNone, fdir::Accused::kNobody,
     "phase / - / reliability / power",
     "mission phase {s} begins: reliability {a|normal|high|?}, power {b|full|save|?}"},
    {ev::kIoDevicesTaken, "io_devices_taken", fdir::Severity::kWarningLo, fdir::kStepRecover, fdir::Diagnosis::kNone, fdir::Accused::kNobody,
     "the tile that had them / IMU samples stranded / frames stranded / telecommands stranded: the I/O "
     "role, started on the cross-strap's other attachment, set the select to its tile; what waited in "
     "the FIFOs of the tile it left is lost",
     "the I/O role took the devices over from tile {s}: {c} IMU samples, {a} frames and {b} telecommands "
     "left there are lost"},
    {ev::kSafeMode, "safe_mode", fdir::Severity::kFatal, fdir::kStepNone, fdir::Diagnosis::kNone, fdir::Accused::kNobody,
     "constraint / - / level",
     "trn_supervisor cannot meet {s|reliability {a|normal|high|?}|power {a|full|save|?}|capacity {a|full "
     "rate|half rate|?}|?}: safe mode reported to the vehicle"},
}};

namespace detail {
constexpr bool app_ids_free() noexcept {
  for (std::size_t i = 0; i < kEventTable.size(); ++i) {
    if (fdir::event_info(kEventTable[i].id) != nullptr || static_cast<std::uint16_t>(kEventTable[i].id) == 0U) {
      return false;
    }
    for (std::size_t j = i + 1U; j < kEventTable.size(); ++j) {
      if (kEventTable[i].id == kEventTable[j].id) {
        return false;
      }
    }
  }
  return true;
}
}  // namespace detail
static_assert(detail::app_ids_free(), "every application id once, and none that fdir's table declares");

/** The table row of @p id, or nullptr for an id not in the application's table. */
constexpr const fdir::EventInfo* event_info(fdir::EventId id) noexcept {
  for (const fdir::EventInfo& e : kEventTable) {
    if (e.id == id) {
      return &e;
    }
  }
  return nullptr;
}

/**
 * Writes event @p id of the current tile: an application event with its row
 * here, any other with fdir's (fdir::report). [task|isr]
 */
inline void report(fdir::EventId id, std::uint32_t subject, std::uint32_t cause, std::uint32_t a = 0U,
                   std::uint32_t b = 0U) noexcept {
  const fdir::EventInfo* info = trn::event_info(id);
  if (info != nullptr) {
    fdir::report(*info, subject, cause, a, b);
  } else {
    fdir::report(id, subject, cause, a, b);
  }
}

}  // namespace trn
