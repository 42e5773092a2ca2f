/**
 * @file fdir_join.cpp
 * @brief Flight events collected into the run log; detections and recoveries joined to the ground truth.
 */
#include "tools/common/fdir_join.hpp"

#include "bsp_tile64/profile.hpp"
#include "tools/common/fault_plan.hpp"
#include "fdir/supervisor.hpp"
#include "fdir/tile_health.hpp"
#include "trn/filter/state_check.hpp"
#include "trn/match.hpp"
#include "trn/tasks/filter_core.hpp"
#include "trn/tasks/messages.hpp"
#include "trn/tasks/sdc_points.hpp"
#include "trn/tasks/supervisors.hpp"
#include "trn/vision/correlator.hpp"

#include <algorithm>
#include <array>
#include <cstdio>
#include <cstring>

namespace tools {
namespace {

using fdir::EventId;

double seconds(bsp::Cycles c, double clock_hz) { return static_cast<double>(c) / clock_hz; }

/** Replica @p i's tile named in a tmr_no_majority event (b: missing | tile of replica i << 8 (i + 1)). */
std::uint32_t no_majority_tile(const fdir::Event& e, std::uint32_t i) { return (e.b >> (8U * (i + 1U))) & 0xFFU; }

EventCategory category_of(const fdir::Event& e) {
  if ((e.steps & fdir::kStepDetect) != 0U) {
    return EventCategory::kDetect;
  }
  if ((e.steps & fdir::kStepIsolate) != 0U) {
    return EventCategory::kIsolate;
  }
  if ((e.steps & fdir::kStepRecover) != 0U) {
    return EventCategory::kRecover;
  }
  return EventCategory::kInfo;
}

const char* boot_cause_name(std::uint32_t cause) noexcept {
  switch (cause) {
    case static_cast<std::uint32_t>(bsp::BootCause::kPowerOn): return "power-on";
    case static_cast<std::uint32_t>(bsp::BootCause::kCommand): return "command";
    case static_cast<std::uint32_t>(bsp::BootCause::kWatchdog): return "own watchdog";
    default: return "crash or external reset";
  }
}

}  // namespace

const char* tile_health_name(TileHealth h) noexcept {
  switch (h) {
    case TileHealth::kSuspect: return "suspect";
    case TileHealth::kRecovered: return "recovered";
    case TileHealth::kFailed: return "failed";
    case TileHealth::kOk: break;
  }
  return "ok";
}

namespace {

/** A refused filter state: which check, what it measured against its limit (fields in thousandths). */
void describe_filter_state_bad(const fdir::Event& e, const char* s, std::span<char> b) noexcept {
  static constexpr std::array<const char*, 10> kUnit{"", "", "", "m/s", "m", "", "m", "m/s", "rad", ""};
  const auto check = static_cast<trn::filter::StateCheck>(e.cause);
  const char* unit = e.cause < kUnit.size() ? kUnit[e.cause] : "";
  if (check == trn::filter::StateCheck::kNotFinite) {
    (void)std::snprintf(b.data(), b.size(), "the filter's state after job %s is not finite: not delivered", s);
    return;
  }
  const double per = check == trn::filter::StateCheck::kAttitudeNorm ? 1e6 : 1e3;
  const char* sep = unit[0] != '\0' ? " " : "";
  (void)std::snprintf(b.data(), b.size(), "the filter's state after job %s fails its %s check (%.*f%s%s, limit "
                      "%.*f%s%s): not delivered", s, trn::filter::state_check_name(check), per > 1e3 ? 6 : 3,
                      e.a / per, sep, unit, per > 1e3 ? 6 : 3, e.b / per, sep, unit);
}

/** The filter's settings changed in RAM: which parts, and whether they were built again. */
void describe_filter_settings_bad(const fdir::Event& e, const char* s, std::span<char> b) noexcept {
  static constexpr std::array<const char*, 3> kPart{"configuration", "camera", "process noise"};
  std::array<char, 48> parts{};
  std::size_t n = 0;
  for (std::size_t i = 0; i < kPart.size(); ++i) {
    if (((e.cause >> i) & 1U) != 0U && n < parts.size()) {
      const int w = std::snprintf(parts.data() + n, parts.size() - n, "%s%s", n > 0U ? ", " : "", kPart[i]);
      n += w > 0 ? static_cast<std::size_t>(w) : 0U;
    }
  }
  (void)std::snprintf(b.data(), b.size(), "the filter's settings in RAM (%s) changed by the end of job %s: not "
                      "delivered, %s", parts.data(), s, e.a != 0U ? "built again from the image" : "NOT built again");
}

/** The text of the filter's TMR events (after the name), into @p b; false for another event. */
bool describe_tmr_event(const fdir::Event& e, const char* s, std::span<char> b) noexcept {
  switch (e.id) {
    case EventId::kCommandTaken:
      if ((e.cause & trn::tasks::kSupCommandSeq) != 0U) {
        (void)std::snprintf(b.data(), b.size(), "the filter supervisor's command %u (code %s: %s) taken by the filter at "
                            "job %u", e.cause & ~trn::tasks::kSupCommandSeq, s,
                            e.subject == trn::tasks::kCmdFilterTmr ? "TMR" : "simplex", e.a);
      } else {
        (void)std::snprintf(b.data(), b.size(), "telecommand %u (code %s) taken by the filter at job %u", e.cause, s, e.a);
      }
      return true;
    case EventId::kTmrStarting:
      (void)std::snprintf(b.data(), b.size(), "filter to TMR: replicas seeded with the state after job %s (epoch %u)", s,
                          e.cause);
      return true;
    case EventId::kTmrEstablished:
      (void)std::snprintf(b.data(), b.size(), "TMR established at job %s: three replicas agree with the filter "
                          "(%u jobs after the command); the voter delivers", s, e.a);
      return true;
    case EventId::kTmrSimplex:
      (void)std::snprintf(b.data(), b.size(), "filter simplex again at job %s (%s)", s,
                          e.cause == 0U   ? "command"
                          : e.cause == 3U ? "the filter restarted: TMR again once it has caught up"
                                          : "TMR not established in time");
      return true;
    case EventId::kTmrOutvoted:
      (void)std::snprintf(b.data(), b.size(), "replica %u on tile %s outvoted at job %u (%s)", e.a, s, e.cause,
                          e.b == 1U ? "different output or state" : "no output");
      return true;
    case EventId::kTmrAgrees:
      (void)std::snprintf(b.data(), b.size(), "replica %u on tile %s agrees again at job %u", e.a, s, e.cause);
      return true;
    case EventId::kTmrExcluded:
      (void)std::snprintf(b.data(), b.size(), "replica %u on tile %s excluded at job %u: it re-synchronises (%u voting)",
                          e.a, s, e.cause, e.b);
      return true;
    case EventId::kTmrResynced:
      (void)std::snprintf(b.data(), b.size(), "replica %u on tile %s seeded with the voted state, votes again from job "
                          "%u (%u voting)", e.a, s, e.cause, e.b);
      return true;
    case EventId::kTmrNoMajority:
      (void)std::snprintf(b.data(), b.size(), "no majority at job %s (different 0x%x, missing 0x%x; replicas on "
                          "tiles %u, %u, %u): nothing delivered", s, e.a, e.b & 0xFFU, no_majority_tile(e, 0U),
                          no_majority_tile(e, 1U), no_majority_tile(e, 2U));
      return true;
    case EventId::kAbftCorrected:
    case EventId::kAbftFailed: {
      const std::uint32_t row = e.cause >> 16U;
      const std::uint32_t col = e.cause & 0xFFFFU;
      const char* verdict = e.id == EventId::kAbftFailed ? "still wrong" : "right";
      if (col == fdir::kAbftColNotChecked && (e.a >> 16U) == 1U) {
        (void)std::snprintf(b.data(), b.size(), "product %s: row %u off its checksum (rows checked), %s after %u "
                            "recomputation(s)", s, row, verdict, e.b);
      } else if (col == fdir::kAbftColNotChecked) {
        (void)std::snprintf(b.data(), b.size(), "product %s: %u rows off their checksums, the worst %u (rows checked), "
                            "%s after %u recomputation(s)", s, e.a >> 16U, row, verdict, e.b);
      } else if (row != 0xFFFFU && col != 0xFFFFU) {
        (void)std::snprintf(b.data(), b.size(), "product %s: element (%u, %u) wrong, %s after %u recomputation(s)", s,
                            row, col, e.id == EventId::kAbftFailed ? "still wrong" : "right", e.b);
      } else {
        (void)std::snprintf(b.data(), b.size(), "product %s: %u row(s) and %u column(s) off their checksums, %s after "
                            "%u recomputation(s)", s, e.a >> 16U, e.a & 0xFFFFU,
                            e.id == EventId::kAbftFailed ? "still wrong" : "right", e.b);
      }
      return true;
    }
    case EventId::kCorrelationCorrected:
    case EventId::kCorrelationFailed: {
      const char* what = e.cause == 1U   ? "its dot products off the integral image's checksum"
                         : e.cause == 2U ? "its surface changed before the peak search ended"
                                         : "a score around its peak different when computed again";
      (void)std::snprintf(b.data(), b.size(), "%s%s at frame %u: correlation wrong (%s), %s after %u "
                          "recomputation(s)", e.subject == trn::kCoarseLandmark ? "the coarse stage" : "landmark ",
                          e.subject == trn::kCoarseLandmark ? "" : s, e.a, what,
                          e.id == EventId::kCorrelationFailed ? "still wrong, not matched" : "right", e.b);
      return true;
    }
    case EventId::kTmrVoterResumed:
      (void)std::snprintf(b.data(), b.size(), "the voter restarted at job %s goes on voting (epoch %u): delivers from "
                          "job %u; records of its outage written: %u", s, e.cause, e.a, e.b);
      return true;
    default:
      return false;
  }
}

const char* node_name(std::uint32_t n) noexcept {
  return n == trn::tasks::kNodeTrn      ? "trn_supervisor"
         : n == trn::tasks::kNodeVision ? "vision_supervisor"
         : n == trn::tasks::kNodeFilter ? "filter_supervisor"
                                        : "?";
}

const char* constraint_name(std::uint32_t c) noexcept {
  return c == 0U ? "reliability" : c == 1U ? "power" : c == 2U ? "capacity" : "?";
}

const char* level_name(std::uint32_t c, std::uint32_t level) noexcept {
  if (level > 1U) {
    return "?";
  }
  switch (c) {
    case 0U: return level == 0U ? "normal" : "high";
    case 1U: return level == 0U ? "full" : "save";
    case 2U: return level == 0U ? "full rate" : "half rate";
    default: return "?";
  }
}

const char* alternative_name(std::uint32_t a) noexcept {
  switch (a) {
    case trn::tasks::kAltDelegate: return "hand the policy down";
    case trn::tasks::kAltSimplex: return "filter simplex";
    case trn::tasks::kAltTmr: return "filter in TMR";
    case trn::tasks::kAltTmrReseed: return "TMR again from a fresh seed";
    case trn::tasks::kAltFullRate: return "every frame on the healthy vision tiles";
    case trn::tasks::kAltHalfRate: return "half the image rate";
    case trn::tasks::kAltAcceptSimplex: return "accept the simplex filter (reliability lowered, reported)";
    case trn::tasks::kAltReplicasOn: return "the filter's replicas powered";
    case trn::tasks::kAltReplicasParked: return "the replicas off while the filter is simplex";
    default: return "nothing to do";
  }
}

const char* from_name(std::uint32_t f) noexcept {
  return f == fdir::kFromPhase    ? "the mission phase"
         : f == fdir::kFromGround  ? "a telecommand"
         : f == fdir::kFromDefault ? "its default"
                                   : node_name(f);
}

/** The text of the supervisor tree's events (after the name), into @p b; false for another event. */
bool describe_supervisor_event(const fdir::Event& e, std::span<char> b) noexcept {
  const std::uint32_t c = e.cause & 0xFFU;
  switch (e.id) {
    case EventId::kSupPolicy:
      (void)std::snprintf(b.data(), b.size(), "%s takes %s %s from %s", node_name(e.subject), constraint_name(c),
                          level_name(c, e.a), from_name(e.b));
      return true;
    case EventId::kSupApply: {
      const std::uint32_t why = e.cause >> 8U;
      std::array<char, 64> reason{};
      (void)std::snprintf(reason.data(), reason.size(), "%s",
                          why == 0U ? "the policy" : why == 1U ? "the one before did not meet it" : "");
      if (why == 2U) {
        (void)std::snprintf(reason.data(), reason.size(), "escalation from %s", node_name(e.b >> 8U));
      }
      (void)std::snprintf(b.data(), b.size(), "%s: %s for %s %s (%s)", node_name(e.subject), alternative_name(e.a),
                          constraint_name(c), level_name(c, e.b & 0xFFU), reason.data());
      return true;
    }
    case EventId::kSupNotMet:
      (void)std::snprintf(b.data(), b.size(), "%s: %s does not meet %s %s", node_name(e.subject), alternative_name(e.a),
                          constraint_name(c), level_name(c, e.b));
      return true;
    case EventId::kSupEscalated:
      (void)std::snprintf(b.data(), b.size(), "%s has no way left to meet %s %s: escalated to %s", node_name(e.subject),
                          constraint_name(c), level_name(c, e.a),
                          e.b == fdir::kNoSupervisor ? "the vehicle" : node_name(e.b));
      return true;
    case EventId::kSupMet:
      (void)std::snprintf(b.data(), b.size(), "%s meets %s %s (%s)", node_name(e.subject), constraint_name(c),
                          level_name(c, e.b), alternative_name(e.a));
      return true;
    case EventId::kPhaseBegin:
      (void)std::snprintf(b.data(), b.size(), "mission phase %u begins: reliability %s, power %s", e.subject,
                          level_name(0U, e.a), level_name(1U, e.b));
      return true;
    case EventId::kSafeMode:
      (void)std::snprintf(b.data(), b.size(), "trn_supervisor cannot meet %s %s: safe mode reported to the vehicle",
                          constraint_name(e.subject), level_name(e.subject, e.a));
      return true;
    case EventId::kTileParked:
    case EventId::kTileWoken:
      (void)std::snprintf(b.data(), b.size(), "tile %u switched %s by the power policy (asked by tile %u)", e.subject,
                          e.id == EventId::kTileParked ? "off" : "on", e.cause);
      return true;
    default:
      return false;
  }
}

/** The text of the network-health events (after the name), into @p b. @return false for another event. */
bool describe_net_health_event(const fdir::Event& e, const char* s, std::span<char> b) noexcept {
  switch (e.id) {
    case EventId::kSuspectVote:
      (void)std::snprintf(b.data(), b.size(), "tile %u reports tile %s (vote %u of %u)", e.cause, s, e.a, e.b);
      break;
    case EventId::kSwitchFailed:
      (void)std::snprintf(b.data(), b.size(), "switch of tile %s declared failed (%u neighbours agree): map version %u",
                          s, e.a, e.b);
      break;
    case EventId::kLinkFailed:
      if (e.a == 0U) {
        (void)std::snprintf(b.data(), b.size(), "link between tiles %s and %u declared failed (both ends report each "
                            "other only): map version %u", s, e.cause, e.b);
      } else {
        (void)std::snprintf(b.data(), b.size(), "link between tiles %s and %u declared failed (the %u transit probes "
                            "heard across it lost, and no other): map version %u", s, e.cause, e.a, e.b);
      }
      break;
    case EventId::kMapPublished:
      (void)std::snprintf(b.data(), b.size(), "fault map version %u sent to %u of %u live tiles: traffic routes around",
                          e.subject, e.a, e.b);
      break;
    case EventId::kCoreSuspect:
      (void)std::snprintf(b.data(), b.size(), "core of tile %s silent behind a switch that routes (%u transits "
                          "through it answer)", s, e.a);
      break;
    case EventId::kTransitFailed:
      (void)std::snprintf(b.data(), b.size(), "switch of tile %s declared failed (all %u transit probes through it "
                          "lost): map version %u", s, e.a, e.b);
      break;
    case EventId::kLinkOrSwitchFailed:
      (void)std::snprintf(b.data(), b.size(), "link between tiles %u and %s or the switch of spare %s failed (the "
                          "%u transit probes heard across the link lost, none heard through the switch but over it: "
                          "they look the same from here): the switch taken out, map version %u", e.cause, s, s, e.a,
                          e.b);
      break;
    default:
      return false;
  }
  return true;
}

/** The text of the core-health and filter-restart events (after the name), into @p b. */
void describe_health_event(const fdir::Event& e, const char* s, std::span<char> b) noexcept {
  switch (e.id) {
    case EventId::kTaskOverdue:
      (void)std::snprintf(b.data(), b.size(), "task %s of tile %u missed its check-in by %u ticks (budget %u): "
                          "the watchdog is no longer kicked", s, e.cause, e.a, e.b);
      break;
    case EventId::kWatchdogExpired:
      (void)std::snprintf(b.data(), b.size(), "watchdog of tile %s expired (%u expiries so far)", s, e.a);
      break;
    case EventId::kTileReset:
      if (e.cause == 2U) {
        (void)std::snprintf(b.data(), b.size(), "tile %s reset by the supervisor: its results stayed wrong", s);
      } else {
        (void)std::snprintf(b.data(), b.size(), "tile %s reset by %s (reset %u of at most %u)", s,
                            e.cause == 1U ? "its watcher" : "the supervisor", e.a, e.b);
      }
      break;
    case EventId::kTileRecovered:
      (void)std::snprintf(b.data(), b.size(), "tile %s booted its role again and reported, %u ticks (ms) after its reset", s,
                          e.a);
      break;
    case EventId::kTileRebooted:
      if (e.cause == static_cast<std::uint32_t>(bsp::BootCause::kCommand)) {
        (void)std::snprintf(b.data(), b.size(), "tile %s booted again after a reset command: its role restarts", s);
      } else {
        (void)std::snprintf(b.data(), b.size(), "tile %s booted again without a command (cause %s): its role restarts",
                            s, boot_cause_name(e.cause));
      }
      break;
    case EventId::kTileLost:
      if (e.cause == fdir::kLostSwitchFailed) {
        (void)std::snprintf(b.data(), b.size(), "tile %s cut off: its switch is declared failed; retired, its roles "
                            "go to spares", s);
      } else {
        (void)std::snprintf(b.data(), b.size(), "tile %s did not report back %u ticks (ms) after its reset", s, e.a);
      }
      break;
    case EventId::kRoleMoved:
      if (e.b == 0U) {
        (void)std::snprintf(b.data(), b.size(), "worker slot %s: tile %u switched off for wrong results, spare %u "
                            "takes its place", s, e.cause, e.a);
      } else {
        (void)std::snprintf(b.data(), b.size(), "role slot %s moves from retired tile %u to spare %u (directory "
                            "version %u)", s, e.cause, e.a, e.b);
      }
      break;
    case EventId::kRoleRestored:
      (void)std::snprintf(b.data(), b.size(), "role slot %s runs again on tile %u (was tile %u), %u ticks (ms) after the move",
                          s, e.a, e.cause, e.b);
      break;
    case EventId::kSelfTestMismatch:
      (void)std::snprintf(b.data(), b.size(), "tile %s outvoted by two others in self-test round %u (%u in a row, "
                          "retired at %u)", s, e.cause, e.a, e.b);
      break;
    case EventId::kSelfTestAgree:
      (void)std::snprintf(b.data(), b.size(), "tile %s agrees again in self-test round %u", s, e.cause);
      break;
    case EventId::kSupervisorSilent:
      (void)std::snprintf(b.data(), b.size(), "no heartbeat from the supervisor's tile %s for %u ticks (ms): its watcher "
                          "(tile %u) takes it as hung (%u resets so far)", s, e.a, e.cause, e.b);
      break;
    case EventId::kWatcherCutOff:
      (void)std::snprintf(b.data(), b.size(), "no heartbeat from the supervisor's tile %s for %u ticks (ms), but its "
                          "watcher (tile %u) hears none of its neighbours or transits: its own silence, no reset", s,
                          e.a, e.cause);
      break;
    case EventId::kSelfTestLate:
      (void)std::snprintf(b.data(), b.size(), "tile %s had not answered self-test round %u after %u ticks (voted "
                          "if it answers before the next round)", s, e.cause, e.a);
      break;
    case EventId::kFilterResumed:
      (void)std::snprintf(b.data(), b.size(), "filter resumed from checkpoint %s (IMU sample %u), %u samples to "
                          "replay from the I/O record", s, e.b, e.a);
      break;
    case EventId::kFilterStateBad:
      describe_filter_state_bad(e, s, b);
      break;
    case EventId::kFilterSettingsBad:
      describe_filter_settings_bad(e, s, b);
      break;
    case EventId::kCheckpointBad:
      (void)std::snprintf(b.data(), b.size(), "filter checkpoint slot %s failed its checks: not used (%u bad)", s, e.a);
      break;
    case EventId::kImuGap:
      (void)std::snprintf(b.data(), b.size(), "%u IMU samples from sample %s neither received nor recorded", e.a, s);
      break;
    case EventId::kNoSpare:
      (void)std::snprintf(b.data(), b.size(), "role slot %s of tile %u cannot move: no spare", s, e.cause);
      break;
    default:
      if (!describe_tmr_event(e, s, b) && !describe_supervisor_event(e, b)) {
        (void)std::snprintf(b.data(), b.size(), "subject %s, cause %u, %u, %u", s, e.cause, e.a, e.b);
      }
      break;
  }
}

}  // namespace

std::size_t describe_flight_event(const fdir::Event& e, std::span<char> out) noexcept {
  if (out.empty()) {
    return 0U;
  }
  const fdir::EventInfo* info = fdir::event_info(e.id);
  const int head = std::snprintf(out.data(), out.size(), "%s: ", info != nullptr ? info->name : "unknown");
  const std::size_t used = head > 0 ? std::min(static_cast<std::size_t>(head), out.size() - 1U) : 0U;
  const std::span<char> b = out.subspan(used);
  std::array<char, 12> subject{};
  if (e.subject == fdir::kUnknown) {
    subject[0] = '?';
  } else {
    (void)std::snprintf(subject.data(), subject.size(), "%u", e.subject);
  }
  const char* s = subject.data();
  switch (e.id) {
    case EventId::kPacketCorrected:
      (void)std::snprintf(b.data(), b.size(), "packet from tile %s corrected by its SECDED code (channel %u, seq %u)",
                          s, e.cause, e.a);
      break;
    case EventId::kPacketForwarded:
      (void)std::snprintf(b.data(), b.size(), "packet from tile %s misdelivered here, forwarded to tile %u", s,
                          e.cause);
      break;
    case EventId::kPacketDamaged:
      (void)std::snprintf(b.data(), b.size(), "packet from tile %s damaged beyond correction%s", s,
                          e.a != 0U ? ": NACK sent" : ": left to the sender's timeout");
      break;
    case EventId::kPacketResent:
      (void)std::snprintf(b.data(), b.size(), "stream to tile %s resent go-back-N after a %s (channel %u, from seq %u)",
                          s, e.cause == 0U ? "NACK" : "timeout", e.a, e.b);
      break;
    case EventId::kPacketGaveUp:
      (void)std::snprintf(b.data(), b.size(), "packet to tile %s given up (channel %u, seq %u): %s", s, e.a, e.b,
                          e.cause == 1U ? "not delivered (it never left)" : "delivery unknown (no ACK came back)");
      break;
    case EventId::kRouteUnreachable:
      (void)std::snprintf(b.data(), b.size(), "no route to tile %s (channel %u, seq %u): %s", s, e.a, e.b,
                          e.cause == 1U ? "not delivered" : "given up, delivery unknown");
      break;
    case EventId::kPacketSettled:
      (void)std::snprintf(b.data(), b.size(), "packet to tile %s given up (channel %u, seq %u) was %s", s, e.a, e.b,
                          e.cause == 2U ? "delivered: only its ACKs were lost" : "not delivered: the receiver skipped it");
      break;
    case EventId::kForwardUnreachable:
      (void)std::snprintf(b.data(), b.size(), "no route to forward a packet to tile %s", s);
      break;
    case EventId::kNeighbourSuspect:
      (void)std::snprintf(b.data(), b.size(), "neighbour tile %s does not answer the probe: reported", s);
      break;
    case EventId::kMapApplied:
      (void)std::snprintf(b.data(), b.size(), "fault map version %u applied (from tile %u): routes rebuilt", e.subject,
                          e.cause);
      break;
    case EventId::kMapPushed:
      (void)std::snprintf(b.data(), b.size(), "neighbour tile %s probes with an older map: sent version %u", s,
                          e.a);
      break;
    case EventId::kTransitLost:
      (void)std::snprintf(b.data(), b.size(), "transit probe to tile %s unanswered: reported", s);
      break;
    case EventId::kTransitBack:
      (void)std::snprintf(b.data(), b.size(), "transit probe to tile %s answers again: reported", s);
      break;
    case EventId::kWorkerSilent:
      (void)std::snprintf(b.data(), b.size(), "worker tile %s silent for %u frames: isolated, its work goes to the others",
                          s, e.a);
      break;
    case EventId::kWorkerBack:
      (void)std::snprintf(b.data(), b.size(), "worker tile %s answers again: back in the frame", s);
      break;
    case EventId::kFrameDone:
      (void)std::snprintf(b.data(), b.size(), "frame %u done: %u matches, %u units lost", e.a, e.b, e.cause);
      break;
    case EventId::kResultsSuspect:
      (void)std::snprintf(b.data(), b.size(), "worker tile %s: %u of its %u results in the window off the frame's fit: "
                          "%s", s, e.a, e.b, e.cause == 1U ? "wrong again after its reset, replacement asked"
                                                            : "suspect, its results not used");
      break;
    case EventId::kResultsConsistent:
      (void)std::snprintf(b.data(), b.size(), "worker tile %s: results consistent again for %u frames%s: used again", s,
                          e.a, e.cause == 1U ? " after its reset" : "");
      break;
    case EventId::kVisionSetUpFailed: {
      static constexpr std::array<const char*, 6> kSteps{"?", "its tile lists", "the map product", "its DDR carves",
                                                        "the landmark selection", "the relit coarse map"};
      (void)std::snprintf(b.data(), b.size(), "the vision coordinator could not start: %s failed (status %u); "
                          "no frame will be planned", kSteps[e.subject < kSteps.size() ? e.subject : 0U], e.a);
      break;
    }
    case EventId::kCoarseBandRedone: {
      static constexpr std::array<const char*, 5> kWhy{"?", "it could not be sent", "no answer in time",
                                                       "its checks failed", "its copy differs from its digest"};
      (void)std::snprintf(b.data(), b.size(), "coarse band from row %u of frame %u dealt to tile %s: %s; "
                          "computed by the coordinator", e.a, e.b, s, kWhy[e.cause < kWhy.size() ? e.cause : 0U]);
      break;
    }
    case EventId::kLandmarkProductRefused: {
      static constexpr std::array<const char*, 6> kWhy{"?", "the block is too short", "its header is wrong",
                                                       "it was selected with other settings",
                                                       "it was selected on another map", "its records are wrong"};
      (void)std::snprintf(b.data(), b.size(), "the ground's landmark table (%u bytes) refused: %s; the coordinator "
                          "selects the landmarks itself", e.a, kWhy[e.cause < kWhy.size() ? e.cause : 0U]);
      break;
    }
    case EventId::kMonitorWarn:
    case EventId::kMonitorFatal:
      (void)std::snprintf(b.data(), b.size(), "monitor %s %s: value %u against %u", s,
                          e.id == EventId::kMonitorWarn ? "warning" : "fatal", e.a, e.b);
      break;
    case EventId::kActionCapped:
      (void)std::snprintf(b.data(), b.size(), "monitor %s: %u actions taken, no more (cap)", s, e.a);
      break;
    case EventId::kAssertFailed:
      (void)std::snprintf(b.data(), b.size(), "assertion %s failed (line %u): recovery requested", s, e.cause);
      break;
    default:
      if (!describe_net_health_event(e, s, b)) {
        describe_health_event(e, s, b);
      }
      break;
  }
  return used + std::char_traits<char>::length(b.data());
}

std::string describe_flight_event(const fdir::Event& e) {
  std::array<char, kEventTextBytes> buf{};
  const std::size_t n = describe_flight_event(e, buf);
  return std::string(buf.data(), n);
}

FlightEventCollector::FlightEventCollector(std::size_t capacity) { events_.reserve(capacity); }

void FlightEventCollector::take(const fdir::Event& e) noexcept {
  switch (e.id) {
    case EventId::kSwitchFailed:
    case EventId::kTransitFailed:
    case EventId::kLinkOrSwitchFailed: health_[e.subject % bsp::kMaxTiles] = TileHealth::kFailed; break;
    case EventId::kWorkerSilent:
    case EventId::kCoreSuspect:
    case EventId::kNeighbourSuspect:
    case EventId::kWatchdogExpired:
    case EventId::kResultsSuspect:
    case EventId::kTileReset:
      if (e.subject < bsp::kMaxTiles && health_[e.subject] != TileHealth::kFailed) {
        health_[e.subject] = TileHealth::kSuspect;
      }
      break;
    case EventId::kTileLost:
      health_[e.subject % bsp::kMaxTiles] = TileHealth::kFailed;
      break;
    case EventId::kRoleMoved:
      health_[e.cause % bsp::kMaxTiles] = TileHealth::kFailed;
      break;
    case EventId::kRoleRestored:
      health_[e.a % bsp::kMaxTiles] = TileHealth::kRecovered;
      break;
    case EventId::kWorkerBack:
    case EventId::kResultsConsistent:
    case EventId::kTileRecovered:
    case EventId::kTileRebooted:
      if (e.subject < bsp::kMaxTiles) {
        health_[e.subject] = TileHealth::kRecovered;
      }
      break;
    case EventId::kFrameDone:
      ++frames_;
      matches_ += e.b;
      break;
    default: break;
  }
}

void FlightEventCollector::poll(double clock_hz, EventLog& log) noexcept {
  for (bsp::TileId t = 0; t < bsp::kMaxTiles; ++t) {
    const std::uint64_t written = fdir::event_log_written(t);
    for (; next_[t] < written; ++next_[t]) {
      fdir::Event e{};
      if (!fdir::event_log_read(t, next_[t], &e)) {
        ++lost_;  // overwritten before this poll
        continue;
      }
      take(e);
      if (events_.size() < events_.capacity()) {
        events_.push_back(e);
      } else {
        ++lost_;
      }
      if (e.id == EventId::kFrameDone) {
        continue;  // one a second: the summary counts them, the log stays readable
      }
      std::array<char, kEventTextBytes> text{};
      const std::size_t n = describe_flight_event(e, text);
      (void)log.add(seconds(e.cycle, clock_hz), category_of(e), e.tile, std::string_view(text.data(), n));
    }
  }
}

}  // namespace tools
