/**
 * @file fault_account.cpp
 * @brief The strict join: detections by accusation, wrong diagnoses, false alarms, healthy tiles
 *        disturbed, recovery on the roles' output streams.
 */
#include "tools/common/accounting/fault_account.hpp"
#include "trn/events.hpp"

#include "bsp_tile64/emu/profile.hpp"
#include "tools/common/mission/fault_plan.hpp"
#include "trn/match.hpp"
#include "trn/filter/filter_core.hpp"
#include "trn/tasks/messages.hpp"
#include "trn/tasks/sdc_points.hpp"
#include "trn/tasks/supervisors/supervisors.hpp"
#include "trn/tasks/vision/vision_coord.hpp"
#include "trn/tasks/vision/vision_worker.hpp"
#include "trn/vision/correlator.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <sstream>

namespace tools {

using fdir::Diagnosis;
using fdir::EventId;
using bsp::FaultKind;
using trn::tasks::Role;

const std::array<DetectBound, static_cast<std::size_t>(FaultKind::kCount)> kDetectBounds{{
    {FaultKind::kCoreHang, 3.0,
     "the watchdog names a silent core within 20 ms; a silent vision worker is named after the frames it missed in a "
     "row, at one frame a second"},
    {FaultKind::kCoreReset, 3.0, "as a hang: the tile is silent until it boots again"},
    {FaultKind::kSdc, 5.0,
     "a tile's own checks report in the same job or landmark (tighter bounds in the rules); a lasting shift of a "
     "vision tile's matches is named after the consistency window's frames"},
    {FaultKind::kSeu, 5.0,
     "the self-test reaches a tile every 0.7-2.3 s; the filter's checks read its state at every job"},
    {FaultKind::kWatchdogFail, 0.0, "latent: nothing on the chip tests a watchdog; only the hang it then misses shows"},
    {FaultKind::kPacketBitFlip, 0.25,
     "the receiver decodes the packet at its next poll; a lost one is resent after one retransmit timeout"},
    {FaultKind::kSwitchFail, 1.0, "the neighbours' votes within 40 ms, transits through a spare's switch within 100 ms"},
    {FaultKind::kLinkFail, 1.0, "as a switch"},
}};

namespace {

/** How long after its detection (or the map that isolates it) the service may come back and count. */
constexpr double kRecoverWindowS = 5.0;
/** A stream is back once it flows this long without a gap over kSteadyGapS (or to the end of the run). */
constexpr double kSteadyS = 0.5;
constexpr double kSteadyGapS = 0.1;
/** A watchdog expires this long at most after its tile asked for its restart (assert_failed). */
constexpr double kRequestedRestartS = 0.100;
/** ... and for the tile-health supervisor's self-test rounds, slower. */
constexpr double kRoundGapS = 1.0;
/** How long after a corrupted product its check reports it at most: one filter period. */
constexpr double kAbftSameJobS = 0.010;
/** A corrupted dot product or surface: the landmark's passes and recomputations (under 20 ms a unit). */
constexpr double kCorrelationSameLandmarkS = 0.020;
/** ... and a band of the coarse stage (the stage takes 40-100 ms). */
constexpr double kCorrelationCoarseStageS = 0.300;
/** A replica's corrupted output is voted on in its job: the vote waits for the last output. */
constexpr double kTmrSameVoteS = 0.030;
/** A damaged packet's resend comes within one retransmit timeout (16 round trips at most). */
constexpr double kDamagedResendS = 0.250;
/** A flipped packet is decoded at the receiver's next poll, milliseconds later even behind a full queue. */
constexpr double kPacketDecodeS = 0.100;

constexpr double kForever = std::numeric_limits<double>::infinity();

double seconds(bsp::Cycles c, double clock_hz) { return static_cast<double>(c) / clock_hz; }

/** Neighbour of @p t in direction @p dir on the grid (kNoTile off the grid). */
bsp::TileId neighbour_of(bsp::TileId t, std::uint64_t dir) {
  // The grid of the chip the image was configured for (the join runs after the flight).
  const trn::tasks::Deployment& dep = *trn::tasks::image_config().deployment;
  const std::uint32_t cols = dep.cols;
  const std::uint32_t rows = dep.rows;
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

/** The other end of a link fault (kNoTile for any other kind). */
bsp::TileId far_end(const bsp::FaultRecord& r) {
  return r.spec.kind == FaultKind::kLinkFail ? neighbour_of(r.spec.tile, r.spec.param) : bsp::kNoTile;
}

/** Whether fault @p r is on tile @p t (a link: either end). */
bool on_tile(const bsp::FaultRecord& r, bsp::TileId t) { return r.spec.tile == t || far_end(r) == t; }

/** A fault that stays: a failed switch or link, a watchdog, a part that computes wrong from then on. */
bool permanent(const bsp::FaultRecord& r) {
  return r.spec.kind == FaultKind::kSwitchFail || r.spec.kind == FaultKind::kLinkFail ||
         r.spec.kind == FaultKind::kWatchdogFail || (r.spec.kind == FaultKind::kSdc && r.spec.shift != 0.0);
}

/** Whether @p e is the simplex filter's (or a replica's) check refusing its state or settings after fault @p r on its tile. */
bool filter_check_of(const bsp::FaultRecord& r, const fdir::Event& e, double clock_hz) {
  if (e.tile != r.spec.tile || e.cycle < r.applied_cycle) {
    return false;
  }
  if (e.id == trn::ev::kFilterSettingsBad) {
    // An upset in the settings' bytes only (the EKF carve's first bytes).
    return r.spec.kind == FaultKind::kSeu && r.carve != nullptr && std::strcmp(r.carve, trn::tasks::kEkfCarve) == 0 &&
           r.carve_offset < trn::tasks::kEkfSettingsBytes;
  }
  if (e.id == trn::ev::kFilterStateChanged) {
    return r.spec.kind == FaultKind::kSeu;  // between two jobs: only an upset of the RAM changes it
  }
  // A corrupted update (sdc) in the job it hit; an upset at any later job.
  return e.id == trn::ev::kFilterStateBad &&
         (r.spec.kind == FaultKind::kSeu || seconds(e.cycle - r.applied_cycle, clock_hz) <= kAbftSameJobS);
}

bool correlation_check_of(const bsp::FaultRecord& r, const fdir::Event& e, double clock_hz) {
  const bool point = r.spec.channel == trn::vision::kCorrelationDotChannel ||
                     r.spec.channel == trn::vision::kCorrelationSurfaceChannel;
  return point && e.tile == r.spec.tile &&
         seconds(e.cycle - r.applied_cycle, clock_hz) <=
             (e.subject == trn::kCoarseLandmark ? kCorrelationCoarseStageS : kCorrelationSameLandmarkS);
}

bool coarse_band_check_of(const bsp::FaultRecord& r, const fdir::Event& e, double clock_hz) {
  return r.spec.channel == trn::tasks::kCoarseBandChannel && e.subject == r.spec.tile &&
         seconds(e.cycle - r.applied_cycle, clock_hz) <= kCorrelationCoarseStageS;
}

/** Index in @p acc of the tile @p t (the claim slot), or acc.count if not named. */
std::uint32_t slot_of(const tools::Accusation& acc, bsp::TileId t) {
  for (std::uint32_t i = 0; i < acc.count; ++i) {
    if (acc.tiles[i] == t) {
      return i;
    }
  }
  return acc.count;
}

/**
 * Whether accusation @p acc of event @p e detects injection @p r: a class the kind allows, the
 * fault's tile (a link: both ends) within the kind's bound, and the tighter rule of the check that
 * wrote it. Sets @p slot to the claim it takes.
 */
bool credits(const bsp::FaultRecord& r, const fdir::Event& e, const tools::Accusation& acc, double clock_hz,
             std::uint32_t& slot) {
  if (e.cycle < r.applied_cycle || !class_detects(r.spec.kind, r.crashed, acc.diagnosis) ||
      seconds(e.cycle - r.applied_cycle, clock_hz) > detect_bound_s(r.spec.kind)) {
    return false;
  }
  const bsp::TileId t = r.spec.tile;
  const double after = seconds(e.cycle - r.applied_cycle, clock_hz);
  slot = 0U;
  switch (r.spec.kind) {
    case FaultKind::kPacketBitFlip:
      // The receiver (or a forwarder) decodes the packet from source t; a packet too damaged to name its
      // source is any flip's, but only then. A resend by t after a timeout: the loss noticed.
      if (e.id == EventId::kPacketCorrected || e.id == EventId::kPacketForwarded || e.id == EventId::kPacketDamaged) {
        return (e.subject == t || e.subject == fdir::kUnknown) && after <= kPacketDecodeS;
      }
      return e.id == EventId::kPacketResent && e.tile == t && e.cause == 1U;
    case FaultKind::kLinkFail:
      return acc.names(t) && acc.names(far_end(r));
    case FaultKind::kSeu:
    case FaultKind::kSdc:
      switch (event_code(e.id)) {
        case event_code(trn::ev::kFilterStateBad):
        case event_code(trn::ev::kFilterStateChanged):
        case event_code(trn::ev::kFilterSettingsBad): return filter_check_of(r, e, clock_hz);
        case event_code(trn::ev::kCorrelationCorrected):
        case event_code(trn::ev::kCorrelationFailed): return correlation_check_of(r, e, clock_hz);
        case event_code(EventId::kAbftCorrected):
        case event_code(EventId::kAbftFailed): return e.tile == t && after <= kAbftSameJobS;
        case event_code(trn::ev::kCoarseBandRedone): return coarse_band_check_of(r, e, clock_hz);
        case event_code(trn::ev::kTileSettingsBad):
          // An upset in the vision roles' settings only (their carves).
          return r.spec.kind == FaultKind::kSeu && e.tile == t && r.carve != nullptr &&
                 (std::strcmp(r.carve, trn::tasks::kCoordSettingsCarve) == 0 ||
                  std::strcmp(r.carve, trn::tasks::kWorkerSettingsCarve) == 0 ||
                  std::strcmp(r.carve, trn::tasks::kFilterTaskCarve) == 0 ||
                  std::strcmp(r.carve, trn::tasks::kSupSettingsCarve) == 0);
        case event_code(trn::ev::kTmrNoMajority):
          slot = slot_of(acc, t);
          return slot < acc.count && after <= kTmrSameVoteS;
        default: return acc.names(t);
      }
    default:
      return acc.names(t);
  }
}

/** Whether @p acc names the tile(s) of @p r the way its kind is named (a link: both ends). */
bool names_fault(const tools::Accusation& acc, const bsp::FaultRecord& r) {
  return r.spec.kind == FaultKind::kLinkFail ? acc.names(r.spec.tile) && acc.names(far_end(r))
                                             : acc.names(r.spec.tile);
}

/** The tile an action acts on, for the actions that disturb a tile (kNoTile for any other event). */
bsp::TileId acted_on(const fdir::Event& e) {
  switch (event_code(e.id)) {
    case event_code(EventId::kTileReset):
    case event_code(EventId::kTileLost):
    case event_code(trn::ev::kTmrExcluded):
    case event_code(trn::ev::kTmrOutvoted):
    case event_code(EventId::kSelfTestMismatch):
    case event_code(EventId::kResultsSuspect):
    case event_code(EventId::kSwitchFailed):
    case event_code(EventId::kTransitFailed):
    case event_code(EventId::kLinkOrSwitchFailed): return e.subject < bsp::kMaxTiles ? e.subject : bsp::kNoTile;
    case event_code(EventId::kRoleMoved): return e.cause < bsp::kMaxTiles ? e.cause : bsp::kNoTile;
    default: return bsp::kNoTile;
  }
}

/** The context of one join: events in time order and the records. */
struct Join {
  std::span<const bsp::FaultRecord> records;
  std::span<const fdir::Event> events;
  std::vector<std::size_t> order;  ///< event indices in time order
  std::vector<double> t_s;         ///< per event
  double clock_hz;
  const ServiceStreams& streams;

  [[nodiscard]] double applied_s(const bsp::FaultRecord& r) const { return seconds(r.applied_cycle, clock_hz); }

  /** Until when fault @p r leaves its tile faulty (a hung core: until its reset, retirement or reboot). */
  [[nodiscard]] double active_until(const bsp::FaultRecord& r) const {
    if (permanent(r)) {
      return kForever;
    }
    const double from = applied_s(r);
    if (r.spec.kind == FaultKind::kCoreHang) {
      for (const std::size_t k : order) {
        const fdir::Event& e = events[k];
        if (t_s[k] < from) {
          continue;
        }
        const bool reset = (e.id == EventId::kTileReset || e.id == EventId::kTileLost ||
                            e.id == EventId::kTileRebooted) && e.subject == r.spec.tile;
        if (reset || (e.id == EventId::kRoleMoved && e.cause == r.spec.tile)) {
          return t_s[k] + kRecoverWindowS;
        }
      }
      return kForever;
    }
    return from + detect_bound_s(r.spec.kind) + kRecoverWindowS;
  }

  /** The role tile @p t held at @p at_s: its boot role, moved by every role_moved (and supervisor move) before. */
  [[nodiscard]] Role role_at(bsp::TileId t, double at_s) const {
    std::array<Role, trn::tasks::kMapTiles> roles = trn::tasks::tile_roles(*trn::tasks::image_config().deployment);
    for (const std::size_t k : order) {
      if (t_s[k] > at_s) {
        break;
      }
      const fdir::Event& e = events[k];
      if (e.id == EventId::kRoleMoved && e.cause < roles.size() && e.a < roles.size()) {
        roles[e.a] = roles[e.cause];
        roles[e.cause] = Role::kSpare;
      } else if (e.id == EventId::kSupervisorTookOver && e.subject < roles.size() && e.cause < roles.size()) {
        roles[e.subject] = roles[e.cause];  // the standby runs the supervisor's role now
        roles[e.cause] = Role::kSpare;
      }
    }
    return t < roles.size() ? roles[t] : Role::kSpare;
  }

  /** Whether the filter ran as a TMR at @p at_s (started or established, not given up since). */
  [[nodiscard]] bool tmr_active_at(double at_s) const {
    bool active = false;
    for (const std::size_t k : order) {
      if (t_s[k] > at_s) {
        break;
      }
      const EventId id = events[k].id;
      if (id == trn::ev::kTmrStarting || id == trn::ev::kTmrEstablished || id == trn::ev::kTmrVoterResumed) {
        active = true;
      } else if (id == trn::ev::kTmrSimplex) {
        active = false;
      }
    }
    return active;
  }

  /** First event index in time order at or after @p from_s (within the window) for which @p pred holds. */
  template <typename Pred>
  [[nodiscard]] std::size_t first_after(double from_s, double until_s, Pred pred) const {
    for (const std::size_t k : order) {
      if (t_s[k] < from_s) {
        continue;
      }
      if (t_s[k] > until_s) {
        break;
      }
      if (pred(events[k])) {
        return k;
      }
    }
    return events.size();
  }
};

/**
 * The first time after @p from_s at which stream @p s flows again steadily (kSteadyS without a gap
 * over kSteadyGapS, or to its end), within @p until_s; and the longest gap of the stream from its last
 * output at or before @p fault_s to then. @return false if it does not come back.
 */
bool stream_back(std::span<const double> s, double fault_s, double from_s, double until_s, double& back_s,
                 double& gap_s, double steady_gap_s = kSteadyGapS) {
  const auto first = std::upper_bound(s.begin(), s.end(), from_s);
  for (auto it = first; it != s.end() && *it <= until_s; ++it) {
    bool steady = true;
    for (auto j = it; j + 1 != s.end() && *j < *it + kSteadyS; ++j) {
      if (*(j + 1) - *j > steady_gap_s) {
        steady = false;
        break;
      }
    }
    if (!steady) {
      continue;
    }
    back_s = *it;
    auto before = std::upper_bound(s.begin(), s.end(), fault_s);
    double prev = before == s.begin() ? 0.0 : *(before - 1);
    gap_s = 0.0;
    for (auto j = before; j != s.end() && *j <= back_s; ++j) {
      gap_s = std::max(gap_s, *j - prev);
      prev = *j;
    }
    return true;
  }
  return false;
}

/**
 * The detection's event does the recovery itself: the data corrected or computed again in place, or (a
 * broken seal) the changed copy made again from the computed value, or dropped before anything used it.
 */
bool corrects_in_place(const fdir::Event& d) {
  return d.id == EventId::kPacketCorrected || d.id == EventId::kPacketForwarded || d.id == EventId::kPacketResent ||
         d.id == EventId::kAbftCorrected || d.id == trn::ev::kCorrelationCorrected ||
         d.id == trn::ev::kCoarseBandRedone || d.id == trn::ev::kResultSealBroken;
}

/** A flight report that tile @p t runs its role again (the roles without an output stream the host measures). */
bool runs_again(const fdir::Event& e, bsp::TileId t) {
  return ((e.id == EventId::kTileRecovered || e.id == EventId::kSelfTestAgree ||
           e.id == EventId::kResultsConsistent) && e.subject == t) ||
         (e.id == EventId::kRoleRestored && e.cause == t) ||
         (e.id == EventId::kTileRebooted && e.subject == t &&
          e.cause == static_cast<std::uint32_t>(bsp::BootCause::kCommand));
}

/** Sets the outcome's recovery to event @p k of the join. */
void recovered_at(const Join& j, std::size_t k, Recovery how, FaultOutcome& o) {
  o.recovery = how;
  o.recovered_s = j.t_s[k];
  o.recovered_by = tools::event_info(j.events[k].id)->name;
}

/**
 * A replica of a TMR running when the fault took effect: back when it votes with three again (the
 * replica seeded or agreeing again, any replica seeded with three voting: the one that took its role
 * on a spare, TMR established); the filter simplex again gives TMR up. A replica cleared (a self-test
 * that agrees again) that no vote missed or outvoted since the fault kept voting: never stopped.
 */
void replica_votes_again(const Join& j, bsp::TileId t, double det_s, double from, double until, FaultOutcome& o) {
  if (from > det_s && j.first_after(o.injected_s, from, [&](const fdir::Event& e) {
        return (e.id == trn::ev::kTmrOutvoted || e.id == trn::ev::kTmrExcluded) && e.subject == t;
      }) == j.events.size()) {
    const std::size_t c = j.first_after(from, from, [&](const fdir::Event& e) { return runs_again(e, t); });
    if (c < j.events.size()) {
      recovered_at(j, c, Recovery::kRecovered, o);
      o.service_gap_s = 0.0;
      return;
    }
  }
  // A fall-back to one filter (no majority) is on the way back: TMR established again after it is the
  // recovery; without it, the fall-back is the mode given up.
  const auto fell_back = [](const fdir::Event& e) {
    return e.id == trn::ev::kTmrSimplex && e.cause == trn::ev::kTmrSimplexNoMajority;
  };
  std::size_t k = j.first_after(from, until, [&](const fdir::Event& e) {
    return ((e.id == trn::ev::kTmrResynced || e.id == trn::ev::kTmrAgrees) && e.subject == t) ||
           (e.id == trn::ev::kTmrResynced && e.b >= 3U) || e.id == trn::ev::kTmrEstablished ||
           (e.id == trn::ev::kTmrSimplex && !fell_back(e));
  });
  if (k == j.events.size()) {
    k = j.first_after(from, until, fell_back);
  }
  if (k < j.events.size()) {
    recovered_at(j, k, j.events[k].id == trn::ev::kTmrSimplex ? Recovery::kDegradedAccepted : Recovery::kRecovered, o);
  }
}

/** Recovery of detected fault @p r (detected by event @p det): fills the outcome's recovery fields. */
/**
 * The fault map version that routes around the tile a switch or link detection @p d names: the
 * detection's own (its field b), or, when the supervisor's watcher named the switch (it publishes
 * no map), that of the standby's declaration of tile @p t; none (all ones) without one.
 */
std::uint32_t routing_version(const Join& j, const fdir::Event& d, bsp::TileId t, double det_s, double until) {
  if (d.id != EventId::kSupervisorMoved) {
    return d.b;
  }
  const std::size_t k = j.first_after(det_s, until, [&](const fdir::Event& e) {
    return (e.id == EventId::kSwitchFailed || e.id == EventId::kTransitFailed) && e.subject == t;
  });
  return k == j.events.size() ? 0xFFFF'FFFFU : j.events[k].b;
}

void recover(const Join& j, const bsp::FaultRecord& r, std::size_t det, FaultOutcome& o) {
  const fdir::Event& d = j.events[det];
  const bsp::TileId t = r.spec.tile;
  const double det_s = j.t_s[det];
  if (corrects_in_place(d)) {
    o.recovery = Recovery::kRecovered;
    o.recovered_s = det_s;
    o.service_gap_s = 0.0;
    o.recovered_by = tools::event_info(d.id)->name;
    return;
  }
  const double until = det_s + kRecoverWindowS;
  const auto found = [&](std::size_t k, Recovery how) { recovered_at(j, k, how, o); };
  if (d.id == EventId::kPacketDamaged) {
    // Its resend: by the named source to the tile that dropped it, or, the source unknown, by or to
    // the flipped tile, within one retransmit timeout. A probe or an ACK a later one covers is resent
    // by nobody: detected, not recovered.
    const std::size_t k = j.first_after(det_s, det_s + kDamagedResendS, [&](const fdir::Event& e) {
      if (e.id != EventId::kPacketResent) {
        return false;
      }
      return d.subject != fdir::kUnknown ? e.tile == d.subject && e.subject == d.tile : e.tile == t || e.subject == t;
    });
    if (k < j.events.size()) {
      found(k, Recovery::kRecovered);
      o.service_gap_s = -1.0;
    }
    return;
  }
  // When the service can be back: the network isolated (the map that routes around it is out), a
  // tile found computing wrong cleared (agrees again, consistent again, its role on a spare), else
  // at once.
  // Roles whose outputs the host does not measure: the supervisors, the spares, and a replica while
  // the filter is simplex (it stands by, voting nothing).
  const bool no_stream = o.role == Role::kSpare || o.role == Role::kFilterSupervisor ||
                         o.role == Role::kVisionSupervisor ||
                         (o.role == Role::kFilterReplica && !j.tmr_active_at(o.injected_s));
  double from = det_s;
  const fdir::Diagnosis cls = tools::accusation_of(d).diagnosis;
  if (cls == Diagnosis::kSwitch || cls == Diagnosis::kLink || cls == Diagnosis::kSwitchOrLink) {
    const std::uint32_t version = routing_version(j, d, t, det_s, until);
    const std::size_t k =
        j.first_after(det_s, until, [&](const fdir::Event& e) { return e.id == EventId::kMapPublished && e.subject >= version; });
    if (k == j.events.size()) {
      return;
    }
    from = j.t_s[k];
    if (no_stream) {
      found(k, Recovery::kRecovered);  // no output stream: routes around it are the service
      return;
    }
  } else if (d.id == EventId::kSelfTestMismatch || d.id == EventId::kResultsSuspect) {
    const std::size_t k = j.first_after(det_s, until, [&](const fdir::Event& e) { return runs_again(e, t); });
    if (k == j.events.size()) {
      return;
    }
    from = j.t_s[k];
    if (no_stream) {
      found(k, Recovery::kRecovered);
      return;
    }
  }
  double back = 0.0;
  double gap = 0.0;
  switch (o.role) {
    case Role::kFilter:
      if (stream_back(j.streams.filter_outputs_s, o.injected_s, from, until, back, gap)) {
        o.recovery = Recovery::kRecovered;
        o.recovered_s = back;
        o.service_gap_s = gap;
        o.recovered_by = "filter_outputs";
      }
      return;
    case Role::kIo:
      if (stream_back(j.streams.io_samples_s, o.injected_s, from, until, back, gap)) {
        o.recovery = Recovery::kRecovered;
        o.recovered_s = back;
        o.service_gap_s = gap;
        o.recovered_by = "io_samples";
      }
      return;
    case Role::kTrnSupervisor:
      // The tile-health supervisor runs there: its self-test rounds (one every few hundred ms).
      if (stream_back(j.streams.health_rounds_s, o.injected_s, from, until, back, gap, kRoundGapS)) {
        o.recovery = Recovery::kRecovered;
        o.recovered_s = back;
        o.service_gap_s = gap;
        o.recovered_by = "health_rounds";
      }
      return;
    case Role::kVisionCoordinator:
    case Role::kVision: {
      // The coordinator's next frame; for a vision tile, one with no unit lost.
      const bool coordinator = o.role == Role::kVisionCoordinator;
      const std::size_t k = j.first_after(from, until, [&](const fdir::Event& e) {
        return e.id == trn::ev::kFrameDone && (coordinator || e.cause == 0U);
      });
      if (k < j.events.size()) {
        found(k, Recovery::kRecovered);
      }
      return;
    }
    case Role::kFilterReplica:
      if (no_stream) {
        break;  // standing by: the flight's word that it runs again (below)
      }
      replica_votes_again(j, t, det_s, from, until, o);
      return;
    case Role::kFilterSupervisor:
    case Role::kVisionSupervisor: {
      if (d.id == trn::ev::kTileSettingsBad) {
        // Its settings built again before the pass that uses them: the node runs on, in place.
        o.recovery = Recovery::kRecovered;
        o.recovered_s = det_s;
        o.service_gap_s = 0.0;
        o.recovered_by = tools::event_info(d.id)->name;
        return;
      }
      // No stream the host measures: its node's own word that it runs (a policy taken, applied or
      // met, written by its tile), or the flight's word that the tile runs its role again.
      const std::size_t k = j.first_after(det_s, until, [&](const fdir::Event& e) {
        return ((e.id == EventId::kSupPolicy || e.id == EventId::kSupApply || e.id == EventId::kSupMet) && e.tile == t) ||
               runs_again(e, t);
      });
      if (k < j.events.size()) {
        found(k, Recovery::kRecovered);
      }
      return;
    }
    default:
      break;
  }
  // The flight's word that the tile runs its role again (its role restored on a spare included).
  const std::size_t k = j.first_after(det_s, until, [&](const fdir::Event& e) { return runs_again(e, t); });
  if (k < j.events.size()) {
    found(k, Recovery::kRecovered);
    return;
  }
  if (o.role == Role::kFilterReplica) {
    // A replica standing by is called on when the filter next goes TMR: three voting then, however
    // late, is its service back (no gap: nothing was asked of it before).
    const std::size_t est = j.first_after(det_s, kForever, [&](const fdir::Event& e) {
      return e.id == trn::ev::kTmrEstablished || (e.id == trn::ev::kTmrResynced && e.b >= 3U);
    });
    if (est < j.events.size()) {
      found(est, Recovery::kRecovered);
    }
  }
}

/**
 * Every accusation no injection took as its detection: explained (a fault still active on a tile it
 * names, with a class its kind allows), charged to a fault as a wrong diagnosis (the wrong class for
 * a fault active on a tile it names; else the wrong tile within the bound of the latest fault before
 * it), or a false alarm.
 */
void charge_accusations(const Join& j, const std::vector<tools::Accusation>& accusations,
                        const std::vector<std::uint8_t>& claimed, const std::vector<std::size_t>& inj,
                        const std::vector<double>& until, FaultAccount& acc) {
  const std::span<const bsp::FaultRecord> records = j.records;
  const std::span<const fdir::Event> events = j.events;
  for (const std::size_t k : j.order) {
    const tools::Accusation& a = accusations[k];
    if (!tools::is_diagnosis(a.diagnosis) || a.count == 0U) {
      continue;
    }
    const fdir::Event& e = events[k];
    // A link's accusation names its two ends: one accusation. A vote without a majority: one per replica.
    const std::uint32_t parts = e.id == trn::ev::kTmrNoMajority ? a.count : 1U;
    for (std::uint32_t p = 0; p < parts; ++p) {
      if ((claimed[k] & (1U << p)) != 0U) {
        continue;
      }
      tools::Accusation one = a;
      if (parts > 1U) {
        one.tiles = {a.tiles[p], bsp::kNoTile, bsp::kNoTile};
        one.count = 1U;
      }
      // A silence the tile asked for itself (assert_failed stops its watchdog's kicks) is its own
      // request for a restart, not a diagnosis.
      if (a.diagnosis == Diagnosis::kCoreSilent &&
          j.first_after(j.t_s[k] - kRequestedRestartS, j.t_s[k], [&](const fdir::Event& x) {
            return x.id == EventId::kAssertFailed && one.names(x.tile);
          }) < events.size()) {
        continue;
      }
      bool explained = false;
      std::size_t same_tile = records.size();  // an active fault of a tile it names: the wrong class
      std::size_t charge = records.size();     // the latest fault within its bound: the wrong tile
      for (const std::size_t i : inj) {
        const bsp::FaultRecord& r = records[i];
        if (r.applied_cycle > e.cycle) {
          break;
        }
        const double age = j.t_s[k] - j.applied_s(r);
        const bool active = j.t_s[k] <= until[i];
        if (active && names_fault(one, r) && class_detects(r.spec.kind, r.crashed, a.diagnosis)) {
          explained = true;
          break;
        }
        bool on = false;
        for (std::uint32_t n = 0; n < one.count; ++n) {
          on = on || on_tile(r, one.tiles[n]);
        }
        if (active && on) {
          same_tile = i;
        }
        if (age <= detect_bound_s(r.spec.kind) ||
            (r.spec.kind == FaultKind::kWatchdogFail && age <= detect_bound_s(FaultKind::kCoreHang))) {
          charge = i;  // the latest one wins
        }
      }
      charge = same_tile < records.size() ? same_tile : charge;
      if (explained) {
        continue;
      }
      if (charge < records.size()) {
        FaultOutcome& o = acc.outcomes[charge];
        if (o.wrong_accusations == 0U) {
          o.first_wrong = e.id;
          o.first_wrong_tile = one.tiles[0];
        }
        ++o.wrong_accusations;
        o.diagnosis = o.detected ? DiagnosisVerdict::kRightAndWrong : DiagnosisVerdict::kWrong;
      } else {
        acc.false_alarms.push_back({k, one.tiles[0]});
      }
    }
  }
}

/** Every action on a tile no active fault was on. */
void count_disturbed(const Join& j, const std::vector<std::size_t>& inj, const std::vector<double>& until,
                     FaultAccount& acc) {
  const std::span<const bsp::FaultRecord> records = j.records;
  const std::span<const fdir::Event> events = j.events;
  for (const std::size_t k : j.order) {
    const bsp::TileId t = acted_on(events[k]);
    if (t == bsp::kNoTile) {
      continue;
    }
    bool faulty = false;
    for (const std::size_t i : inj) {
      const bsp::FaultRecord& r = records[i];
      if (r.applied_cycle <= events[k].cycle && on_tile(r, t) && j.t_s[k] <= until[i]) {
        faulty = true;
        break;
      }
    }
    if (!faulty) {
      acc.healthy_disturbed.push_back({k, t});
    }
  }
}

}  // namespace

double detect_bound_s(FaultKind kind) noexcept {
  for (const DetectBound& b : kDetectBounds) {
    if (b.kind == kind) {
      return b.seconds;
    }
  }
  return 0.0;
}

bool class_detects(FaultKind kind, bool crashed, Diagnosis d) noexcept {
  switch (kind) {
    case FaultKind::kCoreHang: return d == Diagnosis::kCoreSilent;
    case FaultKind::kCoreReset: return d == Diagnosis::kCoreSilent || d == Diagnosis::kCoreCrashed;
    case FaultKind::kSeu:
      return crashed ? d == Diagnosis::kCoreSilent || d == Diagnosis::kCoreCrashed
                     : d == Diagnosis::kWrongResult || d == Diagnosis::kMemoryUpset;
    case FaultKind::kSdc: return d == Diagnosis::kWrongResult;
    case FaultKind::kPacketBitFlip: return d == Diagnosis::kPacket;
    case FaultKind::kSwitchFail: return d == Diagnosis::kSwitch || d == Diagnosis::kSwitchOrLink;
    case FaultKind::kLinkFail: return d == Diagnosis::kLink || d == Diagnosis::kSwitchOrLink;
    case FaultKind::kWatchdogFail:
    case FaultKind::kCount: break;
  }
  return false;
}

const char* effect_name(Effect e) noexcept {
  switch (e) {
    case Effect::kNotDelivered: return "not_delivered";
    case Effect::kDetected: return "detected";
    case Effect::kNotDetected: return "not_detected";
    case Effect::kNoEffect: return "no_effect";
  }
  return "?";
}

const char* verdict_name(DiagnosisVerdict v) noexcept {
  switch (v) {
    case DiagnosisVerdict::kNone: return "none";
    case DiagnosisVerdict::kRight: return "right";
    case DiagnosisVerdict::kWrong: return "wrong";
    case DiagnosisVerdict::kRightAndWrong: return "right_and_wrong";
  }
  return "?";
}

const char* recovery_name(Recovery r) noexcept {
  switch (r) {
    case Recovery::kNone: return "none";
    case Recovery::kRecovered: return "recovered";
    case Recovery::kDegradedAccepted: return "degraded_accepted";
  }
  return "?";
}

FaultAccount join_faults(std::span<const bsp::FaultRecord> records, std::span<const fdir::Event> events,
                         double clock_hz, const ServiceStreams& streams) {
  FaultAccount acc;
  acc.outcomes.resize(records.size());
  Join j{records, events, {}, {}, clock_hz, streams};
  j.order.resize(events.size());
  j.t_s.resize(events.size());
  for (std::size_t i = 0; i < events.size(); ++i) {
    j.order[i] = i;
    j.t_s[i] = seconds(events[i].cycle, clock_hz);
  }
  std::stable_sort(j.order.begin(), j.order.end(), [&](std::size_t a, std::size_t b) {
    return events[a].cycle < events[b].cycle || (events[a].cycle == events[b].cycle && events[a].tile < events[b].tile);
  });
  std::vector<tools::Accusation> accusations(events.size());
  for (std::size_t k = 0; k < events.size(); ++k) {
    accusations[k] = tools::accusation_of(events[k]);
  }
  std::vector<std::uint8_t> claimed(events.size(), 0U);  // bit per claim slot (a tile named; slot 0 otherwise)
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
  // Detections: each injection, in the order they took effect, takes the earliest accusation that credits it.
  double latency_sum = 0.0;
  for (const std::size_t i : inj) {
    const bsp::FaultRecord& r = records[i];
    FaultOutcome& o = acc.outcomes[i];
    o.delivered = true;
    o.effect = Effect::kNotDetected;
    o.injected_s = j.applied_s(r);
    o.role = j.role_at(r.spec.tile, o.injected_s);
    ++acc.injected;
    std::size_t det = events.size();
    for (const std::size_t k : j.order) {
      if (events[k].cycle < r.applied_cycle) {
        continue;
      }
      if (j.t_s[k] - o.injected_s > detect_bound_s(r.spec.kind)) {
        break;
      }
      std::uint32_t slot = 0U;
      if (credits(r, events[k], accusations[k], clock_hz, slot) && (claimed[k] & (1U << slot)) == 0U) {
        claimed[k] = static_cast<std::uint8_t>(claimed[k] | (1U << slot));
        det = k;
        break;
      }
    }
    if (det == events.size()) {
      continue;
    }
    const fdir::Event& d = events[det];
    o.detected = true;
    o.effect = Effect::kDetected;
    o.diagnosis = DiagnosisVerdict::kRight;
    o.detected_s = j.t_s[det];
    o.detected_by = d.id;
    o.detector = d.tile;
    ++acc.detected;
    latency_sum += o.detected_s - o.injected_s;
    acc.max_detection_latency_s = std::max(acc.max_detection_latency_s, o.detected_s - o.injected_s);
    recover(j, r, det, o);
    o.recovered = o.recovery == Recovery::kRecovered;
    acc.recovered += o.recovered ? 1U : 0U;
    acc.degraded_accepted += o.recovery == Recovery::kDegradedAccepted ? 1U : 0U;
  }
  acc.mean_detection_latency_s = acc.detected > 0U ? latency_sum / static_cast<double>(acc.detected) : 0.0;

  std::vector<double> until(records.size(), 0.0);
  for (const std::size_t i : inj) {
    until[i] = j.active_until(records[i]);
  }
  charge_accusations(j, accusations, claimed, inj, until, acc);
  for (const std::size_t i : inj) {
    acc.misdiagnosed += acc.outcomes[i].wrong_accusations > 0U ? 1U : 0U;
  }

  count_disturbed(j, inj, until, acc);
  return acc;
}

void mark_no_effect(FaultAccount& account) {
  for (FaultOutcome& o : account.outcomes) {
    if (o.delivered && !o.detected && o.wrong_accusations == 0U) {
      o.effect = Effect::kNoEffect;
    }
  }
}

void log_fault_outcomes(std::span<const bsp::FaultRecord> records, std::span<const fdir::Event> events,
                        const FaultAccount& account, double clock_hz, EventLog& log) {
  for (std::size_t i = 0; i < records.size() && i < account.outcomes.size(); ++i) {
    const bsp::FaultRecord& r = records[i];
    const FaultOutcome& o = account.outcomes[i];
    const double t_s = o.delivered ? o.injected_s : seconds(r.spec.cycle, clock_hz);
    std::string text = describe_fault(r);
    std::array<char, 240> b{};
    if (!o.delivered) {
      (void)std::snprintf(b.data(), b.size(), " -> not delivered");
    } else if (!o.detected) {
      (void)std::snprintf(b.data(), b.size(), " -> not detected by the flight software%s",
                          o.effect == Effect::kNoEffect ? " (no effect)" : "");
    } else {
      const int n = std::snprintf(b.data(), b.size(), " -> detected by tile %u (%s) %.1f ms later", o.detector,
                                  tools::event_info(o.detected_by)->name, (o.detected_s - o.injected_s) * 1e3);
      const std::size_t used = n > 0 ? std::min(static_cast<std::size_t>(n), b.size() - 1U) : 0U;
      if (o.recovery == Recovery::kNone) {
        (void)std::snprintf(b.data() + used, b.size() - used, ", not recovered");
      } else {
        const int m = std::snprintf(b.data() + used, b.size() - used, ", %s %.1f ms after detection (%s)",
                                    o.recovery == Recovery::kRecovered ? "recovered" : "degraded (accepted)",
                                    (o.recovered_s - o.detected_s) * 1e3, o.recovered_by);
        const std::size_t more = m > 0 ? std::min(used + static_cast<std::size_t>(m), b.size() - 1U) : used;
        if (o.service_gap_s > 0.0) {
          (void)std::snprintf(b.data() + more, b.size() - more, ", gap %.0f ms", o.service_gap_s * 1e3);
        }
      }
    }
    text += b.data();
    if (o.wrong_accusations > 0U) {
      std::array<char, 80> w{};
      (void)std::snprintf(w.data(), w.size(), "; MISDIAGNOSED: %s of tile %u (%u)", tools::event_info(o.first_wrong)->name,
                          o.first_wrong_tile, o.wrong_accusations);
      text += w.data();
    }
    if (o.delivered) {
      text += " [";
      text += trn::tasks::role_name(o.role);
      text += "]";
    }
    (void)log.add(t_s, o.delivered ? EventCategory::kInject : EventCategory::kInfo, r.spec.tile, text);
  }
  for (const Unexplained& u : account.false_alarms) {
    const fdir::Event& e = events[u.event];
    const tools::Accusation a = tools::accusation_of(e);
    std::array<char, 160> b{};
    (void)std::snprintf(b.data(), b.size(), "FALSE ALARM: %s accuses tile %u (%s); no injected fault explains it",
                        tools::event_info(e.id)->name, u.tile, tools::diagnosis_name(a.diagnosis));
    (void)log.add(seconds(e.cycle, clock_hz), EventCategory::kInfo, e.tile, b.data());
  }
  for (const Unexplained& u : account.healthy_disturbed) {
    const fdir::Event& e = events[u.event];
    std::array<char, 160> b{};
    (void)std::snprintf(b.data(), b.size(), "HEALTHY TILE DISTURBED: %s acts on tile %u, which no fault had hit",
                        tools::event_info(e.id)->name, u.tile);
    (void)log.add(seconds(e.cycle, clock_hz), EventCategory::kInfo, e.tile, b.data());
  }
}

const char* upset_model_name(bsp::UpsetModel m) noexcept {
  switch (m) {
    case bsp::UpsetModel::kFlipped:
      return "flipped";
    case bsp::UpsetModel::kHostCrash:
      return "host_crash";
    case bsp::UpsetModel::kControlCrash:
      return "control_crash";
    case bsp::UpsetModel::kStackCrash:
      return "stack_crash";
    case bsp::UpsetModel::kNone:
      break;
  }
  return "";
}

std::string faults_csv(std::span<const bsp::FaultRecord> records, const FaultAccount& account) {
  std::ostringstream o;
  o << "t_s,kind,tile,role,delivered,carve,crashed,effect,accusing_event,accusing_tile,latency_ms,diagnosis,"
       "wrong_accusations,first_wrong_event,first_wrong_tile,recovery,recovery_by,recovery_ms,service_gap_ms,upset\n";
  const auto ms = [](double s) {
    std::array<char, 32> b{};
    (void)std::snprintf(b.data(), b.size(), "%.3f", s * 1e3);
    return std::string(b.data());
  };
  for (std::size_t i = 0; i < records.size() && i < account.outcomes.size(); ++i) {
    const bsp::FaultRecord& r = records[i];
    const FaultOutcome& f = account.outcomes[i];
    std::array<char, 32> t{};
    (void)std::snprintf(t.data(), t.size(), "%.6f", f.delivered ? f.injected_s : 0.0);
    o << (f.delivered ? t.data() : "") << ',' << fault_kind_name(r.spec.kind) << ',' << r.spec.tile << ','
      << (f.delivered ? trn::tasks::role_name(f.role) : "") << ',' << (f.delivered ? 1 : 0) << ','
      << (r.carve != nullptr ? r.carve : "") << ',' << (r.crashed ? 1 : 0) << ',' << effect_name(f.effect) << ',';
    if (f.detected) {
      o << tools::event_info(f.detected_by)->name << ',' << f.detector << ',' << ms(f.detected_s - f.injected_s);
    } else {
      o << ",,";
    }
    o << ',' << verdict_name(f.diagnosis) << ',' << f.wrong_accusations << ',';
    if (f.wrong_accusations > 0U) {
      o << tools::event_info(f.first_wrong)->name << ',' << f.first_wrong_tile;
    } else {
      o << ',';
    }
    o << ',' << recovery_name(f.recovery) << ',' << f.recovered_by << ',';
    o << (f.recovery != Recovery::kNone ? ms(f.recovered_s - f.detected_s) : std::string{}) << ',';
    o << (f.service_gap_s >= 0.0 ? ms(f.service_gap_s) : std::string{}) << ',' << upset_model_name(r.upset) << '\n';
  }
  return o.str();
}

}  // namespace tools
