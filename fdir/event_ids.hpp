/**
 * @file event_ids.hpp
 * @brief The flight event ids of the lower layers (udn, fdir): one reviewable table of their
 *        detection, isolation and recovery steps.
 *
 * Every event a flight layer writes (fdir/event_log.hpp) has an id declared
 * once, with its severity, the fault-management steps it stands for (an event
 * can be a detection and a recovery at once, as a packet corrected by its
 * code), what it accuses, what its four fields hold and its text. The events
 * these layers raise are declared here (kEventTable); the application declares
 * its own in its layer (trn/events.hpp: vision frames, the filter's restarts
 * and TMR, checked correlation, mission phases), with ids this table leaves
 * free, and writes them with trn::report. The host fills the text from the
 * fields and joins the events to the injector's ground truth by the rule of
 * docs/FDIR.md; it never decides a step itself. Ids are grouped: 0x01xx
 * messaging, 0x02xx network health, 0x03xx workers' liveness and results,
 * 0x04xx health table and asserts, 0x05xx core health (watchdogs, resets,
 * spares), 0x08xx checked matrix products, 0x09xx supervisors and power.
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
  kPacketCorrected = 0x0101,
  kPacketForwarded = 0x0102,
  kPacketDamaged = 0x0103,
  kPacketResent = 0x0104,
  kPacketGaveUp = 0x0105,
  kRouteUnreachable = 0x0106,
  kForwardUnreachable = 0x0107,
  kNeighbourSuspect = 0x0108,
  kMapApplied = 0x0109,
  kMapPushed = 0x010A,
  kTransitLost = 0x010B,
  kTransitBack = 0x010C,
  kPacketSettled = 0x010D,
  kEndpointStateBad = 0x010E,
  // ---- network health (fdir/net_health)
  kSuspectVote = 0x0201,
  kSwitchFailed = 0x0202,
  kLinkFailed = 0x0203,
  kMapPublished = 0x0204,
  kCoreSuspect = 0x0205,
  kTransitFailed = 0x0206,
  kLinkOrSwitchFailed = 0x0207,
  // ---- workers' liveness and results (fdir/liveness, fdir/result_trust)
  kWorkerSilent = 0x0301,
  kWorkerBack = 0x0302,
  kResultsSuspect = 0x0304,
  kResultsConsistent = 0x0305,
  // ---- health table, asserts
  kMonitorWarn = 0x0401,
  kMonitorFatal = 0x0402,
  kActionCapped = 0x0403,
  kAssertFailed = 0x0404,
  // ---- core health (fdir/tile_health)
  kTaskOverdue = 0x0501,
  kWatchdogExpired = 0x0502,
  kTileReset = 0x0503,
  kTileRecovered = 0x0504,
  kTileRebooted = 0x0505,
  kTileLost = 0x0506,
  kRoleMoved = 0x0507,
  kRoleRestored = 0x0508,
  kNoSpare = 0x0509,
  kSelfTestMismatch = 0x050A,
  kSelfTestAgree = 0x050B,
  kSelfTestLate = 0x050C,
  kSupervisorSilent = 0x050D,
  kWatcherCutOff = 0x050E,
  kSupervisorPathCut = 0x050F,
  kSupervisorMoved = 0x0510,
  kSupervisorTookOver = 0x0511,
  kSupervisorUnheard = 0x0512,
  // ---- checked matrix products (fdir/abft)
  kAbftCorrected = 0x0801,
  kAbftFailed = 0x0802,
  // ---- supervisors (fdir/supervisor), power
  kSupPolicy = 0x0901,
  kSupApply = 0x0902,
  kSupNotMet = 0x0903,
  kSupEscalated = 0x0904,
  kSupMet = 0x0905,
  kTileParked = 0x0907,
  kTileWoken = 0x0908,
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

/**
 * One event, declared once: the flight encoder (fdir::report) takes its severity and steps from
 * here, the host its text and the join its accusation; docs/FDIR.md's table is checked against it.
 */
struct EventInfo {
  EventId id;
  const char* name;
  Severity severity;
  std::uint8_t steps;  ///< Step bits
  Diagnosis diagnosis;  ///< what it accuses (the host's tools/common/accounting/accusation.hpp refines it by the event's fields)
  Accused accused;      ///< whom
  const char* args;     ///< what its fields hold: "subject / cause / a / b" (trailing ones it leaves 0 omitted)
  /**
   * Its text, a template the host fills from the fields (tools/common/accounting/event_text.hpp):
   * {s} {c} {a} {b} a field in decimal ("?" for kUnknown); after the letter, .hi .lo (16-bit halves),
   * .b0 to .b3 (bytes), .top (bit 31) or .rest (bits 0-30) select part of it; then :x prints it in
   * hex, @type names it by a host type (node, alternative, ...), |p0|p1|... takes phrase p<value>
   * (the last for any larger value; phrases may hold fields), &w0|w1|... lists the words of its set bits.
   */
  const char* text;
};

/** The table: every id once. */
inline constexpr std::array<EventInfo, 56> kEventTable{{
    {EventId::kPacketCorrected, "packet_corrected", Severity::kWarningLo, kStepDetect | kStepRecover, Diagnosis::kPacket, Accused::kNobody,
     "source tile / channel / seq",
     "packet from tile {s} corrected by its SECDED code (channel {c}, seq {a})"},
    {EventId::kPacketForwarded, "packet_forwarded", Severity::kWarningLo, kStepDetect | kStepRecover, Diagnosis::kPacket, Accused::kNobody,
     "source / destination (a flipped header brought it; a clean detour leg is not an event)",
     "packet from tile {s} misdelivered here, forwarded to tile {c}"},
    {EventId::kPacketDamaged, "packet_damaged", Severity::kWarningHi, kStepDetect, Diagnosis::kPacket, Accused::kNobody,
     "source or `?` / channel / 1 if NACKed",
     "packet from tile {s} damaged beyond correction{a|: left to the sender's timeout|: NACK sent}"},
    {EventId::kPacketResent, "packet_resent", Severity::kWarningLo, kStepRecover, Diagnosis::kPacket, Accused::kNobody,
     "destination / 0 NACK, 1 timeout / channel / seq (a resend after the receiver answered BUSY, its "
     "queue full, is flow control: counted in `FtStats::resent_busy`, not an event; docs/FT_MESSAGING.md)",
     "stream to tile {s} resent go-back-N after a {c|NACK|timeout} (channel {a}, from seq {b})"},
    {EventId::kPacketGaveUp, "packet_gave_up", Severity::kWarningHi, kStepDetect, Diagnosis::kNone, Accused::kNobody,
     "destination / 0 delivery unknown (it left, no ACK came back), 1 not delivered (it never left) / "
     "channel / seq",
     "packet to tile {s} given up (channel {a}, seq {b}): {c|delivery unknown (no ACK came back)|not "
     "delivered (it never left)|delivery unknown (no ACK came back)}"},
    {EventId::kRouteUnreachable, "route_unreachable", Severity::kWarningHi, kStepDetect, Diagnosis::kNone, Accused::kNobody,
     "destination / as packet_gave_up (a send refused: 1) / channel / seq",
     "no route to tile {s} (channel {a}, seq {b}): {c|given up, delivery unknown|not delivered|given up, "
     "delivery unknown}"},
    {EventId::kForwardUnreachable, "forward_unreachable", Severity::kWarningHi, kStepDetect, Diagnosis::kNone, Accused::kNobody,
     "destination",
     "no route to forward a packet to tile {s}"},
    {EventId::kNeighbourSuspect, "neighbour_suspect", Severity::kWarningHi, kStepDetect, Diagnosis::kSuspicion, Accused::kSubject,
     "silent neighbour",
     "neighbour tile {s} does not answer the probe: reported"},
    {EventId::kMapApplied, "map_applied", Severity::kInfo, kStepRecover, Diagnosis::kNone, Accused::kNobody,
     "version / tile it came from",
     "fault map version {s} applied (from tile {c}): routes rebuilt"},
    {EventId::kMapPushed, "map_pushed", Severity::kInfo, kStepNone, Diagnosis::kNone, Accused::kNobody,
     "neighbour / - / version",
     "neighbour tile {s} probes with an older map: sent version {a}"},
    {EventId::kTransitLost, "transit_lost", Severity::kWarningLo, kStepNone, Diagnosis::kNone, Accused::kNobody,
     "target (the prober is the tile)",
     "transit probe to tile {s} unanswered: reported"},
    {EventId::kTransitBack, "transit_back", Severity::kInfo, kStepNone, Diagnosis::kNone, Accused::kNobody,
     "target",
     "transit probe to tile {s} answers again: reported"},
    {EventId::kPacketSettled, "packet_settled", Severity::kWarningLo, kStepDetect, Diagnosis::kNone, Accused::kNobody,
     "destination / 2 delivered (only its ACKs were lost), 1 not delivered (skipped at the resync point) "
     "/ channel / seq: a `packet_gave_up` of unknown delivery, settled by the receiver's record",
     "packet to tile {s} given up (channel {a}, seq {b}) was {c|not delivered: the receiver skipped "
     "it|not delivered: the receiver skipped it|delivered: only its ACKs were lost|not delivered: the "
     "receiver skipped it}"},
    {EventId::kEndpointStateBad, "endpoint_state_bad", Severity::kWarningHi, kStepDetect | kStepRecover, Diagnosis::kMemoryUpset, Accused::kWriter,
     "part (1 route table, 2 the node's tile, 3 epoch, 4 send slot, 5 send window count, 6 receive queue, 7 "
     "queues-ready bits, 8 a queued message, 9 forward slot, 10 SYNC slot, 11 fault map, 12 reports to send, 13 "
     "transit probes, 14 neighbour probe; udn::FtRepair) / the part's index / the value found: an index, count or "
     "length of the tile's messaging endpoint that no valid state holds (an upset of its RAM); that part reset "
     "(docs/FT_MESSAGING.md)",
     "messaging endpoint state upset: {s|?|route table|node's tile|epoch|send slot|send window count|receive "
     "queue|queues-ready bits|queued message|forward slot|SYNC slot|fault map|reports to send|transit probes|neighbour "
     "probe|?} {c} held {a}: reset"},
    {EventId::kSuspectVote, "suspect_vote", Severity::kWarningLo, kStepDetect, Diagnosis::kSuspicion, Accused::kSubject,
     "suspect / reporter / votes / votes needed",
     "tile {c} reports tile {s} (vote {a} of {b})"},
    {EventId::kSwitchFailed, "switch_failed", Severity::kWarningHi, kStepDetect | kStepIsolate, Diagnosis::kSwitch, Accused::kSubject,
     "tile / deciding reporter / votes / map version",
     "switch of tile {s} declared failed ({a} neighbours agree): map version {b}"},
    {EventId::kLinkFailed, "link_failed", Severity::kWarningHi, kStepDetect | kStepIsolate, Diagnosis::kLink, Accused::kSubjectAndCause,
     "tile / neighbour / transits heard across it, all lost (0: its two ends voted it) / map version",
     "link between tiles {s} and {c} declared failed ({a|both ends report each other only|the {a} transit "
     "probes heard across it lost, and no other}): map version {b}"},
    {EventId::kMapPublished, "map_published", Severity::kInfo, kStepRecover, Diagnosis::kNone, Accused::kNobody,
     "version / - / tiles sent to / targets",
     "fault map version {s} sent to {a} of {b} live tiles: traffic routes around"},
    {EventId::kCoreSuspect, "core_suspect", Severity::kWarningHi, kStepDetect, Diagnosis::kCoreSilent, Accused::kSubject,
     "tile / - / transits through it that answer",
     "core of tile {s} silent behind a switch that routes ({a} transits through it answer)"},
    {EventId::kTransitFailed, "transit_failed", Severity::kWarningHi, kStepDetect | kStepIsolate, Diagnosis::kSwitch, Accused::kSubject,
     "tile / 0 the transits through it, 1 an end tile: the transits to or through it, lost longer than a "
     "hung core there stays silent, 2 the supervisor's tile its watcher moved the role from / those "
     "transits / map version",
     "switch of tile {s} declared failed ({c|all {a} transit probes through it lost|an end tile: all {a} "
     "transit probes to or through it lost longer than a hung core stays silent|the supervisor's tile its "
     "watcher moved the role from: silent after a reset|?}): map version {b}"},
    {EventId::kLinkOrSwitchFailed, "link_or_switch_failed", Severity::kWarningHi, kStepDetect | kStepIsolate, Diagnosis::kSwitchOrLink, Accused::kSubjectAndCause,
     "spare / the link's other end / transits heard across the link / map version: the lost transits are "
     "all the health tile hears through the spare's switch, so the link or that switch failed (they look "
     "the same from there); the switch is taken out of the routes, which covers both",
     "link between tiles {c} and {s} or the switch of spare {s} failed (the {a} transit probes heard "
     "across the link lost, none heard through the switch but over it: they look the same from here): the "
     "switch taken out, map version {b}"},
    {EventId::kWorkerSilent, "worker_silent", Severity::kWarningHi, kStepDetect | kStepIsolate, Diagnosis::kCoreSilent, Accused::kSubject,
     "worker / - / misses",
     "worker tile {s} silent for {a} frames: isolated, its work goes to the others"},
    {EventId::kWorkerBack, "worker_back", Severity::kInfo, kStepRecover, Diagnosis::kNone, Accused::kNobody,
     "worker",
     "worker tile {s} answers again: back in the frame"},
    {EventId::kResultsSuspect, "results_suspect", Severity::kWarningHi, kStepDetect | kStepIsolate, Diagnosis::kWrongResult, Accused::kSubject,
     "worker / 0 first, 1 again after its reset (replacement asked); 2, 3 the same by the bias test / failed "
     "in the window, or (2, 3) its mean residual on the worse axis in thousandths of a pixel / checked in it, "
     "or (2, 3) fitted in it",
     "worker tile {s}: {c|{a} of its {b} results in the window off the frame's fit: suspect, its results not "
     "used|{a} of its {b} results in the window off the frame's fit: wrong again after its reset, "
     "replacement asked|its {b} results in the window off the frame's fit by {a@mpx} px on average: suspect, "
     "its results not used|its {b} results in the window off the frame's fit by {a@mpx} px on average: "
     "wrong again after its reset, replacement asked|?}"},
    {EventId::kResultsConsistent, "results_consistent", Severity::kInfo, kStepRecover, Diagnosis::kNone, Accused::kNobody,
     "worker / 0 while suspect, 1 after its reset / clean frames in a row",
     "worker tile {s}: results consistent again for {a} frames{c|| after its reset|}: used again"},
    {EventId::kMonitorWarn, "monitor_warn", Severity::kWarningLo, kStepDetect, Diagnosis::kNone, Accused::kNobody,
     "monitor / - / value / threshold",
     "monitor {s} warning: value {a} against {b}"},
    {EventId::kMonitorFatal, "monitor_fatal", Severity::kWarningHi, kStepDetect | kStepIsolate, Diagnosis::kNone, Accused::kNobody,
     "monitor / action / value / threshold",
     "monitor {s} fatal: value {a} against {b}"},
    {EventId::kActionCapped, "action_capped", Severity::kFatal, kStepNone, Diagnosis::kNone, Accused::kNobody,
     "monitor / action / actions / cap",
     "monitor {s}: {a} actions taken, no more (cap)"},
    {EventId::kAssertFailed, "assert_failed", Severity::kFatal, kStepDetect, Diagnosis::kWrongResult, Accused::kWriter,
     "check id / line",
     "assertion {s} failed (line {c}): recovery requested"},
    {EventId::kTaskOverdue, "task_overdue", Severity::kWarningHi, kStepDetect, Diagnosis::kCoreSilent, Accused::kCause,
     "task id / tile / ticks late / budget",
     "task {s} of tile {c} missed its check-in by {a} ticks (budget {b}): the watchdog is no longer kicked"},
    {EventId::kWatchdogExpired, "watchdog_expired", Severity::kWarningHi, kStepDetect, Diagnosis::kCoreSilent, Accused::kSubject,
     "tile / - / expiries so far",
     "watchdog of tile {s} expired ({a} expiries so far)"},
    {EventId::kTileReset, "tile_reset", Severity::kWarningHi, kStepIsolate, Diagnosis::kNone, Accused::kNobody,
     "tile / 0 by the supervisor, 1 by its watcher, 2 by the supervisor for wrong results / resets of it "
     "/ cap",
     "tile {s} reset by {c|the supervisor (reset {a} of at most {b})|its watcher (reset {a} of at most "
     "{b})|the supervisor: its results stayed wrong|the supervisor (reset {a} of at most {b})}"},
    {EventId::kTileRecovered, "tile_recovered", Severity::kInfo, kStepRecover, Diagnosis::kNone, Accused::kNobody,
     "tile / boot cause / ticks since the reset",
     "tile {s} booted its role again and reported, {a} ticks (ms) after its reset"},
    {EventId::kTileRebooted, "tile_rebooted", Severity::kWarningHi, kStepDetect | kStepRecover, Diagnosis::kCoreCrashed, Accused::kSubject,
     "tile / boot cause (3: crash or external)",
     "tile {s} booted again {c|without a command (cause power-on)|after a reset command|without a command "
     "(cause own watchdog)|without a command (cause crash or external reset)}: its role restarts"},
    {EventId::kTileLost, "tile_lost", Severity::kFatal, kStepDetect, Diagnosis::kNone, Accused::kNobody,
     "tile / 0 no boot report after its reset, 1 reset refused, the watcher (supervisor not reset), 0x100 "
     "its switch declared failed: retired, roles to spares / ticks waited",
     "tile {s} {c.b1|did not report back {a} ticks (ms) after its reset|cut off: its switch is declared "
     "failed; retired, its roles go to spares|did not report back {a} ticks (ms) after its reset}"},
    {EventId::kRoleMoved, "role_moved", Severity::kWarningHi, kStepIsolate, Diagnosis::kNone, Accused::kNobody,
     "role slot (9: a vision tile replaced for wrong results) / retired tile / spare / directory version "
     "(0 for a replaced vision tile)",
     "{b|worker slot {s}: tile {c} switched off for wrong results, spare {a} takes its place|role slot "
     "{s} moves from retired tile {c} to spare {a} (directory version {b})}"},
    {EventId::kRoleRestored, "role_restored", Severity::kInfo, kStepRecover, Diagnosis::kNone, Accused::kNobody,
     "role slot / retired tile / spare / ticks since the move",
     "role slot {s} runs again on tile {a} (was tile {c}), {b} ticks (ms) after the move"},
    {EventId::kNoSpare, "no_spare", Severity::kFatal, kStepNone, Diagnosis::kNone, Accused::kNobody,
     "role slot / tile",
     "role slot {s} of tile {c} cannot move: no spare"},
    {EventId::kSelfTestMismatch, "self_test_mismatch", Severity::kWarningHi, kStepDetect, Diagnosis::kWrongResult, Accused::kSubject,
     "tile / round / disagreements in a row / to retire",
     "tile {s} outvoted by two others in self-test round {c} ({a} in a row, retired at {b})"},
    {EventId::kSelfTestAgree, "self_test_agree", Severity::kInfo, kStepRecover, Diagnosis::kNone, Accused::kNobody,
     "tile / round / disagreements before",
     "tile {s} agrees again in self-test round {c}"},
    {EventId::kSelfTestLate, "self_test_late", Severity::kWarningLo, kStepNone, Diagnosis::kSuspicion, Accused::kSubject,
     "tile / round / wait ticks",
     "tile {s} had not answered self-test round {c} after {a} ticks (voted if it answers before the next "
     "round)"},
    {EventId::kSupervisorSilent, "supervisor_silent", Severity::kWarningHi, kStepDetect, Diagnosis::kCoreSilent, Accused::kSubject,
     "supervisor's tile / watcher / ticks from its last heartbeat before the reset to its first after / "
     "resets so far (written when the watcher's reset brought it back: it was hung)",
     "the supervisor's tile {s} was silent {a} ticks (ms) to its watcher (tile {c}) and the tiles beside it, "
     "and its reset brought it back: it was hung ({b} resets so far)"},
    {EventId::kSupervisorUnheard, "supervisor_unheard", Severity::kWarningHi, kStepDetect, Diagnosis::kSuspicion, Accused::kSubject,
     "supervisor's tile / watcher / ticks since its last heartbeat / resets so far (the tiles beside it miss "
     "it too: hung with its own watchdog failed, or its switch; the watcher resets it to tell them apart)",
     "no heartbeat from the supervisor's tile {s} for {a} ticks (ms), and the tiles beside it miss it too: "
     "hung or cut off; its watcher (tile {c}) resets it to tell ({b} resets so far)"},
    {EventId::kWatcherCutOff, "watcher_cut_off", Severity::kWarningLo, kStepNone, Diagnosis::kNone, Accused::kNobody,
     "supervisor's tile / watcher / ticks since its last heartbeat (the watcher hears none of its "
     "neighbours or transits: no reset)",
     "no heartbeat from the supervisor's tile {s} for {a} ticks (ms), but its watcher (tile {c}) hears "
     "none of its neighbours or transits: its own silence, no reset"},
    {EventId::kSupervisorPathCut, "supervisor_path_cut", Severity::kWarningLo, kStepNone, Diagnosis::kNone, Accused::kNobody,
     "supervisor's tile / watcher / ticks since its last heartbeat / tiles beside it that hear it (their "
     "neighbour probes answered, none silent: its core runs and its switch routes, the way to the "
     "watcher is cut; no reset)",
     "no heartbeat from the supervisor's tile {s} for {a} ticks (ms), but {b} tile(s) beside it hear it: "
     "the way to its watcher (tile {c}) is cut, no reset"},
    {EventId::kSupervisorMoved, "supervisor_moved", Severity::kFatal, kStepDetect | kStepIsolate, Diagnosis::kSwitch, Accused::kSubject,
     "supervisor's tile / watcher / standby / ticks since the watcher's reset (still silent to the watcher "
     "and to the tiles beside it: no hang, its switch; switched off, the standby switched on to run its role)",
     "the supervisor's tile {s} stayed silent {b} ticks (ms) after its reset, to its watcher (tile {c}) and "
     "the tiles beside it: its switch is taken as failed; switched off, standby {a} takes the supervisor's role"},
    {EventId::kSupervisorTookOver, "supervisor_took_over", Severity::kWarningHi, kStepRecover, Diagnosis::kNone, Accused::kNobody,
     "new supervisor's tile / the tile it replaces / 1 state from the ledger, 0 from the boot configuration "
     "/ directory version of its move",
     "tile {s} runs the supervisor's role in place of tile {c}, its state {a|from the boot configuration|from "
     "the supervisor's ledger} (directory version {b})"},
    {EventId::kAbftCorrected, "abft_corrected", Severity::kWarningLo, kStepDetect | kStepRecover, Diagnosis::kWrongResult, Accused::kWriter,
     "product site (1 F P, 2 (F P) F^T, 3 P H^T, 4 the gain, 5 K (P H^T)^T's upper triangle) / row << 16 "
     "| column located (0xFFFF: not one; 0xFFFE: rows only checked) / bad rows << 16 | bad columns / "
     "recomputations",
     "product {s}: {c@abft_where}, right after {b} recomputation(s)"},
    {EventId::kAbftFailed, "abft_failed", Severity::kWarningHi, kStepDetect, Diagnosis::kWrongResult, Accused::kWriter,
     "product site / row << 16 | column located / bad rows << 16 | bad columns / recomputations, as abft_corrected",
     "product {s}: {c@abft_where}, still wrong after {b} recomputation(s)"},
    {EventId::kSupPolicy, "sup_policy", Severity::kInfo, kStepNone, Diagnosis::kNone, Accused::kNobody,
     "node (0 TRN, 1 vision, 2 filter) / constraint (0 reliability, 1 power, 2 capacity) / level / from "
     "(a node, 256 the phase, 257 a telecommand, 258 its default)",
     "{s@node} takes {c.b0@constraint} {a@level} from {b@from}"},
    {EventId::kSupApply, "sup_apply", Severity::kInfo, kStepNone, Diagnosis::kNone, Accused::kNobody,
     "node / constraint | reason << 8 (0 policy, 1 the one before not met, 2 an escalation) / alternative "
     "(1 hand down, 2 simplex, 3 TMR, 4 TMR from a fresh seed, 5 full rate, 6 half rate, 7 accept "
     "simplex, 8 replicas powered, 9 replicas off) / level | child << 8",
     "{s@node}: {a@alternative} for {c.b0@constraint} {b.b0@level} ({c.b1|the policy|the one before did "
     "not meet it|escalation from {b.b1@node}|})"},
    {EventId::kSupNotMet, "sup_not_met", Severity::kWarningHi, kStepDetect, Diagnosis::kNone, Accused::kNobody,
     "node / constraint / alternative / level",
     "{s@node}: {a@alternative} does not meet {c.b0@constraint} {b@level}"},
    {EventId::kSupEscalated, "sup_escalated", Severity::kWarningLo, kStepNone, Diagnosis::kNone, Accused::kNobody,
     "node / constraint / level / parent (255: the vehicle)",
     "{s@node} has no way left to meet {c.b0@constraint} {a@level}: escalated to {b@node}"},
    {EventId::kSupMet, "sup_met", Severity::kInfo, kStepNone, Diagnosis::kNone, Accused::kNobody,
     "node / constraint / alternative / level",
     "{s@node} meets {c.b0@constraint} {b@level} ({a@alternative})"},
    {EventId::kTileParked, "tile_parked", Severity::kInfo, kStepNone, Diagnosis::kNone, Accused::kNobody,
     "tile / the tile that asked",
     "tile {s} switched off by the power policy (asked by tile {c})"},
    {EventId::kTileWoken, "tile_woken", Severity::kInfo, kStepNone, Diagnosis::kNone, Accused::kNobody,
     "tile / the tile that asked",
     "tile {s} switched on by the power policy (asked by tile {c})"},
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
