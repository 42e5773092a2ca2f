/**
 * @file event_ids.hpp
 * @brief The flight event ids: one reviewable table of every detection, isolation and recovery step.
 *
 * Every event a flight layer writes (fdir/event_log.hpp) has an id from this
 * table. The table gives each id its severity and the fault-management steps
 * it stands for (an event can be a detection and a recovery at once, as a
 * packet corrected by its code). The host formats the text of each id and
 * joins the events to the injector's ground truth by the rule of docs/FDIR.md;
 * it never decides a step itself. Ids are grouped by layer: 0x01xx messaging,
 * 0x02xx network health, 0x03xx vision, 0x04xx health table and asserts, 0x05xx core
 * health (watchdogs, resets, spares), 0x06xx filter restarts, 0x07xx the filter's TMR, 0x08xx checked
 * computations (matrix products, correlation), 0x09xx supervisors, mission phases and power.
 */
#pragma once

#include <array>
#include <cstdint>

namespace fdir {

/** How bad (F Prime / cFS EVS style). */
enum class Severity : std::uint8_t { kInfo = 0, kWarningLo = 1, kWarningHi = 2, kFatal = 3 };

/** Fault-management steps an event stands for (bit set). */
enum Step : std::uint8_t {
  kStepNone = 0U,
  kStepDetect = 1U,   ///< a fault was noticed
  kStepIsolate = 2U,  ///< the faulty part was cut out (routes, work, role)
  kStepRecover = 4U,  ///< service is whole again (data corrected or resent, routes rebuilt)
};

enum class EventId : std::uint16_t {
  // ---- messaging (udn, through the endpoint's event sink)
  kPacketCorrected = 0x0101,   ///< subject: source tile, cause: channel, a: seq
  kPacketForwarded = 0x0102,   ///< misdelivered packet forwarded; subject: source tile, cause: destination index
  kPacketDamaged = 0x0103,     ///< beyond correction; subject: source tile (kUnknown if not identified), a: 1 if NACKed
  kPacketResent = 0x0104,      ///< go-back-N; subject: destination, cause: 0 NACK / 1 timeout, a: channel, b: seq
  kPacketGaveUp = 0x0105,      ///< given up; subject: destination, cause: delivery (0 unknown, 1 not delivered), a: channel, b: seq
  kRouteUnreachable = 0x0106,  ///< no route; subject: destination, cause: delivery (as packet_gave_up), a: channel, b: seq
  kForwardUnreachable = 0x0107,///< a forwarder had no route; subject: destination
  kNeighbourSuspect = 0x0108,  ///< the probe missed a neighbour N rounds; subject: neighbour
  kMapApplied = 0x0109,        ///< routes rebuilt from a fault map; subject: version, cause: tile it came from
  kMapPushed = 0x010A,         ///< a neighbour was behind: our map sent to it; subject: neighbour, a: version
  kTransitLost = 0x010B,       ///< a transit probe's target stopped answering; subject: target
  kTransitBack = 0x010C,       ///< a lost transit answers again; subject: target
  kPacketSettled = 0x010D,     ///< a give-up of unknown delivery settled by the receiver's record; subject: destination, cause: 2 delivered (its ACKs were lost) / 1 not delivered, a: channel, b: seq
  // ---- network health (fdir/net_health)
  kSuspectVote = 0x0201,       ///< subject: suspect tile, cause: reporter, a: distinct reporters so far
  kSwitchFailed = 0x0202,      ///< subject: tile, a: votes, b: map version
  kLinkFailed = 0x0203,        ///< subject: tile, cause: neighbour across the link, a: transits lost (0: its ends voted), b: map version
  kMapPublished = 0x0204,      ///< every live tile was sent the map; subject: version, a: tiles sent to
  kCoreSuspect = 0x0205,       ///< the probes see a silent core behind a switch that still routes; subject: tile, a: transits through it that answer
  kTransitFailed = 0x0206,     ///< every transit probe through a switch lost: declared failed; subject: tile, a: transits, b: map version
  kLinkOrSwitchFailed = 0x0207,///< the transits lost across a link are all that is heard through a spare's switch at its end: the link or that switch failed, which cannot be told apart from the health tile; the switch is taken out of the routes (that covers both); subject: the spare, cause: the link's other end, a: transits, b: map version
  // ---- vision (trn, through fdir/liveness)
  kWorkerSilent = 0x0301,      ///< subject: worker tile, a: frames missed in a row; its work goes to the others
  kWorkerBack = 0x0302,        ///< subject: worker tile; it answered again and gets work
  kFrameDone = 0x0303,         ///< a: frame, b: matches, cause: units lost
  kResultsSuspect = 0x0304,    ///< a worker's results fail the consistency check (result_trust.hpp); subject: tile, cause: 0 first time / 1 again after its reset (its replacement is asked), a: failed in the window, b: checked in it
  kResultsConsistent = 0x0305, ///< a suspect worker's results pass again; subject: tile, cause: 0 while suspect / 1 after its reset, a: clean rounds in a row
  kCoarseBandRedone = 0x0307,  ///< the coordinator computed a band of the coarse surface itself; subject: the tile it was dealt to, cause: why (1 not sent, 2 no answer in time, 3 the tile's checks failed or it could not compute it, 4 the copy differs from the tile's digest), a: the band's first row, b: frame
  kLandmarkProductRefused = 0x0308, ///< the ground's landmark table failed its checks: the coordinator selects the landmarks itself; cause: why (trn::tasks::ProductCheck: 1 too short, 2 header, 3 other settings, 4 other map, 5 records), a: the block's bytes
  kVisionSetUpFailed = 0x0306, ///< the vision coordinator could not start: no frame will be planned; subject: step (1 its lists, 2 map product, 3 DDR carves, 4 landmark selection, 5 relit coarse map), a: the step's status code
  // ---- health table, asserts
  kMonitorWarn = 0x0401,       ///< subject: monitor index, a: value, b: threshold
  kMonitorFatal = 0x0402,      ///< subject: monitor index, a: value, b: threshold; the action is taken
  kActionCapped = 0x0403,      ///< subject: monitor index, a: actions taken; no more (no reset loop)
  kAssertFailed = 0x0404,      ///< subject: assert id, cause: line; the tile asks for its recovery
  // ---- core health (fdir/tile_health)
  kTaskOverdue = 0x0501,       ///< a task missed its check-in; subject: task id, cause: tile, a: ticks late, b: budget; the watchdog is no longer kicked
  kWatchdogExpired = 0x0502,   ///< the supervisor took a tile's watchdog interrupt; subject: tile, a: expiries so far
  kTileReset = 0x0503,         ///< a silent tile was reset; subject: tile, cause: 0 by the supervisor, 1 by the supervisor's watcher, 2 by the supervisor for wrong results (a coordinator's report), a: resets of it, b: cap
  kTileRecovered = 0x0504,     ///< a reset tile booted its role again and reported; subject: tile, cause: boot cause, a: ticks since the reset
  kTileRebooted = 0x0505,      ///< a tile booted again without a command (crash); subject: tile, cause: boot cause
  kTileLost = 0x0506,          ///< a tile given up: subject: tile, cause: 0 never reported back after its reset (a: ticks waited), 1 its reset refused, the watcher's tile (the supervisor's reset refused), kLostSwitchFailed its switch failed (cut off)
  kRoleMoved = 0x0507,         ///< a retired tile's role goes to a spare; subject: role slot (or a worker's boot slot), cause: old tile, a: spare, b: directory version (0: a worker replaced for wrong results, not a directory role)
  kRoleRestored = 0x0508,      ///< the spare booted the role and reported; subject: role slot, cause: retired tile, a: spare, b: ticks since the move
  kNoSpare = 0x0509,           ///< a role could not move (no spare left, or it would not switch on); subject: slot, cause: old tile
  kSelfTestMismatch = 0x050A,  ///< a tile was outvoted by two others in a self-test; subject: tile, cause: round, a: disagreements in a row, b: to retire
  kSelfTestAgree = 0x050B,     ///< an outvoted tile agrees again; subject: tile, cause: round, a: disagreements before
  kSelfTestLate = 0x050C,      ///< a tile had not answered a self-test round at its wait (an answer before the next round still counts); subject: tile, cause: round, a: wait ticks
  kSupervisorSilent = 0x050D,  ///< the watcher missed the supervisor's heartbeat; subject: supervisor tile, cause: watcher, a: ticks since the last, b: resets so far
  kWatcherCutOff = 0x050E,     ///< the watcher hears none of its neighbours or transits: a missing heartbeat is its own silence, no reset; subject: supervisor tile, cause: watcher, a: ticks since the last heartbeat
  // ---- navigation filter restarts (trn/tasks/filter_task)
  kFilterResumed = 0x0601,     ///< the filter started from a DDR checkpoint; subject: checkpoint number, a: IMU samples to replay, b: last sample it holds
  kCheckpointBad = 0x0602,     ///< a checkpoint slot failed its checks and is not used; subject: slot, a: bad slots
  kImuGap = 0x0603,            ///< IMU samples neither received nor still recorded; subject: first missing, a: samples
  kCommandTaken = 0x0604,      ///< a telecommand reached the filter; subject: code, cause: its sequence number, a: job
  kFilterStateBad = 0x0605,    ///< the simplex filter's state after a job failed its plausibility check (trn/filter/state_check.hpp) and was not delivered; subject: job, cause: the check (1 not finite, 2 attitude norm, 3 speed, 4 range, 5 IMU bias, 6-9 position, velocity, attitude, bias step), a: value, b: limit (thousandths of the check's unit, the attitude norm's distance from 1 in millionths; saturated); kFilterResumed follows when it went back to a checkpoint
  kFilterSettingsBad = 0x0606, ///< the settings in RAM (configuration, camera, process noise) of the simplex filter or a TMR replica changed since they were built (their CRC-32C, after every job): the job's solution is not delivered and the settings are built again from the image; the filter goes back to its last checkpoint (kFilterResumed follows), a replica drops its state and waits for a seed (kTmrResynced follows); subject: job, cause: the parts changed (1 configuration, 2 camera, 4 process noise), a: 1 when rebuilt
  // ---- TMR of the filter (trn/tasks/filter_task, fdir/tmr)
  kTmrStarting = 0x0701,       ///< replicas seeded with the filter's state; subject: job, cause: epoch
  kTmrEstablished = 0x0702,    ///< three replicas agree with the filter: the voter delivers; subject: job, cause: epoch, a: jobs it took
  kTmrSimplex = 0x0703,        ///< one filter again; subject: job, cause: 0 command, 2 TMR not established in time, 3 the filter restarted (TMR starts again once it caught up)
  kTmrOutvoted = 0x0704,       ///< a replica's output was outvoted; subject: its tile, cause: job, a: replica, b: 1 different, 2 missing
  kTmrAgrees = 0x0705,         ///< an outvoted replica agrees again; subject: its tile, cause: job, a: replica, b: disagreements before
  kTmrExcluded = 0x0706,       ///< a replica no longer votes and must re-synchronise; subject: its tile, cause: job, a: replica, b: replicas left
  kTmrResynced = 0x0707,       ///< a replica seeded from the voted state votes again; subject: its tile, cause: job, a: replica, b: replicas voting
  kTmrNoMajority = 0x0708,     ///< no two replicas agree: nothing delivered; subject: job, cause: voting mask, a: different, b: missing | tile of replica i << 8 (i + 1)
  kTmrVoterResumed = 0x0709,   ///< a restarted voter goes on from its place in DDR; subject: job, cause: epoch, a: next job to deliver, b: records of the outage it writes
  // ---- checked matrix products (fdir/abft) and checked correlation (trn/vision/correlator, logged by the vision tile)
  kAbftCorrected = 0x0801,     ///< a product failed its checksums and passed when computed again; subject: site, cause: row << 16 | column of the element located (0xFFFF: not one; kAbftColNotChecked: rows only), a: bad rows << 16 | bad columns, b: recomputations
  kAbftFailed = 0x0802,        ///< a product still failed its checksums after every recomputation; same fields
  kCorrelationCorrected = 0x0803,  ///< a landmark's correlation failed a check and passed when computed again; subject: landmark, cause: the check that failed first (1 dot-product checksum, 2 surface digest, 3 peak score), a: frame, b: recomputations
  kCorrelationFailed = 0x0804,     ///< still failing after every recomputation: the match is rejected, nothing sent; same fields
  // ---- supervisors (fdir/supervisor), mission phases, power
  kSupPolicy = 0x0901,     ///< a node took a policy; subject: node, cause: constraint, a: level, b: from (node, kFromPhase, kFromGround)
  kSupApply = 0x0902,      ///< a node applies an alternative; subject: node, cause: constraint | reason << 8, a: alternative, b: level | child << 8 (an escalation's)
  kSupNotMet = 0x0903,     ///< the alternative in use does not meet its level (debounced); subject: node, cause: constraint, a: alternative, b: level
  kSupEscalated = 0x0904,  ///< every alternative failed: the parent is told; subject: node, cause: constraint, a: level, b: parent
  kSupMet = 0x0905,        ///< the level is met; subject: node, cause: constraint, a: alternative, b: level
  kPhaseBegin = 0x0906,    ///< the mission phase begins; subject: phase, a: reliability, b: power
  kTileParked = 0x0907,    ///< a tile not needed is switched off by the power policy; subject: tile, cause: node
  kTileWoken = 0x0908,     ///< a parked tile is switched on before it is needed; subject: tile, cause: node
  kSafeMode = 0x0909,      ///< the top node has no alternative left: safe mode reported to the vehicle; subject: constraint, a: level
};

/** Column field of an abft event whose product was checked on its rows only (no column checked). */
inline constexpr std::uint32_t kAbftColNotChecked = 0xFFFEU;

/**
 * What an event accuses: the class of fault it diagnoses. The join (host) credits a
 * detection only to an accusation of the fault's tile with a class the fault's kind
 * allows, counts one of the wrong tile or class as a wrong diagnosis and one no
 * injected fault explains as a false alarm (docs/FDIR.md, "The join").
 */
enum class Diagnosis : std::uint8_t {
  kNone = 0,     ///< not an accusation: an action, a recovery, a notice
  kSuspicion,    ///< one observer's suspicion, not a diagnosis: a probe missed, a vote cast, an answer late
  kCoreSilent,   ///< the core does not answer (hung, or crashed and not back yet), seen from outside
  kCoreCrashed,  ///< the tile booted again without a command (it says so itself)
  kWrongResult,  ///< the tile computed, stored or sent something wrong
  kMemoryUpset,  ///< data in RAM changed since it was written (its checksum)
  kSwitch,       ///< the tile's switch routes nothing
  kLink,         ///< the link between two tiles carries nothing
  kSwitchOrLink, ///< a link or the switch at one of its ends, not told apart
  kPacket,       ///< a packet damaged or lost on its way (about the data, no tile accused)
};

/** Which fields of an event name the tiles it accuses. */
enum class Accused : std::uint8_t {
  kNobody = 0,       ///< no tile: a packet, a DDR block, a product
  kSubject,          ///< the subject
  kCause,            ///< the cause
  kWriter,           ///< the tile that wrote it, about itself
  kSubjectAndCause,  ///< a link: both its ends
  kReplicas,         ///< tmr_no_majority: each replica its mask names as different (tiles in b)
};

struct EventInfo {
  EventId id;
  const char* name;
  Severity severity;
  std::uint8_t steps;  ///< Step bits
  Diagnosis diagnosis;  ///< what it accuses (fdir/accusation.hpp refines it by the event's fields)
  Accused accused;      ///< whom
};

/** The table: every id once. */
inline constexpr std::array<EventInfo, 74> kEventTable{{
    {EventId::kPacketCorrected, "packet_corrected", Severity::kWarningLo, kStepDetect | kStepRecover, Diagnosis::kPacket, Accused::kNobody},
    {EventId::kPacketForwarded, "packet_forwarded", Severity::kWarningLo, kStepDetect | kStepRecover, Diagnosis::kPacket, Accused::kNobody},
    {EventId::kPacketDamaged, "packet_damaged", Severity::kWarningHi, kStepDetect, Diagnosis::kPacket, Accused::kNobody},
    {EventId::kPacketResent, "packet_resent", Severity::kWarningLo, kStepRecover, Diagnosis::kPacket, Accused::kNobody},
    {EventId::kPacketGaveUp, "packet_gave_up", Severity::kWarningHi, kStepDetect, Diagnosis::kNone, Accused::kNobody},
    {EventId::kRouteUnreachable, "route_unreachable", Severity::kWarningHi, kStepDetect, Diagnosis::kNone, Accused::kNobody},
    {EventId::kForwardUnreachable, "forward_unreachable", Severity::kWarningHi, kStepDetect, Diagnosis::kNone, Accused::kNobody},
    {EventId::kNeighbourSuspect, "neighbour_suspect", Severity::kWarningHi, kStepDetect, Diagnosis::kSuspicion, Accused::kSubject},
    {EventId::kMapApplied, "map_applied", Severity::kInfo, kStepRecover, Diagnosis::kNone, Accused::kNobody},
    {EventId::kMapPushed, "map_pushed", Severity::kInfo, kStepNone, Diagnosis::kNone, Accused::kNobody},
    {EventId::kTransitLost, "transit_lost", Severity::kWarningLo, kStepNone, Diagnosis::kNone, Accused::kNobody},
    {EventId::kTransitBack, "transit_back", Severity::kInfo, kStepNone, Diagnosis::kNone, Accused::kNobody},
    {EventId::kPacketSettled, "packet_settled", Severity::kWarningLo, kStepDetect, Diagnosis::kNone, Accused::kNobody},
    {EventId::kSuspectVote, "suspect_vote", Severity::kWarningLo, kStepDetect, Diagnosis::kSuspicion, Accused::kSubject},
    {EventId::kSwitchFailed, "switch_failed", Severity::kWarningHi, kStepDetect | kStepIsolate, Diagnosis::kSwitch, Accused::kSubject},
    {EventId::kLinkFailed, "link_failed", Severity::kWarningHi, kStepDetect | kStepIsolate, Diagnosis::kLink, Accused::kSubjectAndCause},
    {EventId::kMapPublished, "map_published", Severity::kInfo, kStepRecover, Diagnosis::kNone, Accused::kNobody},
    {EventId::kCoreSuspect, "core_suspect", Severity::kWarningHi, kStepDetect, Diagnosis::kCoreSilent, Accused::kSubject},
    {EventId::kTransitFailed, "transit_failed", Severity::kWarningHi, kStepDetect | kStepIsolate, Diagnosis::kSwitch, Accused::kSubject},
    {EventId::kLinkOrSwitchFailed, "link_or_switch_failed", Severity::kWarningHi, kStepDetect | kStepIsolate, Diagnosis::kSwitchOrLink, Accused::kSubjectAndCause},
    {EventId::kWorkerSilent, "worker_silent", Severity::kWarningHi, kStepDetect | kStepIsolate, Diagnosis::kCoreSilent, Accused::kSubject},
    {EventId::kWorkerBack, "worker_back", Severity::kInfo, kStepRecover, Diagnosis::kNone, Accused::kNobody},
    {EventId::kFrameDone, "frame_done", Severity::kInfo, kStepNone, Diagnosis::kNone, Accused::kNobody},
    {EventId::kResultsSuspect, "results_suspect", Severity::kWarningHi, kStepDetect | kStepIsolate, Diagnosis::kWrongResult, Accused::kSubject},
    {EventId::kResultsConsistent, "results_consistent", Severity::kInfo, kStepRecover, Diagnosis::kNone, Accused::kNobody},
    {EventId::kVisionSetUpFailed, "vision_set_up_failed", Severity::kFatal, kStepDetect, Diagnosis::kNone, Accused::kNobody},
    {EventId::kCoarseBandRedone, "coarse_band_redone", Severity::kWarningLo, kStepDetect | kStepRecover, Diagnosis::kWrongResult, Accused::kSubject},
    {EventId::kLandmarkProductRefused, "landmark_product_refused", Severity::kWarningLo, kStepDetect | kStepRecover, Diagnosis::kNone, Accused::kNobody},
    {EventId::kMonitorWarn, "monitor_warn", Severity::kWarningLo, kStepDetect, Diagnosis::kNone, Accused::kNobody},
    {EventId::kMonitorFatal, "monitor_fatal", Severity::kWarningHi, kStepDetect | kStepIsolate, Diagnosis::kNone, Accused::kNobody},
    {EventId::kActionCapped, "action_capped", Severity::kFatal, kStepNone, Diagnosis::kNone, Accused::kNobody},
    {EventId::kAssertFailed, "assert_failed", Severity::kFatal, kStepDetect, Diagnosis::kWrongResult, Accused::kWriter},
    {EventId::kTaskOverdue, "task_overdue", Severity::kWarningHi, kStepDetect, Diagnosis::kCoreSilent, Accused::kCause},
    {EventId::kWatchdogExpired, "watchdog_expired", Severity::kWarningHi, kStepDetect, Diagnosis::kCoreSilent, Accused::kSubject},
    {EventId::kTileReset, "tile_reset", Severity::kWarningHi, kStepIsolate, Diagnosis::kNone, Accused::kNobody},
    {EventId::kTileRecovered, "tile_recovered", Severity::kInfo, kStepRecover, Diagnosis::kNone, Accused::kNobody},
    {EventId::kTileRebooted, "tile_rebooted", Severity::kWarningHi, kStepDetect | kStepRecover, Diagnosis::kCoreCrashed, Accused::kSubject},
    {EventId::kTileLost, "tile_lost", Severity::kFatal, kStepDetect, Diagnosis::kNone, Accused::kNobody},
    {EventId::kRoleMoved, "role_moved", Severity::kWarningHi, kStepIsolate, Diagnosis::kNone, Accused::kNobody},
    {EventId::kRoleRestored, "role_restored", Severity::kInfo, kStepRecover, Diagnosis::kNone, Accused::kNobody},
    {EventId::kNoSpare, "no_spare", Severity::kFatal, kStepNone, Diagnosis::kNone, Accused::kNobody},
    {EventId::kSelfTestMismatch, "self_test_mismatch", Severity::kWarningHi, kStepDetect, Diagnosis::kWrongResult, Accused::kSubject},
    {EventId::kSelfTestAgree, "self_test_agree", Severity::kInfo, kStepRecover, Diagnosis::kNone, Accused::kNobody},
    {EventId::kSelfTestLate, "self_test_late", Severity::kWarningLo, kStepNone, Diagnosis::kSuspicion, Accused::kSubject},
    {EventId::kSupervisorSilent, "supervisor_silent", Severity::kWarningHi, kStepDetect, Diagnosis::kCoreSilent, Accused::kSubject},
    {EventId::kWatcherCutOff, "watcher_cut_off", Severity::kWarningLo, kStepNone, Diagnosis::kNone, Accused::kNobody},
    {EventId::kFilterResumed, "filter_resumed", Severity::kInfo, kStepRecover, Diagnosis::kNone, Accused::kNobody},
    {EventId::kCheckpointBad, "checkpoint_bad", Severity::kWarningHi, kStepDetect, Diagnosis::kMemoryUpset, Accused::kNobody},
    {EventId::kImuGap, "imu_gap", Severity::kWarningHi, kStepDetect, Diagnosis::kNone, Accused::kNobody},
    {EventId::kCommandTaken, "command_taken", Severity::kInfo, kStepNone, Diagnosis::kNone, Accused::kNobody},
    {EventId::kFilterStateBad, "filter_state_bad", Severity::kWarningHi, kStepDetect | kStepIsolate, Diagnosis::kWrongResult, Accused::kWriter},
    {EventId::kFilterSettingsBad, "filter_settings_bad", Severity::kWarningHi, kStepDetect | kStepIsolate, Diagnosis::kMemoryUpset, Accused::kWriter},
    {EventId::kTmrStarting, "tmr_starting", Severity::kInfo, kStepNone, Diagnosis::kNone, Accused::kNobody},
    {EventId::kTmrEstablished, "tmr_established", Severity::kInfo, kStepNone, Diagnosis::kNone, Accused::kNobody},
    {EventId::kTmrSimplex, "tmr_simplex", Severity::kInfo, kStepNone, Diagnosis::kNone, Accused::kNobody},
    {EventId::kTmrOutvoted, "tmr_outvoted", Severity::kWarningHi, kStepDetect, Diagnosis::kWrongResult, Accused::kSubject},
    {EventId::kTmrAgrees, "tmr_agrees", Severity::kInfo, kStepRecover, Diagnosis::kNone, Accused::kNobody},
    {EventId::kTmrExcluded, "tmr_excluded", Severity::kWarningHi, kStepIsolate, Diagnosis::kNone, Accused::kNobody},
    {EventId::kTmrResynced, "tmr_resynced", Severity::kInfo, kStepRecover, Diagnosis::kNone, Accused::kNobody},
    {EventId::kTmrNoMajority, "tmr_no_majority", Severity::kFatal, kStepDetect, Diagnosis::kWrongResult, Accused::kReplicas},
    {EventId::kTmrVoterResumed, "tmr_voter_resumed", Severity::kInfo, kStepRecover, Diagnosis::kNone, Accused::kNobody},
    {EventId::kAbftCorrected, "abft_corrected", Severity::kWarningLo, kStepDetect | kStepRecover, Diagnosis::kWrongResult, Accused::kWriter},
    {EventId::kAbftFailed, "abft_failed", Severity::kWarningHi, kStepDetect, Diagnosis::kWrongResult, Accused::kWriter},
    {EventId::kCorrelationCorrected, "correlation_corrected", Severity::kWarningLo, kStepDetect | kStepRecover, Diagnosis::kWrongResult, Accused::kWriter},
    {EventId::kCorrelationFailed, "correlation_failed", Severity::kWarningHi, kStepDetect, Diagnosis::kWrongResult, Accused::kWriter},
    {EventId::kSupPolicy, "sup_policy", Severity::kInfo, kStepNone, Diagnosis::kNone, Accused::kNobody},
    {EventId::kSupApply, "sup_apply", Severity::kInfo, kStepNone, Diagnosis::kNone, Accused::kNobody},
    {EventId::kSupNotMet, "sup_not_met", Severity::kWarningHi, kStepDetect, Diagnosis::kNone, Accused::kNobody},
    {EventId::kSupEscalated, "sup_escalated", Severity::kWarningLo, kStepNone, Diagnosis::kNone, Accused::kNobody},
    {EventId::kSupMet, "sup_met", Severity::kInfo, kStepNone, Diagnosis::kNone, Accused::kNobody},
    {EventId::kPhaseBegin, "phase_begin", Severity::kInfo, kStepNone, Diagnosis::kNone, Accused::kNobody},
    {EventId::kTileParked, "tile_parked", Severity::kInfo, kStepNone, Diagnosis::kNone, Accused::kNobody},
    {EventId::kTileWoken, "tile_woken", Severity::kInfo, kStepNone, Diagnosis::kNone, Accused::kNobody},
    {EventId::kSafeMode, "safe_mode", Severity::kFatal, kStepNone, Diagnosis::kNone, Accused::kNobody},
}};

namespace detail {
constexpr bool ids_unique() noexcept {
  for (std::size_t i = 0; i < kEventTable.size(); ++i) {
    for (std::size_t j = i + 1U; j < kEventTable.size(); ++j) {
      if (kEventTable[i].id == kEventTable[j].id || static_cast<std::uint16_t>(kEventTable[i].id) == 0U) {
        return false;
      }
    }
  }
  return true;
}
}  // namespace detail
static_assert(detail::ids_unique(), "every event id once in the table");

/** The table row of @p id, or nullptr for an id not in the table. */
constexpr const EventInfo* event_info(EventId id) noexcept {
  for (const EventInfo& e : kEventTable) {
    if (e.id == id) {
      return &e;
    }
  }
  return nullptr;
}

/** Subject or cause that is not known (e.g. the source of a packet too damaged to read). */
inline constexpr std::uint32_t kUnknown = 0xFFFF'FFFFU;

}  // namespace fdir
