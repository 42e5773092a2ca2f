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

/** How long after an injection a detection may come and still be its (emulated seconds). */
constexpr double kDetectWindowS = 5.0;
/** How long after its detection the recovery may come. */
constexpr double kRecoverWindowS = 5.0;

double seconds(bsp::Cycles c, double clock_hz) { return static_cast<double>(c) / clock_hz; }

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

/** Neighbour of @p t in direction @p dir on the 8x8 grid (kNoTile off the grid). */
bsp::TileId neighbour_of(bsp::TileId t, std::uint64_t dir, std::uint32_t cols, std::uint32_t rows) {
  const std::uint32_t x = t % cols;
  const std::uint32_t y = t / cols;
  switch (dir) {
    case 0: return x + 1U < cols ? t + 1U : bsp::kNoTile;
    case 1: return x > 0U ? t - 1U : bsp::kNoTile;
    case 2: return y > 0U ? t - cols : bsp::kNoTile;
    case 3: return y + 1U < rows ? t + cols : bsp::kNoTile;
    default: return bsp::kNoTile;
  }
}

const char* boot_cause_name(std::uint32_t cause) noexcept {
  switch (cause) {
    case static_cast<std::uint32_t>(bsp::BootCause::kPowerOn): return "power-on";
    case static_cast<std::uint32_t>(bsp::BootCause::kCommand): return "command";
    case static_cast<std::uint32_t>(bsp::BootCause::kWatchdog): return "own watchdog";
    default: return "crash or external reset";
  }
}

/** A fault of the core of @p t (hang, reset): the tile named by a detection of its silence or its switch. */
bool detects_core(bsp::TileId t, const fdir::Event& e) {
  if (e.id == EventId::kTaskOverdue) {
    return e.tile == t;  // the tile's own agent names one of its tasks
  }
  return (e.id == EventId::kWorkerSilent || e.id == EventId::kSwitchFailed || e.id == EventId::kNeighbourSuspect ||
          e.id == EventId::kCoreSuspect || e.id == EventId::kWatchdogExpired || e.id == EventId::kTileRebooted ||
          e.id == EventId::kSupervisorSilent || e.id == EventId::kSelfTestMismatch ||
          e.id == EventId::kTmrOutvoted) &&
         e.subject == t;
}

/**
 * Wrong data leaves the tile answering: only a check of what it computed or stored names it
 * (a neighbour that stops hearing it nearby is about something else, e.g. a failed link).
 */
bool detects_wrong_data(bsp::TileId t, const fdir::Event& e) {
  return (e.id == EventId::kSelfTestMismatch || (e.id == EventId::kTmrOutvoted && e.b == 1U)) && e.subject == t;
}

/** How long after a corrupted product its check reports it at most: one filter period. */
constexpr double kAbftSameJobS = 0.010;

/**
 * How long after a corrupted dot product or surface the vision tile reports it at most: the
 * landmark's two correlation passes and their recomputations (a few ms each; one unit of landmarks
 * takes under 20 ms), reported once the landmark is done.
 */
constexpr double kCorrelationSameLandmarkS = 0.020;
/** ... and a band of the coarse stage, reported by the tile that computed it once the band is done (the coordinator's stage takes 40-100 ms). */
constexpr double kCorrelationCoarseStageS = 0.300;

/**
 * Whether @p e is the simplex filter's plausibility check refusing its state
 * after fault @p r on its tile: for a corrupted update (sdc), in the job it
 * hit; for an upset (seu), at any later job. Or, for an upset in the
 * EKF's settings, the filter finding them changed.
 */
bool filter_state_check_of(const bsp::FaultRecord& r, const fdir::Event& e, double clock_hz) {
  if (e.tile != r.spec.tile || e.cycle < r.applied_cycle) {
    return false;
  }
  if (e.id == EventId::kFilterSettingsBad) {
    // An upset in the settings' bytes only (the EKF carve's first bytes): one elsewhere in the EKF
    // took the settings check of a later upset that did land there.
    return r.spec.kind == bsp::FaultKind::kSeu && r.carve != nullptr &&
           std::strcmp(r.carve, trn::tasks::kEkfCarve) == 0 && r.carve_offset < trn::tasks::kEkfSettingsBytes;
  }
  return e.id == EventId::kFilterStateBad &&
         (r.spec.kind == bsp::FaultKind::kSeu || seconds(e.cycle - r.applied_cycle, clock_hz) <= kAbftSameJobS);
}

/** Whether @p e is a checked correlation's event about the sdc @p r (same tile, a correlation point, soon after). */
bool correlation_check_of(const bsp::FaultRecord& r, const fdir::Event& e, double clock_hz) {
  const bool point = r.spec.channel == trn::vision::kCorrelationDotChannel ||
                     r.spec.channel == trn::vision::kCorrelationSurfaceChannel;
  return point && (e.id == EventId::kCorrelationCorrected || e.id == EventId::kCorrelationFailed) &&
         e.tile == r.spec.tile && e.cycle >= r.applied_cycle &&
         seconds(e.cycle - r.applied_cycle, clock_hz) <=
             (e.subject == trn::kCoarseLandmark ? kCorrelationCoarseStageS : kCorrelationSameLandmarkS);
}

/**
 * Whether @p e is the coordinator finding the corrupted band @p r of a vision tile (its copy
 * against the band's digest) and computing it itself, within the coarse stage.
 */
bool coarse_band_check_of(const bsp::FaultRecord& r, const fdir::Event& e, double clock_hz) {
  return r.spec.channel == trn::tasks::kCoarseBandChannel && e.id == EventId::kCoarseBandRedone &&
         e.subject == r.spec.tile && e.cycle >= r.applied_cycle &&
         seconds(e.cycle - r.applied_cycle, clock_hz) <= kCorrelationCoarseStageS;
}

/** How long after a replica's output was corrupted its vote reports it at most: the job's vote waits for its last output. */
constexpr double kTmrSameVoteS = 0.030;

/**
 * Longest wait from a damaged packet to the resend that brings it again: the
 * sender's first resend comes one retransmit timeout after the packet left,
 * at most 16 times the measured round trip (docs/FT_MESSAGING.md), tens of
 * milliseconds in the flights measured.
 */
constexpr double kDamagedResendS = 0.250;

/**
 * Longest wait from a flipped packet's send to its decoding: the tile it
 * reaches decodes it at its next poll (every tick), milliseconds later even
 * behind a full receive queue.
 */
constexpr double kPacketDecodeS = 0.100;

/** Replica @p i's tile named in a tmr_no_majority event (b: missing | tile of replica i << 8 (i + 1)). */
bsp::TileId no_majority_tile(const fdir::Event& e, std::uint32_t i) {
  return static_cast<bsp::TileId>((e.b >> (8U * (i + 1U))) & 0xFFU);
}

/** How many replicas a tmr_no_majority event names as different (each a suspect); 1 for any other event. */
std::uint32_t suspects_named(const fdir::Event& e) {
  if (e.id != EventId::kTmrNoMajority) {
    return 1U;
  }
  std::uint32_t n = 0U;
  for (std::uint32_t i = 0; i < 3U; ++i) {
    n += (e.a >> i) & 1U;
  }
  return n;
}

/** Whether @p e is a vote without a majority that names the corrupted output of @p r's tile, in its job. */
bool no_majority_of(const bsp::FaultRecord& r, const fdir::Event& e, double clock_hz) {
  if (e.id != EventId::kTmrNoMajority || e.cycle < r.applied_cycle ||
      seconds(e.cycle - r.applied_cycle, clock_hz) > kTmrSameVoteS) {
    return false;
  }
  for (std::uint32_t i = 0; i < 3U; ++i) {
    if (((e.a >> i) & 1U) != 0U && no_majority_tile(e, i) == r.spec.tile) {
      return true;
    }
  }
  return false;
}

/** Whether flight event @p e detects the injection @p r (see docs/FDIR.md, "The join"). */
bool detects(const bsp::FaultRecord& r, const fdir::Event& e, double clock_hz) {
  const bsp::TileId t = r.spec.tile;
  switch (r.spec.kind) {
    case bsp::FaultKind::kPacketBitFlip: {
      // The receiver (or a forwarder) decodes the packet from source t as it arrives; a packet too
      // damaged to name its source is any flip's, but only then: a later one is another flip's (a flip
      // nobody saw took the next flip's detection before, and that one went unseen in turn). A resend
      // by t after a timeout, within one retransmit timeout, recovers a lost one.
      const double after = seconds(e.cycle - r.applied_cycle, clock_hz);
      if (e.id == EventId::kPacketCorrected || e.id == EventId::kPacketForwarded || e.id == EventId::kPacketDamaged) {
        return (e.subject == t || e.subject == fdir::kUnknown) && after <= kPacketDecodeS;
      }
      return e.id == EventId::kPacketResent && e.tile == t && e.cause == 1U && after <= kDamagedResendS;
    }
    case bsp::FaultKind::kSwitchFail:
      // A spare's switch whose other transits cannot be heard looks like its link from the health
      // tile: the flight says "this link or this switch" and takes the switch out.
      return (e.id == EventId::kSwitchFailed || e.id == EventId::kTransitFailed ||
              e.id == EventId::kLinkOrSwitchFailed) && e.subject == t;
    case bsp::FaultKind::kLinkFail: {
      const bsp::TileId n = neighbour_of(t, r.spec.param, bsp::kTile64.cols, bsp::kTile64.rows);
      const bool pair = (e.subject == t && e.cause == n) || (e.subject == n && e.cause == t);
      return (e.id == EventId::kLinkFailed || e.id == EventId::kLinkOrSwitchFailed) && pair;
    }
    case bsp::FaultKind::kSeu:
      if (r.crashed) {
        return detects_core(t, e);  // it landed in control data: the tile crashed
      }
      return detects_wrong_data(t, e) || filter_state_check_of(r, e, clock_hz);
    case bsp::FaultKind::kSdc:
      // A corrupted product is also found by the tile itself, by its checksums, in the same job: a
      // check of a later product is about that product (a flip below the round-off is never seen).
      // Wrong results (a lasting shift of a vision tile's matches) are found by the coordinator; a
      // corrupted correlation by its tile's checks while the landmark is matched.
      // Two replicas' outputs corrupted in one job leave no majority: the vote names the different ones.
      return detects_wrong_data(t, e) || (e.id == EventId::kResultsSuspect && e.subject == t) ||
             filter_state_check_of(r, e, clock_hz) ||
             correlation_check_of(r, e, clock_hz) || coarse_band_check_of(r, e, clock_hz) || no_majority_of(r, e, clock_hz) ||
             ((e.id == EventId::kAbftCorrected || e.id == EventId::kAbftFailed) && e.tile == t &&
              seconds(e.cycle - r.applied_cycle, clock_hz) <= kAbftSameJobS);
    case bsp::FaultKind::kWatchdogFail:
      // Latent: nothing on the chip checks a watchdog itself; its failure shows only through the hang
      // it then misses, and that detection is the hang's.
      return false;
    default:
      return detects_core(t, e);
  }
}

/**
 * Whether resend @p e brings again what damaged packet @p d lost, the packet
 * being one tile @p source sent (the injection's tile). A data packet comes
 * again by its source's resend (after the receiver's NACK, or a timeout); a
 * lost ACK by the data's sender resending to the ACK's source. When the packet
 * still named its source (d.subject: the receiver NACKed it), only the
 * source's resend to the tile that dropped it; when the damage hid the source
 * (the drop may have been at a forwarder), a resend by or to @p source. Either
 * must follow within kDamagedResendS: a later one, or one between other
 * tiles, is another packet's (before, any resend anywhere was credited to a
 * damaged packet of unknown source, seconds later). A probe, a BUSY answer or
 * an ACK a later one covers is resent by nobody: the damage stays detected and
 * not recovered, for nothing in the flight said more.
 */
bool resend_of_damaged(const fdir::Event& d, const fdir::Event& e, bsp::TileId source, double clock_hz) {
  if (e.id != EventId::kPacketResent || e.cycle < d.cycle || seconds(e.cycle - d.cycle, clock_hz) > kDamagedResendS) {
    return false;
  }
  if (d.subject != fdir::kUnknown) {
    return e.tile == d.subject && e.subject == d.tile;
  }
  return e.tile == source || e.subject == source;
}

/** Whether @p e recovers a fault of tile @p t detected by @p d. */
bool recovers(const fdir::Event& d, const fdir::Event& e, bsp::TileId t, double clock_hz) {
  switch (d.id) {
    case EventId::kPacketCorrected:
    case EventId::kPacketForwarded:
    case EventId::kPacketResent:
      return false;  // recovered by the detecting event itself
    case EventId::kPacketDamaged:
      return resend_of_damaged(d, e, t, clock_hz);
    case EventId::kSwitchFailed:
    case EventId::kTransitFailed:
    case EventId::kLinkFailed:
    case EventId::kLinkOrSwitchFailed:
      return e.id == EventId::kMapPublished && e.subject >= d.b;
    case EventId::kWorkerSilent:
      return (e.id == EventId::kFrameDone && e.cause == 0U) || (e.id == EventId::kWorkerBack && e.subject == d.subject);
    case EventId::kWatchdogExpired:
    case EventId::kSupervisorSilent:
    case EventId::kCoreSuspect:
    case EventId::kNeighbourSuspect:
      return (e.id == EventId::kTileRecovered && e.subject == d.subject) ||
             (e.id == EventId::kRoleRestored && e.cause == d.subject);
    case EventId::kSelfTestMismatch:
      // Agreeing again, its role on a spare, or the tile started again from its image (the
      // supervisor's own tile resets itself: no spare takes its role).
      return (e.id == EventId::kSelfTestAgree && e.subject == d.subject) ||
             (e.id == EventId::kRoleRestored && e.cause == d.subject) ||
             (e.id == EventId::kTileRebooted && e.subject == d.subject);
    case EventId::kResultsSuspect:
      // Consistent again (a transient), or a spare in its place.
      return (e.id == EventId::kResultsConsistent && e.subject == d.subject) ||
             (e.id == EventId::kRoleRestored && e.cause == d.subject);
    case EventId::kTmrOutvoted:
      // A replica outvoted is recovered once it agrees again or was seeded with the voted state.
      return (e.id == EventId::kTmrAgrees || e.id == EventId::kTmrResynced) && e.subject == d.subject;
    case EventId::kTmrNoMajority:
      // A replica it named agreeing with the vote again (a transient), every replica seeded afresh, or
      // the filter simplex again (no replica's output used): what the filter supervisor does about
      // votes without a majority that do not pass.
      if (e.id == EventId::kTmrAgrees || e.id == EventId::kTmrResynced) {
        for (std::uint32_t i = 0; i < 3U; ++i) {
          if (((d.a >> i) & 1U) != 0U && no_majority_tile(d, i) == e.subject) {
            return true;
          }
        }
        return false;
      }
      return e.id == EventId::kTmrStarting || e.id == EventId::kTmrSimplex;
    case EventId::kFilterSettingsBad:
      // A TMR replica that rebuilt its settings drops its state: re-seeded, it votes again.
      if ((e.id == EventId::kTmrResynced || e.id == EventId::kTmrAgrees) && e.subject == d.tile) {
        return true;
      }
      [[fallthrough]];
    case EventId::kFilterStateBad:
      // Back to its last checkpoint: in the job that refused the state (or rebuilt the settings), or
      // after the tile's restart when it was refused again (join_faults() skips a resume refused again).
      return e.id == EventId::kFilterResumed && e.tile == d.tile && e.cycle >= d.cycle;
    case EventId::kTaskOverdue:
      return (e.id == EventId::kTileRecovered && e.subject == d.tile) ||
             (e.id == EventId::kRoleRestored && e.cause == d.tile);
    default:
      // A neighbour's suspicion alone isolates nothing; a tile_rebooted recovers by itself (the
      // tile runs its role again).
      return false;
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

namespace {

/**
 * Whether filter_resumed @p events[k], the recovery of filter_state_bad or
 * filter_settings_bad @p d, did not hold: the filter refused a job again
 * before it had written a newer checkpoint, so its next resume on that tile
 * (after the tile's restart) is from the same checkpoint, or none came before
 * the end. That is the flight's own rule (a checkpoint is not gone back to
 * twice): what was wrong was not in the checkpoint, and the recovery is the
 * later resume. False for any other detection.
 */
bool refused_again(const fdir::Event& d, std::span<const fdir::Event> events, const std::vector<std::size_t>& order,
                   std::size_t k) {
  const auto refusal = [](const fdir::Event& e) {
    return e.id == EventId::kFilterStateBad || e.id == EventId::kFilterSettingsBad;
  };
  if (!refusal(d)) {
    return false;
  }
  const fdir::Event& resumed = events[k];
  bool refused = false;
  for (const std::size_t j : order) {
    const fdir::Event& e = events[j];
    if (e.cycle <= resumed.cycle || e.tile != resumed.tile) {
      continue;
    }
    if (e.id == EventId::kFilterResumed) {
      return refused && e.subject == resumed.subject;
    }
    refused = refused || refusal(e);
  }
  return refused;
}

}  // namespace

FaultAccount join_faults(std::span<const bsp::FaultRecord> records, std::span<const fdir::Event> events,
                         double clock_hz) {
  FaultAccount acc;
  acc.outcomes.resize(records.size());
  // Events in time order (ties: tile, then the order read).
  std::vector<std::size_t> order(events.size());
  for (std::size_t i = 0; i < order.size(); ++i) {
    order[i] = i;
  }
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    return events[a].cycle < events[b].cycle || (events[a].cycle == events[b].cycle && events[a].tile < events[b].tile);
  });
  // An event detects one injection; a vote without a majority one per replica it names as different.
  std::vector<std::uint32_t> claims_left(events.size());
  for (std::size_t k = 0; k < events.size(); ++k) {
    claims_left[k] = suspects_named(events[k]);
  }
  // Injections in the order they took effect.
  std::vector<std::size_t> inj;
  for (std::size_t i = 0; i < records.size(); ++i) {
    if (records[i].status == bsp::FaultStatus::kApplied) {
      inj.push_back(i);
    } else {
      ++acc.not_delivered;
    }
  }
  std::stable_sort(inj.begin(), inj.end(),
                   [&](std::size_t a, std::size_t b) { return records[a].applied_cycle < records[b].applied_cycle; });
  double latency_sum = 0.0;
  for (const std::size_t i : inj) {
    const bsp::FaultRecord& r = records[i];
    FaultOutcome& o = acc.outcomes[i];
    o.delivered = true;
    o.injected_s = seconds(r.applied_cycle, clock_hz);
    ++acc.injected;
    std::size_t det = events.size();
    for (const std::size_t k : order) {
      const double t = seconds(events[k].cycle, clock_hz);
      if (events[k].cycle < r.applied_cycle || claims_left[k] == 0U) {
        continue;
      }
      if (t - o.injected_s > kDetectWindowS) {
        break;
      }
      if (detects(r, events[k], clock_hz)) {
        det = k;
        break;
      }
    }
    if (det == events.size()) {
      continue;
    }
    --claims_left[det];
    const fdir::Event& d = events[det];
    o.detected = true;
    o.detected_s = seconds(d.cycle, clock_hz);
    o.detected_by = d.id;
    o.detector = d.tile;
    ++acc.detected;
    latency_sum += o.detected_s - o.injected_s;
    acc.max_detection_latency_s = std::max(acc.max_detection_latency_s, o.detected_s - o.injected_s);
    if ((d.steps & fdir::kStepRecover) != 0U) {
      o.recovered = true;
      o.recovered_s = o.detected_s;
      ++acc.recovered;
      continue;
    }
    for (const std::size_t k : order) {
      if (events[k].cycle < d.cycle || claims_left[k] == 0U || k == det) {
        continue;
      }
      if (seconds(events[k].cycle, clock_hz) - o.detected_s > kRecoverWindowS) {
        break;
      }
      if (recovers(d, events[k], r.spec.tile, clock_hz) && !refused_again(d, events, order, k)) {
        // A map publication or a complete frame closes every fault it covers: not claimed.
        if (events[k].id == EventId::kPacketResent) {
          claims_left[k] = 0U;
        }
        o.recovered = true;
        o.recovered_s = seconds(events[k].cycle, clock_hz);
        ++acc.recovered;
        break;
      }
    }
  }
  acc.mean_detection_latency_s = acc.detected > 0U ? latency_sum / static_cast<double>(acc.detected) : 0.0;
  return acc;
}

void log_fault_outcomes(std::span<const bsp::FaultRecord> records, const FaultAccount& account, double clock_hz,
                        EventLog& log) {
  for (std::size_t i = 0; i < records.size() && i < account.outcomes.size(); ++i) {
    const bsp::FaultRecord& r = records[i];
    const FaultOutcome& o = account.outcomes[i];
    const double t_s = o.delivered ? o.injected_s : seconds(r.spec.cycle, clock_hz);
    std::string text = describe_fault(r);
    if (o.delivered) {
      std::array<char, 160> b{};
      if (!o.detected) {
        (void)std::snprintf(b.data(), b.size(), " -> not detected by the flight software");
      } else {
        const fdir::EventInfo* info = fdir::event_info(o.detected_by);
        (void)std::snprintf(b.data(), b.size(), " -> detected by tile %u (%s) %.1f ms later%s", o.detector,
                            info != nullptr ? info->name : "?", (o.detected_s - o.injected_s) * 1e3,
                            o.recovered ? "" : ", not recovered");
        if (o.recovered) {
          const std::size_t used = std::char_traits<char>::length(b.data());
          (void)std::snprintf(b.data() + used, b.size() - used, ", recovered %.1f ms after detection",
                              (o.recovered_s - o.detected_s) * 1e3);
        }
      }
      text += b.data();
    } else {
      text += " -> not delivered";
    }
    (void)log.add(t_s, o.delivered ? EventCategory::kInject : EventCategory::kInfo, r.spec.tile, text);
  }
}

}  // namespace tools
