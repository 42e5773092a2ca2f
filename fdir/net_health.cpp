/**
 * @file net_health.cpp
 * @brief Suspect voting (switches and links) and fault-map publication on the health tile.
 */
#include "fdir/net_health.hpp"

#include "fdir/tile_health.hpp"

#include "bsp_tile64/api/memory.hpp"
#include "fdir/assert.hpp"
#include "fdir/event_log.hpp"
#include "kernel/kernel.hpp"
#include "udn/endpoint.hpp"

#include <bit>
#include <new>

namespace fdir {
namespace detail {
namespace {

bool has(std::uint64_t mask, bsp::TileId t) noexcept { return t < 64U && ((mask >> t) & 1ULL) != 0ULL; }

/** Direction of the link from @p a to its mesh neighbour @p b, or false if they are not neighbours. */
bool link_dir(const udn::FaultMap& map, bsp::TileId a, bsp::TileId b, bsp::UdnDir& dir) noexcept {
  const std::uint32_t cols = map.cols;
  if (cols == 0U || a >= map.cols * map.rows || b >= map.cols * map.rows) {
    return false;
  }
  if (b == a + 1U && a / cols == b / cols) {
    dir = bsp::UdnDir::kEast;
  } else if (a == b + 1U && a / cols == b / cols) {
    dir = bsp::UdnDir::kWest;
  } else if (b + cols == a) {
    dir = bsp::UdnDir::kNorth;
  } else if (a + cols == b) {
    dir = bsp::UdnDir::kSouth;
  } else {
    return false;
  }
  return true;
}

}  // namespace

Verdict take_report(Votes& v, udn::FaultMap& map, bsp::TileId reporter, bsp::TileId suspect,
                    std::uint32_t& votes_out) noexcept {
  votes_out = 0U;
  if (reporter >= udn::kRouteMaxTiles || suspect >= udn::kRouteMaxTiles || reporter == suspect ||
      has(v.not_voted, suspect) || has(v.failed, suspect) || has(v.failed, reporter)) {
    return Verdict::kIgnored;  // off on purpose (it answers no ping), already failed, or nonsense
  }
  std::uint64_t& who = v.reporters[suspect];
  const bool again = (who & (1ULL << reporter)) != 0ULL;
  who |= 1ULL << reporter;
  votes_out = static_cast<std::uint32_t>(std::popcount(who));
  if (again && votes_out < v.votes_to_fail) {
    return Verdict::kIgnored;  // a suspicion sent again (udn/endpoint.cpp): nothing new
  }
  if (votes_out >= v.votes_to_fail) {
    if (udn::fault_map_fail_tile(map, suspect) != udn::RouteError::kOk) {
      return Verdict::kCounted;
    }
    v.failed |= 1ULL << suspect;
    return Verdict::kSwitchFailed;
  }
  // Both ends of one link report each other and nobody reports either: the link.
  const std::uint64_t back = v.reporters[reporter];
  bsp::UdnDir dir = bsp::UdnDir::kEast;
  if (votes_out == 1U && back == (1ULL << suspect) && link_dir(map, reporter, suspect, dir) &&
      udn::fault_map_fail_link(map, reporter, dir, true) == udn::RouteError::kOk) {
    v.reporters[suspect] &= ~(1ULL << reporter);  // a link's reports are no votes against either switch
    v.reporters[reporter] &= ~(1ULL << suspect);
    ++v.links;
    return Verdict::kLinkFailed;
  }
  return Verdict::kCounted;
}

}  // namespace detail

namespace {

/** Check id: the health tile could not apply its own decision (its endpoint is closed). */
constexpr std::uint32_t kAssertOwnMap = 0x0201U;
/** Check id: the task's copy of the fault map has a grid no map has (an upset of its state); taken again from the endpoint. */
constexpr std::uint32_t kAssertStateCorrupt = 0x0202U;

/** The health task's state, carved in its tile's RAM. */
struct State {
  detail::Votes votes;
  udn::FaultMap map;
  std::uint64_t lost;          ///< plan transits reported lost (bit per plan index)
  std::array<k::Ticks, kMaxTransits> lost_at;  ///< when each transit was last reported lost (0: never)
  std::uint64_t cfg_not_voted;  ///< the configuration's tiles off by design
  std::uint64_t parked;         ///< tiles the power policy switched off
  k::Ticks transit_change;     ///< when the last transit report arrived
  std::uint64_t core_told;     ///< tiles already reported kCoreSuspect
  ReportWays ways;             ///< how each prober's reports come here (for the link verdict)
  std::array<k::Ticks, udn::kRouteMaxTiles> suspected_at;  ///< first neighbour report of each tile (0: none)
  std::uint64_t targets;      ///< tiles a map goes to (neither off by design nor failed, not this one)
  std::uint64_t to_send;      ///< targets not yet sent the current version
  std::uint32_t sent_count;
  std::uint32_t published;    ///< latest version sent to every target
  k::Ticks started;           ///< when the task started (what it knows of the transits is relearnt after)
};

/**
 * What an upset of the health task's state does (bsp::ControlLayout): it is
 * all the tile's own state (votes, the map, bit sets, ticks), flipped for
 * real. The map's grid is checked before each round (kAssertStateCorrupt).
 */
constexpr std::array kStateFields{
    BSP_CONTROL_NESTED(State, votes, detail::kVotesLayout),
    BSP_CONTROL_NESTED(State, map, udn::kFaultMapLayout),
    BSP_CONTROL_STATE(State, lost),
    BSP_CONTROL_STATE(State, lost_at),
    BSP_CONTROL_STATE(State, cfg_not_voted),
    BSP_CONTROL_STATE(State, parked),
    BSP_CONTROL_STATE(State, transit_change),
    BSP_CONTROL_STATE(State, core_told),
    BSP_CONTROL_NESTED(State, ways, kReportWaysLayout),
    BSP_CONTROL_STATE(State, suspected_at),
    BSP_CONTROL_STATE(State, targets),
    BSP_CONTROL_STATE(State, to_send),
    BSP_CONTROL_STATE(State, sent_count),
    BSP_CONTROL_STATE(State, published),
    BSP_CONTROL_STATE(State, started),
};
constexpr bsp::ControlLayout kStateLayout{kStateFields, sizeof(State), alignof(State)};
static_assert(bsp::control_layout_ok(kStateLayout), "every member of the net-health State");

std::array<State*, bsp::kMaxTiles> g_state{};

std::uint64_t all_tiles(const udn::FaultMap& map) noexcept {
  const std::uint32_t n = map.cols * map.rows;
  return n >= 64U ? ~0ULL : ((1ULL << n) - 1ULL);
}

/** A new decision: apply it here and start sending it to every target. */
void decided(State& s, bsp::TileId self) noexcept {
  (void)check(udn::endpoint_install_map(s.map) == udn::FtError::kOk, kAssertOwnMap);
  s.targets = all_tiles(s.map) & ~s.votes.not_voted & ~s.votes.failed & ~(1ULL << self);
  s.to_send = s.targets;
  s.sent_count = 0U;
}

void take(State& s, bsp::TileId self, std::uint32_t reporter, std::uint32_t suspect) noexcept {
  std::uint32_t votes = 0U;
  const auto r = static_cast<bsp::TileId>(reporter);
  const auto x = static_cast<bsp::TileId>(suspect);
  const detail::Verdict v = detail::take_report(s.votes, s.map, r, x, votes);
  if (v == detail::Verdict::kIgnored) {
    return;
  }
  report(EventId::kSuspectVote, x, r, votes, s.votes.votes_to_fail);
  if (x < udn::kRouteMaxTiles && s.suspected_at[x] == 0U) {
    s.suspected_at[x] = k::now_ticks() == 0U ? 1U : k::now_ticks();
  }
  if (v == detail::Verdict::kSwitchFailed) {
    report(EventId::kSwitchFailed, x, r, votes, s.map.version);
    decided(s, self);
  } else if (v == detail::Verdict::kLinkFailed) {
    report(EventId::kLinkFailed, r, x, 0U, s.map.version);
    decided(s, self);
  }
}

/** A transit report: the plan's bit for (prober, target) set or cleared. */
void take_transit(State& s, const NetHealthConfig& cfg, const udn::TransitReport& t) noexcept {
  const std::uint32_t i = transit_index(cfg.transits, t.prober, t.target);
  if (i >= kMaxTransits) {
    return;  // not a planned transit: nothing to judge it against
  }
  const std::uint64_t bit = std::uint64_t{1} << i;
  if (((s.lost & bit) != 0U) == t.lost) {
    return;  // sent again while it still holds (udn/endpoint.cpp): the settle time and its loss time stay
  }
  s.lost = t.lost ? (s.lost | bit) : (s.lost & ~bit);
  s.transit_change = k::now_ticks();
  if (t.lost) {
    s.lost_at[i] = s.transit_change == 0U ? 1U : s.transit_change;
  }
}

/** Transits whose answer tells about their switches: nothing on the way known failed but @p except. */
std::uint64_t telling(const State& s, const NetHealthConfig& cfg, std::uint64_t except) noexcept {
  std::uint64_t m = 0U;
  for (std::uint32_t i = 0; i < cfg.transits.count && i < kMaxTransits; ++i) {
    m |= (cfg.transits.t[i].path & s.votes.failed & ~except) == 0U ? (std::uint64_t{1} << i) : 0U;
  }
  return m;
}

/**
 * Transits reported lost within the settle time of @p when (a tile's first
 * report): a failed switch loses the transits through it until the new map
 * routes them around it, after which they answer again (and those that had
 * not missed enough rounds yet never were lost). One such transit says the
 * switch failed: no answer through it is evidence of a silent core (a hung
 * core's switch never loses one).
 */
std::uint64_t lost_near(const State& s, const NetHealthConfig& cfg, k::Ticks when) noexcept {
  std::uint64_t m = 0U;
  for (std::uint32_t i = 0; i < cfg.transits.count && i < kMaxTransits; ++i) {
    const k::Ticks at = s.lost_at[i];
    const bool near = at != 0U && at + cfg.settle_ticks >= when && at <= when + cfg.settle_ticks;
    m |= near ? (std::uint64_t{1} << i) : 0U;
  }
  return m;
}

/**
 * No switch explains the lost transits: a link no neighbour vote can name (a
 * spare, or a tile that does not probe, at one end) may. @p mute: transits
 * that tell nothing (across a failed link, to or from a parked tile).
 * @return true on a decision.
 */
bool judge_link(State& s, const NetHealthConfig& cfg, bsp::TileId self, k::Ticks now, std::uint64_t mute) noexcept {
  if (s.ways.version != s.map.version || s.ways.parked != s.parked) {
    bsp::Work work{};
    report_ways(cfg.transits, s.map, self, s.parked, s.ways, work);
    bsp::consume(work);
  }
  // The probers that reported lost transits themselves (their core runs, their reports come), once
  // every loss is older than a hung core stays silent: an end they all share may be one of them.
  std::uint64_t heard = 0U;
  k::Ticks latest = 0U;
  for (std::uint32_t i = 0; i < cfg.transits.count && i < kMaxTransits; ++i) {
    const bool lost = ((s.lost >> i) & 1U) != 0U && ((mute >> i) & 1U) == 0U;
    const bsp::TileId p = cfg.transits.t[i].prober;
    heard |= lost && p < 64U ? (std::uint64_t{1} << p) : 0U;
    latest = lost && s.lost_at[i] > latest ? s.lost_at[i] : latest;
  }
  heard = now - latest >= cfg.end_tile_ticks ? heard & ~s.votes.failed : 0U;
  const LinkVerdict l =
      transit_link_verdict(cfg.transits, s.map.cols, s.map.rows, s.ways, s.lost, s.votes.failed, mute, heard);
  // A spare's switch at an end that nothing heard crosses but over the link may have failed instead:
  // from here the two look the same, and taking the switch out of the routes covers both (the
  // link alone would leave the cut-off tiles' traffic, and their reports, crossing a dead switch).
  const std::uint64_t unsure = l.unsure & s.votes.not_voted & ~s.votes.failed;
  const bsp::TileId spare = unsure == 0U ? bsp::kNoTile : static_cast<bsp::TileId>(std::countr_zero(unsure));
  if (spare != bsp::kNoTile && udn::fault_map_fail_tile(s.map, spare) == udn::RouteError::kOk) {
    s.votes.failed |= std::uint64_t{1} << spare;
    report(EventId::kLinkOrSwitchFailed, spare, spare == l.a ? l.b : l.a, l.transits, s.map.version);
    decided(s, self);
    return true;
  }
  // Every link named (a chain the transits cannot tell apart is taken out whole), one event each.
  bool any = false;
  for (std::uint32_t k = 0; k < 128U && l.count != 0U; ++k) {
    if ((l.links.w[k / 64U] >> (k % 64U) & 1U) == 0U) {
      continue;
    }
    const auto a = static_cast<bsp::TileId>(k / 2U);
    const bool east = (k % 2U) == 0U;
    const auto b = static_cast<bsp::TileId>(east ? a + 1U : a + s.map.cols);
    if (udn::fault_map_fail_link(s.map, a, east ? bsp::UdnDir::kEast : bsp::UdnDir::kSouth, true) ==
        udn::RouteError::kOk) {
      ++s.votes.links;
      report(EventId::kLinkFailed, a, b, l.transits, s.map.version);
      any = true;
    }
  }
  if (any) {
    decided(s, self);
  }
  return any;
}

/**
 * An end tile cut off (end_tile_verdict): every transit to or through it lost
 * for cfg.end_tile_ticks, longer than a hung core there would stay silent
 * (its watchdog, a reset and a boot). Its switch goes into the map like any
 * failed switch (transit_failed, cause 1), and the tile-health supervisor
 * retires the tile and moves its role. @return true on a decision.
 */
bool judge_end_tile(State& s, const NetHealthConfig& cfg, bsp::TileId self, k::Ticks now, std::uint64_t mute) noexcept {
  const std::uint64_t candidates = cfg.transits.untested & cfg.transit_subjects & ~(std::uint64_t{1} << self) & ~s.parked;
  std::uint64_t reported = 0U;
  static_assert(udn::kRouteMaxTiles <= 64U, "a tile mask holds every tile");
  for (bsp::TileId t = 0; t < udn::kRouteMaxTiles; ++t) {
    reported |= s.suspected_at[t] != 0U ? (std::uint64_t{1} << t) : 0U;
  }
  std::uint64_t lost_ones = 0U;
  const bsp::TileId x = end_tile_verdict(cfg.transits, s.lost, candidates, s.votes.failed, mute, reported, lost_ones);
  if (x == bsp::kNoTile) {
    return false;
  }
  k::Ticks latest = 0U;
  for (std::uint32_t i = 0; i < cfg.transits.count && i < kMaxTransits; ++i) {
    latest = ((lost_ones >> i) & 1U) != 0U && s.lost_at[i] > latest ? s.lost_at[i] : latest;
  }
  if (now - latest < cfg.end_tile_ticks || udn::fault_map_fail_tile(s.map, x) != udn::RouteError::kOk) {
    return false;
  }
  s.votes.failed |= std::uint64_t{1} << x;
  report(EventId::kTransitFailed, x, 1U, static_cast<std::uint32_t>(std::popcount(lost_ones)), s.map.version);
  decided(s, self);
  return true;
}

/** Judges the transits once the reports are quiet: a switch or a link failed, or a silent core behind a switch that routes. */
void judge_transits(State& s, const NetHealthConfig& cfg, bsp::TileId self) noexcept {
  const k::Ticks now = k::now_ticks();
  if (cfg.transits.count == 0U || now - s.transit_change < cfg.settle_ticks) {
    return;
  }
  // Transits to or from a parked tile were lost because it is off, not because of a switch.
  std::uint64_t off_ends = 0U;
  for (std::uint32_t i = 0; i < cfg.transits.count && i < kMaxTransits; ++i) {
    const Transit& x = cfg.transits.t[i];
    const bool off = (x.prober < 64U && ((s.parked >> x.prober) & 1ULL) != 0ULL) ||
                     (x.target < 64U && ((s.parked >> x.target) & 1ULL) != 0ULL);
    off_ends |= off ? (std::uint64_t{1} << i) : 0U;
  }
  s.lost &= ~off_ends;
  // A transit across a link the map says failed (voted by its two ends, or named by the transits)
  // tells nothing of a switch.
  const std::uint64_t mute = s.lost != 0U ? transits_across(cfg.transits, udn::failed_link_set(s.map)) : 0U;
  if (s.lost != 0U) {
    const bsp::TileId x = transit_verdict(cfg.transits, s.lost, cfg.transit_subjects, s.votes.failed, mute);
    if (x != bsp::kNoTile && udn::fault_map_fail_tile(s.map, x) == udn::RouteError::kOk) {
      s.votes.failed |= std::uint64_t{1} << x;
      const std::uint64_t through = transits_through(cfg.transits, x);
      report(EventId::kTransitFailed, x, 0U, static_cast<std::uint32_t>(std::popcount(through)), s.map.version);  // cause 0: through it
      decided(s, self);
      return;
    }
    if (judge_link(s, cfg, self, now, mute | off_ends)) {
      return;
    }
    if (judge_end_tile(s, cfg, self, now, mute | off_ends)) {
      return;
    }
  }
  // A reported tile, voted failed or not, whose switch still carries transits: its core is silent.
  // Not before the lost transits had time to be reported again since the task started.
  if (now - s.started < cfg.relearn_ticks) {
    return;
  }
  for (bsp::TileId t = 0; t < udn::kRouteMaxTiles; ++t) {
    const std::uint64_t bit = std::uint64_t{1} << t;
    if (s.suspected_at[t] == 0U || (s.core_told & bit) != 0U || now - s.suspected_at[t] < cfg.settle_ticks) {
      continue;
    }
    const std::uint64_t through = transits_through(cfg.transits, t);
    const std::uint64_t answering = through & telling(s, cfg, bit) & ~s.lost;
    // One transit through it lost when it was reported: its switch failed (the others were routed
    // around it before they missed enough rounds), not its core.
    if (answering != 0U && (through & lost_near(s, cfg, s.suspected_at[t])) == 0U) {
      s.core_told |= bit;
      report(EventId::kCoreSuspect, t, 0U, static_cast<std::uint32_t>(std::popcount(answering)));
      tile_health_core_suspect(t);  // a core its watchdog did not name: the tile-health supervisor acts
    }
  }
}

/** Sends the current map to the targets not sent yet, as far as the window allows this tick. */
void publish(State& s) noexcept {
  std::array<std::uint32_t, udn::kFaultMapWords> w{};
  udn::pack_fault_map(s.map, w);
  for (bsp::TileId t = 0; t < 64U && s.to_send != 0ULL; ++t) {
    if (((s.to_send >> t) & 1ULL) == 0ULL) {
      continue;
    }
    const udn::FtError e = udn::endpoint_send(t, udn::kFtChanMap, w, 0U);
    if (e == udn::FtError::kWindowFull || e == udn::FtError::kNetFull) {
      return;  // the rest next tick
    }
    s.to_send &= ~(1ULL << t);
    s.sent_count += (e == udn::FtError::kOk) ? 1U : 0U;  // no route: it catches up through the probes
  }
  s.published = s.map.version;
  report(EventId::kMapPublished, s.map.version, 0U, s.sent_count, static_cast<std::uint32_t>(std::popcount(s.targets)));
}

}  // namespace

void net_health_set_parked(std::uint64_t parked) noexcept {
  const bsp::TileId self = bsp::current_tile();
  State* s = self < bsp::kMaxTiles ? g_state[self] : nullptr;
  if (s == nullptr) {
    return;
  }
  s->parked = parked;
  s->votes.not_voted = s->cfg_not_voted | parked;
  s->targets &= ~parked;
  s->to_send &= ~parked;
}

namespace {

/**
 * A map newer than the task's own reached this tile's endpoint (from a
 * neighbour, after this tile restarted or took the supervisor's role over):
 * the task goes on from it, so its next decision gets a newer version than
 * every tile holds (a version they hold already would be ignored).
 */
void adopt_newer_map(State& s) noexcept {
  const udn::FaultMap held = udn::endpoint_fault_map();
  if (s.to_send != 0ULL || held.version <= s.map.version || !udn::fault_map_valid(held)) {
    return;
  }
  s.map = held;
  s.votes.failed |= held.failed_tiles;
  s.published = held.version;
}

/**
 * On a standby that took the supervisor's role over: the tile it replaced
 * was silent after its watcher's reset, to it and to the tiles beside it (its
 * switch, supervisor_moved). Its switch goes into the map at once: the probers
 * whose reports would cross it cannot tell this tile what they lose.
 */
void declare_replaced(State& s, bsp::TileId self) noexcept {
  const bsp::TileId x = tile_health_replaced();
  if (x == bsp::kNoTile || ((s.votes.failed >> x) & 1ULL) != 0ULL ||
      udn::fault_map_fail_tile(s.map, x) != udn::RouteError::kOk) {
    return;
  }
  s.votes.failed |= std::uint64_t{1} << x;
  report(EventId::kTransitFailed, x, 2U, 0U, s.map.version);  // cause 2: the tile the watcher moved the role from
  decided(s, self);
}

}  // namespace

void net_health_task_main(void* arg) noexcept {
  const auto* cfg = static_cast<const NetHealthConfig*>(arg);
  const bsp::TileId self = bsp::current_tile();
  if (cfg == nullptr || self >= bsp::kMaxTiles || cfg->votes_to_fail < 2U || !udn::endpoint_wait_ready(100)) {
    return;
  }
  g_state[self] = nullptr;
  bsp::MemError err = bsp::MemError::kOk;
  auto* s = bsp::carve_control_array<State>(bsp::Region{self}, 1, kNetHealthCarve, &err, &kStateLayout);
  if (err != bsp::MemError::kOk || s == nullptr) {
    return;
  }
  ::new (s) State{};
  s->votes.not_voted = cfg->not_voted;
  s->cfg_not_voted = cfg->not_voted;
  s->votes.votes_to_fail = cfg->votes_to_fail;
  s->map = udn::endpoint_fault_map();
  s->votes.failed = s->map.failed_tiles;
  s->published = s->map.version;
  s->started = k::now_ticks();
  g_state[self] = s;
  udn::FtMessage m{};
  for (;;) {
    if (!check(udn::fault_map_valid(s->map), kAssertStateCorrupt)) {
      // Its votes since the last decision are lost with it; the reporters send their suspicions again.
      s->map = udn::endpoint_fault_map();
      s->votes.failed = s->map.failed_tiles;
    }
    adopt_newer_map(*s);
    for (std::uint32_t i = 0; i < udn::kFtRxDepth && udn::endpoint_receive(udn::kFtChanFdir, m) == udn::FtError::kOk;
         ++i) {
      const std::span<const std::uint32_t> w(m.data.data(), m.data_words);
      udn::SuspectReport suspect{};
      udn::TransitReport transit{};
      if (udn::unpack_suspect(w, suspect) && suspect.reporter == m.source) {
        take(*s, self, suspect.reporter, suspect.suspect);
      } else if (udn::unpack_transit(w, transit) && transit.prober == m.source) {
        take_transit(*s, *cfg, transit);
      }
    }
    if (s->to_send == 0ULL) {
      declare_replaced(*s, self);
      judge_transits(*s, *cfg, self);
    }
    if (s->to_send != 0ULL) {
      publish(*s);
    }
    k::checkin();
    k::sleep(s->to_send != 0ULL ? 1 : static_cast<k::Ticks>(cfg->idle_ticks));
  }
}

NetHealthView net_health_view(bsp::TileId tile) noexcept {
  if (tile >= bsp::kMaxTiles || g_state[tile] == nullptr) {
    return NetHealthView{};
  }
  const State& s = *g_state[tile];
  return NetHealthView{s.votes.failed, s.votes.links, s.map.version, s.published};
}

const bsp::ControlLayout& net_health_state_layout() noexcept { return kStateLayout; }

}  // namespace fdir
