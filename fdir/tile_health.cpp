/**
 * @file tile_health.cpp
 * @brief The tile-health supervisor (see tile_health.hpp); the agents are in health_agent.cpp.
 */
#include "fdir/tile_health.hpp"

#include "bsp_tile64/api/memory.hpp"
#include "bsp_tile64/api/power.hpp"
#include "bsp_tile64/api/udn_driver.hpp"
#include "fdir/assert.hpp"
#include "fdir/event_log.hpp"
#include "fdir/health_table.hpp"
#include "fdir/net_health.hpp"
#include "kernel/kernel.hpp"
#include "udn/crc32c.hpp"
#include "udn/endpoint.hpp"

#include <array>
#include <bit>
#include <string_view>
#include <new>

namespace fdir {
namespace {

struct State {
  k::Semaphore expired{0, 1};  ///< given by the watchdog interrupt
  std::uint64_t watched = 0U;  ///< tiles whose agents report here now
  std::uint64_t suspects = 0U; ///< silent cores named by the network-health task, to act on
  // Self-tests: the round in flight, its three tiles and their digests.
  std::uint32_t round = 0U;
  bool round_open = false;
  k::Ticks round_at = 0U;
  bsp::TileId next_target = 0U;
  std::array<bsp::TileId, 3> tested{};
  std::array<std::uint32_t, 3> digest{};
  std::array<bool, 3> answered{};
  std::array<bool, 3> asked{};  ///< the request went out (the network took it): one refused is sent again
  bool late_ok = false;  ///< the last round closed without an answer: a late one still completes it
  std::array<std::uint32_t, bsp::kMaxTiles> disagreements{};  ///< rounds in a row a tile was outvoted
  std::array<std::uint64_t, udn::kRoleSlots> to_tell{};  ///< per slot: tiles still to be sent its latest move
  std::uint64_t map_to_tell = 0U;  ///< tiles that booted and are still to be sent the fault map
  std::uint64_t adopted = 0U;      ///< spares that took a role: sent every new fault map (the health task skips spares)
  std::uint64_t cut_off = 0U;      ///< watched tiles whose switch the fault map declares failed (handled once)
  std::array<std::uint32_t, bsp::kMaxTiles> map_sent{};  ///< fault-map version last sent to each tile
  std::array<std::uint32_t, bsp::kMaxTiles> arriving{};  ///< per spare switched on: the slot it takes (kNoSlot: none)
  std::array<bsp::TileId, bsp::kMaxTiles> arriving_from{};  ///< per spare switched on: the retired tile
  std::array<k::Ticks, bsp::kMaxTiles> moved_at{};
  MonitorSpec spec{};
  std::array<MonitorState, bsp::kMaxTiles> wd{};
  std::array<k::Ticks, bsp::kMaxTiles> reset_at{};
  std::uint64_t booted = 0U;  ///< tiles that reported a boot at least once
  TileHealthView view{};
  // Power policy: tiles parked (off by design) and woken.
  std::uint64_t off_due = 0U;      ///< parked, still to be switched off
  std::uint64_t waking = 0U;       ///< switched on again, boot report awaited
  std::uint64_t park_to_tell = 0U; ///< tiles still to be sent the parked set
  bsp::TileId replaced = bsp::kNoTile;  ///< the supervisor's tile this standby took over from (its switch goes in the map)
  std::uint32_t park_serial = 0U;
  std::array<k::Ticks, bsp::kMaxTiles> off_at{};
  std::array<bsp::TileId, bsp::kMaxTiles> park_by{};      ///< who asked (the answer goes there)
  std::array<std::uint32_t, bsp::kMaxTiles> park_chan{};  ///< on this channel
};

/** Health views and monitor states are emulated state through and through (bsp::ControlLayout). */
constexpr std::array kViewFields{
    BSP_CONTROL_STATE(TileHealthView, expiries),   BSP_CONTROL_STATE(TileHealthView, resets),
    BSP_CONTROL_STATE(TileHealthView, recovered),  BSP_CONTROL_STATE(TileHealthView, rebooted),
    BSP_CONTROL_STATE(TileHealthView, lost),       BSP_CONTROL_STATE(TileHealthView, moves),
    BSP_CONTROL_STATE(TileHealthView, restored),   BSP_CONTROL_STATE(TileHealthView, pending),
    BSP_CONTROL_STATE(TileHealthView, retired),    BSP_CONTROL_STATE(TileHealthView, self_tests),
    BSP_CONTROL_STATE(TileHealthView, self_tests_late), BSP_CONTROL_STATE(TileHealthView, mismatches),
    BSP_CONTROL_STATE(TileHealthView, spares),     BSP_CONTROL_STATE(TileHealthView, parked),
    BSP_CONTROL_STATE(TileHealthView, parks),      BSP_CONTROL_STATE(TileHealthView, wakes),
};
constexpr bsp::ControlLayout kViewLayout{kViewFields, sizeof(TileHealthView), alignof(TileHealthView)};
static_assert(bsp::control_layout_ok(kViewLayout), "every member of TileHealthView");
constexpr std::array kMonitorFields{
    BSP_CONTROL_STATE(MonitorState, status), BSP_CONTROL_STATE(MonitorState, candidate),
    BSP_CONTROL_STATE(MonitorState, same),   BSP_CONTROL_STATE(MonitorState, actions),
    BSP_CONTROL_STATE(MonitorState, capped),
};
constexpr bsp::ControlLayout kMonitorLayout{kMonitorFields, sizeof(MonitorState), alignof(MonitorState)};
static_assert(bsp::control_layout_ok(kMonitorLayout), "every member of MonitorState");

/**
 * What an upset of the supervisor's state does (bsp::ControlLayout): the
 * monitor spec holds its name's host address and is host state; the rest is
 * the tile's own (bit sets, counters, the round, tile ids and slots, ticks,
 * the watchdog semaphore), flipped for real. A tile id read from it is
 * checked before it indexes (kAssertStateCorrupt).
 */
constexpr std::array kStateFields{
    BSP_CONTROL_NESTED(State, expired, k::SemaphoreLayout::kLayout),
    BSP_CONTROL_STATE(State, watched),
    BSP_CONTROL_STATE(State, suspects),
    BSP_CONTROL_STATE(State, round),
    BSP_CONTROL_STATE(State, round_open),
    BSP_CONTROL_STATE(State, round_at),
    BSP_CONTROL_STATE(State, next_target),
    BSP_CONTROL_STATE(State, tested),
    BSP_CONTROL_STATE(State, digest),
    BSP_CONTROL_STATE(State, answered),
    BSP_CONTROL_STATE(State, asked),
    BSP_CONTROL_STATE(State, late_ok),
    BSP_CONTROL_STATE(State, disagreements),
    BSP_CONTROL_STATE(State, to_tell),
    BSP_CONTROL_STATE(State, map_to_tell),
    BSP_CONTROL_STATE(State, adopted),
    BSP_CONTROL_STATE(State, cut_off),
    BSP_CONTROL_STATE(State, map_sent),
    BSP_CONTROL_STATE(State, arriving),
    BSP_CONTROL_STATE(State, arriving_from),
    BSP_CONTROL_STATE(State, moved_at),
    BSP_CONTROL_HOST(State, spec),
    BSP_CONTROL_NESTED(State, wd, kMonitorLayout),
    BSP_CONTROL_STATE(State, reset_at),
    BSP_CONTROL_STATE(State, booted),
    BSP_CONTROL_NESTED(State, view, kViewLayout),
    BSP_CONTROL_STATE(State, off_due),
    BSP_CONTROL_STATE(State, waking),
    BSP_CONTROL_STATE(State, park_to_tell),
    BSP_CONTROL_STATE(State, replaced),
    BSP_CONTROL_STATE(State, park_serial),
    BSP_CONTROL_STATE(State, off_at),
    BSP_CONTROL_STATE(State, park_by),
    BSP_CONTROL_STATE(State, park_chan),
};
constexpr bsp::ControlLayout kStateLayout{kStateFields, sizeof(State), alignof(State)};
static_assert(bsp::control_layout_ok(kStateLayout), "every member of the tile-health State");

/** Check id: a tile id in the supervisor's state is off the chip (an upset of it); that use is skipped. */
constexpr std::uint32_t kAssertStateCorrupt = 0x0301U;

std::array<State*, bsp::kMaxTiles> g_state{};

/** Boot assignments in DDR (survive the spare's switch-on); nullptr before boot_slots_init. */
std::uint32_t* g_boot_slots = nullptr;

/**
 * The supervisor's ledger in DDR: what it must not forget when its tile
 * restarts or its standby takes over (the tiles it watches, the spares still
 * free, the tiles retired and parked, the resets under each tile's cap, the
 * role directory, the fault map), as words under a CRC-32C. Written whenever
 * it changes.
 */
namespace ledger {
constexpr std::size_t kCrc = 0U;
constexpr std::size_t kSerial = 1U;  ///< writes so far (0: never written)
constexpr std::size_t kWriter = 2U;  ///< the supervisor's tile that wrote it
constexpr std::size_t kMasks = 3U;   ///< watched, spares, retired, parked, booted, cut_off, adopted, capped (two words each)
constexpr std::size_t kMaskCount = 8U;
constexpr std::size_t kParkSerial = kMasks + 2U * kMaskCount;
constexpr std::size_t kResets = kParkSerial + 1U;  ///< per tile: resets under its cap
constexpr std::size_t kRoleTiles = kResets + bsp::kMaxTiles;
constexpr std::size_t kRoleVersions = kRoleTiles + udn::kRoleSlots;
constexpr std::size_t kMap = kRoleVersions + udn::kRoleSlots;  ///< the fault map its endpoint holds (pack_fault_map)
constexpr std::size_t kWords = kMap + udn::kFaultMapWords;
}  // namespace ledger
std::uint32_t* g_ledger = nullptr;
/** Ticks a supervisor starting from its ledger waits for its endpoint at most. */
constexpr std::uint32_t kLedgerWaitTicks = 100U;

void watchdog_isr(bsp::TileId tile) noexcept {
  if (tile < bsp::kMaxTiles && g_state[tile] != nullptr) {
    (void)g_state[tile]->expired.give_from_isr();
  }
}

constexpr std::uint64_t bit(bsp::TileId t) noexcept { return 1ULL << t; }

/** Kernel ticks (1 ms in the mission) since @p then. */
std::uint32_t ticks_since(k::Ticks then) noexcept {
  const k::Ticks now = k::now_ticks();
  return static_cast<std::uint32_t>(now >= then ? now - then : 0U);
}

std::uint32_t distance(bsp::TileId a, bsp::TileId b) noexcept {
  const std::uint32_t cols = bsp::udn_grid_cols() == 0U ? 1U : bsp::udn_grid_cols();
  const std::uint32_t ax = a % cols;
  const std::uint32_t ay = a / cols;
  const std::uint32_t bx = b % cols;
  const std::uint32_t by = b / cols;
  return (ax > bx ? ax - bx : bx - ax) + (ay > by ? ay - by : by - ay);
}

/** The spares kept for a slot of their own (cfg.slot_spare). */
std::uint64_t kept_spares(const TileHealthConfig& cfg) noexcept {
  std::uint64_t m = 0ULL;
  for (const bsp::TileId t : cfg.slot_spare) {
    m |= t < bsp::kMaxTiles ? bit(t) : 0ULL;
  }
  return m;
}

/** True if spare @p t is free and the fault map does not name its switch. */
bool spare_usable(const State& s, bsp::TileId t) noexcept {
  return t < bsp::kMaxTiles && (s.view.spares & bit(t)) != 0ULL &&
         (udn::endpoint_fault_map().failed_tiles & bit(t)) == 0ULL;
}

/**
 * The spare for role slot @p slot of tile @p failed: the slot's own
 * (cfg.slot_spare) if it has one, else the free spare nearest @p failed
 * whose switch the fault map does not name, other than those kept for a
 * slot; kNoTile for none.
 */
bsp::TileId pick_spare(const State& s, const TileHealthConfig& cfg, bsp::TileId failed, std::uint32_t slot) noexcept {
  if (slot < udn::kRoleSlots && cfg.slot_spare[slot] != bsp::kNoTile) {
    return spare_usable(s, cfg.slot_spare[slot]) ? cfg.slot_spare[slot] : bsp::kNoTile;
  }
  const std::uint64_t kept = kept_spares(cfg);
  bsp::TileId best = bsp::kNoTile;
  std::uint32_t best_d = 0xFFFF'FFFFU;
  for (bsp::TileId t = 0; t < bsp::kMaxTiles; ++t) {
    if (!spare_usable(s, t) || (kept & bit(t)) != 0ULL) {
      continue;
    }
    const std::uint32_t d = distance(t, failed);
    if (d < best_d) {
      best = t;
      best_d = d;
    }
  }
  return best;
}

/** Resets watched tile @p t and waits for its boot report (kTileReset with @p cause; kTileLost if refused). */
void reset_watched(State& s, bsp::TileId t, std::uint32_t cause) noexcept {
  if (bsp::reset_tile(t) != bsp::BoardError::kOk) {
    report(EventId::kTileLost, t, 1U);
    return;
  }
  ++s.view.resets;
  s.view.pending |= bit(t);
  s.reset_at[t] = k::now_ticks();
  report(EventId::kTileReset, t, cause, s.wd[t].actions, s.spec.max_actions);
}

/**
 * Switches the free spare nearest @p t on to run boot slot @p slot in its
 * place (kNoSpare when there is none). @return the spare, or kNoTile.
 */
bsp::TileId boot_spare(State& s, const TileHealthConfig& cfg, bsp::TileId t, std::uint32_t slot) noexcept {
  const bsp::TileId p = pick_spare(s, cfg, t, slot);
  if (p == bsp::kNoTile || g_boot_slots == nullptr) {
    report(EventId::kNoSpare, slot, t);
    return bsp::kNoTile;
  }
  s.view.spares &= ~bit(p);
  g_boot_slots[p] = slot;
  if (bsp::power_on(p) != bsp::BoardError::kOk) {
    report(EventId::kNoSpare, slot, t);
    return bsp::kNoTile;
  }
  s.watched |= bit(p);
  s.adopted |= bit(p);
  s.arriving[p] = slot;
  s.arriving_from[p] = t;
  s.moved_at[p] = k::now_ticks();
  ++s.view.moves;
  return p;
}

/** Switches @p t off for good and moves every movable role slot it ran to a spare. */
void retire(State& s, const TileHealthConfig& cfg, bsp::TileId t) noexcept {
  if ((s.view.retired & bit(t)) != 0ULL) {
    return;
  }
  const udn::RoleDirectory held = udn::endpoint_roles();
  for (std::uint32_t slot = 0; slot < udn::kRoleSlots; ++slot) {
    const bool kept_gone = cfg.slot_spare[slot] != bsp::kNoTile && !spare_usable(s, cfg.slot_spare[slot]);
    if (held.tile[slot] == t && ((cfg.movable_slots & (1U << slot)) == 0U || kept_gone)) {
      // A role bound to this tile, or whose own spare is gone (the I/O role's second attachment):
      // nowhere to go, so the tile is kept and a later expiry may reset it again.
      report(EventId::kNoSpare, slot, t);
      return;
    }
  }
  s.view.retired |= bit(t);
  s.view.pending &= ~bit(t);
  s.watched &= ~bit(t);
  (void)bsp::power_off(t);
  const udn::RoleDirectory dir = udn::endpoint_roles();
  for (std::uint32_t slot = 0; slot < udn::kRoleSlots; ++slot) {
    if ((cfg.movable_slots & (1U << slot)) == 0U || dir.tile[slot] != t) {
      continue;
    }
    const bsp::TileId p = boot_spare(s, cfg, t, slot);
    if (p == bsp::kNoTile) {
      continue;
    }
    const std::uint32_t version = dir.version[slot] + 1U;
    (void)udn::endpoint_move_role(slot, p, version);
    s.to_tell[slot] = s.watched;
    report(EventId::kRoleMoved, slot, t, p, version);
  }
}

/** A worker whose results stay wrong (a coordinator's report): reset it, or switch it off for a spare. */
void on_results_bad(State& s, const TileHealthConfig& cfg, bsp::TileId from, const ResultsBad& bad) noexcept {
  const bsp::TileId t = bad.worker;
  if ((s.watched & bit(t)) == 0ULL || (s.view.pending & bit(t)) != 0ULL) {
    return;  // not ours, or being reset already
  }
  if (bad.action != ResultsAction::kReplace) {
    reset_watched(s, t, 2U);
    return;
  }
  s.view.retired |= bit(t);
  s.watched &= ~bit(t);
  (void)bsp::power_off(t);
  const bsp::TileId p = boot_spare(s, cfg, t, bad.boot_slot);
  if (p != bsp::kNoTile) {
    report(EventId::kRoleMoved, bad.boot_slot, t, p, 0U);
  }
  std::array<std::uint32_t, kReplacedWords> w{};
  (void)msg::encode(kReplacedMsg, Replaced{t, p}, w);
  (void)udn::endpoint_send(from, bad.answer_channel, w, 0U);  // lost, the coordinator goes on without the tile
}

/** Sends the latest move of each slot, and the fault map, to the tiles still to be told (one try each per pass). */
void tell_moves(State& s) noexcept {
  const udn::FaultMap map = udn::endpoint_fault_map();
  // A tile whose switch the map names failed cannot be reached: nothing is sent to it.
  s.map_to_tell &= ~map.failed_tiles;
  for (std::uint64_t& m : s.to_tell) {
    m &= ~map.failed_tiles;
  }
  const std::uint64_t map_targets = (s.map_to_tell | s.adopted) & s.watched & ~map.failed_tiles;
  if (map_targets != 0ULL && map.version != 0U) {
    std::array<std::uint32_t, udn::kFaultMapWords> w{};
    udn::pack_fault_map(map, w);
    for (bsp::TileId t = 0; t < bsp::kMaxTiles; ++t) {
      const bool due = (s.map_to_tell & bit(t)) != 0ULL || ((s.adopted & bit(t)) != 0ULL && s.map_sent[t] < map.version);
      if ((map_targets & bit(t)) != 0ULL && due && udn::endpoint_send(t, udn::kFtChanMap, w, 0U) == udn::FtError::kOk) {
        s.map_to_tell &= ~bit(t);
        s.map_sent[t] = map.version;
      }
    }
  }
  if (s.park_to_tell != 0ULL) {
    std::array<std::uint32_t, udn::kParkedWords> w{};
    udn::pack_parked(udn::ParkedSet{s.view.parked, s.park_serial}, w);
    for (bsp::TileId t = 0; t < bsp::kMaxTiles; ++t) {
      if ((s.park_to_tell & bit(t)) != 0ULL &&
          ((s.watched & bit(t)) == 0ULL || udn::endpoint_send(t, udn::kFtChanMap, w, 0U) == udn::FtError::kOk)) {
        s.park_to_tell &= ~bit(t);
      }
    }
  }
  const udn::RoleDirectory dir = udn::endpoint_roles();
  for (std::uint32_t slot = 0; slot < udn::kRoleSlots; ++slot) {
    if (s.to_tell[slot] == 0ULL) {
      continue;
    }
    std::array<std::uint32_t, udn::kRoleMoveWords> w{};
    udn::pack_role_move(udn::RoleMove{slot, dir.tile[slot], dir.version[slot]}, w);
    for (bsp::TileId t = 0; t < bsp::kMaxTiles; ++t) {
      if ((s.to_tell[slot] & bit(t)) == 0ULL) {
        continue;
      }
      // Told, or retired meanwhile: nothing more to send it.
      if ((s.watched & bit(t)) == 0ULL || udn::endpoint_send(t, udn::kFtChanMap, w, 0U) == udn::FtError::kOk) {
        s.to_tell[slot] &= ~bit(t);
      }
    }
  }
}

/** The parked set changed: this tile's endpoint and network-health task now, every watched tile by message. */
void parked_changed(State& s) noexcept {
  ++s.park_serial;
  (void)udn::endpoint_set_parked(s.view.parked, s.park_serial);
  net_health_set_parked(s.view.parked);
  s.park_to_tell = s.watched;
}

void answer_park(const State& s, bsp::TileId t, std::uint32_t off) noexcept {
  std::array<std::uint32_t, kParkDoneWords> w{};
  (void)msg::encode(kParkDoneMsg, ParkDone{t, off != 0U}, w);
  (void)udn::endpoint_send(s.park_by[t], s.park_chan[t], w, 0U);  // lost, the asker asks again
}

/** A park or wake request of the power policy. */
void on_park(State& s, bsp::TileId from, const ParkRequest& req, bsp::TileId self) noexcept {
  const bsp::TileId t = req.tile;
  if (t == self) {
    return;
  }
  s.park_by[t] = from;
  s.park_chan[t] = req.answer_channel;
  const bool parked = (s.view.parked & bit(t)) != 0ULL;
  if (req.off) {
    const bool busy = ((s.view.pending | s.view.retired | s.waking) & bit(t)) != 0ULL;
    if (parked && (s.off_due & bit(t)) == 0ULL) {
      answer_park(s, t, 1U);  // asked again: the answer was lost
    }
    if (parked || busy || (s.watched & bit(t)) == 0ULL) {
      return;  // already parked, being reset or woken, or not ours
    }
    s.watched &= ~bit(t);
    s.view.parked |= bit(t);
    s.off_due |= bit(t);
    s.off_at[t] = k::now_ticks() + kParkOffTicks;
    ++s.view.parks;
    report(EventId::kTileParked, t, from);
    parked_changed(s);
  } else if (!parked && (s.watched & bit(t)) != 0ULL && (s.waking & bit(t)) == 0ULL) {
    answer_park(s, t, 0U);  // asked again: the answer was lost
  } else if (parked) {
    s.view.parked &= ~bit(t);
    ++s.view.wakes;
    report(EventId::kTileWoken, t, from);
    if ((s.off_due & bit(t)) != 0ULL) {
      s.off_due &= ~bit(t);  // still on: watched again at once
      s.watched |= bit(t);
      parked_changed(s);
      answer_park(s, t, 0U);
    } else if (bsp::power_on(t) == bsp::BoardError::kOk) {
      s.waking |= bit(t);  // answered at its boot report
      s.view.pending |= bit(t);  // a boot report is awaited: lost past the boot timeout like a reset tile
      s.reset_at[t] = k::now_ticks();
    }
  }
}

/** Parked tiles whose notice had time to arrive are switched off. */
void switch_off_parked(State& s) noexcept {
  const k::Ticks now = k::now_ticks();
  for (bsp::TileId t = 0; t < bsp::kMaxTiles && s.off_due != 0ULL; ++t) {
    if ((s.off_due & bit(t)) != 0ULL && now >= s.off_at[t]) {
      s.off_due &= ~bit(t);
      (void)bsp::power_off(t);
      answer_park(s, t, 1U);
    }
  }
}

/** A tile found silent (its watchdog, or the pings): reset under the cap, else retired. */
void on_expired(State& s, const TileHealthConfig& cfg, bsp::TileId self, bsp::TileId t) noexcept {
  if (t == self || (s.watched & bit(t)) == 0ULL || (s.view.pending & bit(t)) != 0ULL) {
    return;  // its own (the hardware resets it), not ours, or already being reset
  }
  const MonitorResult r = monitor_sample(s.spec, s.wd[t], t, 1U);
  if (!r.act) {
    if (s.wd[t].capped) {
      retire(s, cfg, t);  // past the cap: given up, its roles go to spares
    }
    return;
  }
  reset_watched(s, t, 0U);
}

/** The @p n watched tiles nearest @p target (not it, not @p self), into @p out; @return how many. */
std::uint32_t nearest_watched(const State& s, bsp::TileId target, bsp::TileId self, bsp::TileId* out,
                              std::uint32_t n) noexcept {
  std::uint32_t got = 0U;
  for (std::uint32_t d = 1U; d < 16U && got < n; ++d) {
    for (bsp::TileId t = 0; t < bsp::kMaxTiles && got < n; ++t) {
      if (t != target && t != self && (s.watched & bit(t)) != 0ULL && (s.view.retired & bit(t)) == 0ULL &&
          distance(t, target) == d) {
        out[got++] = t;
      }
    }
  }
  return got;
}

/** The seed every tile of round @p round computes its digest from. */
std::uint32_t round_seed(std::uint32_t round) noexcept { return 0x9E3779B9U * round; }

/**
 * Sends the open round's request to each of its tiles not asked yet. The supervisor's tile sends
 * in bursts (its reports, maps and probes): a request the network refuses for back-pressure is
 * sent again at the next pass while the round is open, not lost. Lost, every round whose third
 * request met a burst went late; after the supervisor's restart that was one round in every one
 * for the rest of the flight (a tile restarts its tasks out of their power-on phase).
 */
void ask(State& s, bsp::TileId self) noexcept {
  std::array<std::uint32_t, kSelfTestWords> w{};
  (void)msg::encode(kSelfTestMsg, SelfTestRequest{s.round, round_seed(s.round)}, w);
  for (std::uint32_t i = 0; i < 3U; ++i) {
    if (!s.asked[i] && s.tested[i] != self) {
      s.asked[i] = udn::endpoint_send(s.tested[i], udn::kFtChanHealth, w, 0U) == udn::FtError::kOk;
    }
  }
}

/** Opens a self-test round: the next watched tile and its two nearest watched tiles compute one seed. */
void open_round(State& s, bsp::TileId self) noexcept {
  for (std::uint32_t k = 0; k < bsp::kMaxTiles; ++k) {
    const bsp::TileId t = static_cast<bsp::TileId>((s.next_target + k) % bsp::kMaxTiles);
    const bool own = t == self && !self_test_pattern(self).empty();  // its turn too, computed here
    if (!own && (t == self || (s.watched & bit(t)) == 0ULL || ((s.view.retired | s.view.pending) & bit(t)) != 0ULL)) {
      continue;
    }
    std::array<bsp::TileId, 2> near{};
    if (nearest_watched(s, t, self, near.data(), 2U) < 2U) {
      return;  // fewer than three tiles to vote
    }
    s.next_target = static_cast<bsp::TileId>((t + 1U) % bsp::kMaxTiles);
    s.tested = {t, near[0], near[1]};
    s.answered = {false, false, false};
    s.asked = {false, false, false};
    ++s.round;
    s.round_open = true;
    s.late_ok = false;
    s.round_at = k::now_ticks();
    if (own) {
      s.asked[0] = true;
      s.answered[0] = self_test_digest(self, round_seed(s.round), s.digest[0]);
    }
    ask(s, self);
    return;
  }
}

/** Votes a round with its three answers: a tile outvoted by the two others disagrees. */
void vote_round(State& s, const TileHealthConfig& cfg, bsp::TileId self) noexcept {
  ++s.view.self_tests;
  for (std::uint32_t i = 0; i < 3U; ++i) {
    const std::uint32_t j = (i + 1U) % 3U;
    const std::uint32_t k = (i + 2U) % 3U;
    const bsp::TileId t = s.tested[i];
    if (!check(t < bsp::kMaxTiles, kAssertStateCorrupt)) {
      continue;
    }
    const bool outvoted = s.digest[j] == s.digest[k] && s.digest[i] != s.digest[j];
    if (outvoted) {
      ++s.view.mismatches;
      ++s.disagreements[t];
      report(EventId::kSelfTestMismatch, t, s.round, s.disagreements[t], cfg.disagreements_to_fail);
      if (s.disagreements[t] >= cfg.disagreements_to_fail && t == self) {
        // Its own tile has no spare to move to: a reset starts it from its image and a clean RAM.
        report(EventId::kTileReset, t, 0U, s.disagreements[t], cfg.disagreements_to_fail);
        (void)bsp::reset_tile(t);
      } else if (s.disagreements[t] >= cfg.disagreements_to_fail) {
        retire(s, cfg, t);
      }
    } else if (s.digest[j] == s.digest[i] || s.digest[k] == s.digest[i]) {
      if (s.disagreements[t] != 0U) {
        report(EventId::kSelfTestAgree, t, s.round, s.disagreements[t]);
      }
      s.disagreements[t] = 0U;
    }
  }
}

/**
 * Closes a round at its wait: voted with three answers; otherwise each tile
 * that has not answered is reported (a busy tile answers late; a silent one is
 * the watchdog's), and a late answer before the next round still completes
 * the vote.
 */
void close_round(State& s, const TileHealthConfig& cfg, bsp::TileId self) noexcept {
  s.round_open = false;
  if (s.answered[0] && s.answered[1] && s.answered[2]) {
    vote_round(s, cfg, self);
    return;
  }
  ++s.view.self_tests_late;
  s.late_ok = true;
  for (std::uint32_t i = 0; i < 3U; ++i) {
    if (!s.answered[i]) {
      report(EventId::kSelfTestLate, s.tested[i], s.round, cfg.self_test_wait_ticks);
    }
  }
}

void take_result(State& s, const TileHealthConfig& cfg, const SelfTestResult& r, bsp::TileId self) noexcept {
  if (r.round != s.round || (!s.round_open && !s.late_ok)) {
    return;  // an older round's, or one voted already
  }
  for (std::uint32_t i = 0; i < 3U; ++i) {
    if (s.tested[i] == r.tile && !s.answered[i]) {
      s.answered[i] = true;
      s.digest[i] = r.digest;
    }
  }
  if (!s.round_open && s.answered[0] && s.answered[1] && s.answered[2]) {
    s.late_ok = false;
    vote_round(s, cfg, self);  // completed by a late answer
  }
}

void on_booted(State& s, bsp::TileId t, std::uint32_t cause) noexcept {
  // It starts from the boot map and directory: the current map and every move
  // so far are sent to it (a spare is not on the health task's publication
  // list, a reset tile may have missed a version).
  if (udn::endpoint_fault_map().version != 0U) {
    s.map_to_tell |= bit(t);  // a first boot starts from the current map already
  }
  const udn::RoleDirectory dir = udn::endpoint_roles();
  for (std::uint32_t slot = 0; slot < udn::kRoleSlots; ++slot) {
    if (dir.version[slot] != 0U) {
      s.to_tell[slot] |= bit(t);
    }
  }
  if ((s.waking & bit(t)) != 0ULL) {
    s.waking &= ~bit(t);  // a parked tile woken by the power policy: watched again, no crash
    s.view.pending &= ~bit(t);
    s.watched |= bit(t);
    s.booted |= bit(t);
    parked_changed(s);
    answer_park(s, t, 0U);
    return;
  }
  if (s.arriving[t] != kNoSlot) {
    ++s.view.restored;
    report(EventId::kRoleRestored, s.arriving[t], s.arriving_from[t], t, ticks_since(s.moved_at[t]));
    s.arriving[t] = kNoSlot;
    s.booted |= bit(t);
    return;
  }
  if ((s.view.pending & bit(t)) != 0ULL) {
    s.view.pending &= ~bit(t);
    ++s.view.recovered;
    monitor_clear(s.wd[t]);
    report(EventId::kTileRecovered, t, cause, ticks_since(s.reset_at[t]));
  } else if ((s.booted & bit(t)) != 0ULL || cause != static_cast<std::uint32_t>(bsp::BootCause::kPowerOn)) {
    ++s.view.rebooted;
    monitor_clear(s.wd[t]);
    report(EventId::kTileRebooted, t, cause);
  }
  s.booted |= bit(t);
}

void check_timeouts(State& s, const TileHealthConfig& cfg) noexcept {
  const k::Ticks now = k::now_ticks();
  for (bsp::TileId t = 0; t < bsp::kMaxTiles; ++t) {
    if ((s.view.pending & bit(t)) != 0ULL && now - s.reset_at[t] > cfg.boot_timeout_ticks) {
      s.view.pending &= ~bit(t);
      s.watched |= s.waking & bit(t);  // a woken tile that never booted is given up like a reset one
      s.waking &= ~bit(t);
      ++s.view.lost;
      report(EventId::kTileLost, t, 0U, ticks_since(s.reset_at[t]));
      retire(s, cfg, t);
    }
  }
}

/**
 * Watched tiles whose switch the fault map declares failed: cut off from the
 * network for good (no reset brings a switch back), so they are retired at
 * once and their roles go to spares; a role bound to its tile stays
 * (no_spare). Each is handled once.
 */
void retire_cut_off(State& s, const TileHealthConfig& cfg, bsp::TileId self) noexcept {
  const std::uint64_t failed = udn::endpoint_fault_map().failed_tiles & s.watched & ~(s.view.retired | s.cut_off);
  for (bsp::TileId t = 0; t < bsp::kMaxTiles; ++t) {
    if ((failed & bit(t)) == 0ULL || t == self) {
      continue;
    }
    s.cut_off |= bit(t);
    report(EventId::kTileLost, t, kLostSwitchFailed, 0U);
    retire(s, cfg, t);
  }
}

/** The watchdogs that expired and the cores the pings named: reset, or retire past the cap. */
void take_expiries(State& s, const TileHealthConfig& cfg, bsp::TileId self) noexcept {
  const std::uint64_t expired = bsp::watchdog_take_expired();
  const std::uint64_t suspects = s.suspects;
  s.suspects = 0U;
  for (bsp::TileId t = 0; t < bsp::kMaxTiles; ++t) {
    if ((expired & bit(t)) != 0ULL) {
      ++s.view.expiries;
      report(EventId::kWatchdogExpired, t, 0U, s.view.expiries);
      on_expired(s, cfg, self, t);
    } else if ((suspects & bit(t)) != 0ULL) {
      on_expired(s, cfg, self, t);  // its watchdog did not expire: the pings found it
    }
  }
}

/** What a report's handler reads besides the report: the supervisor's state, its table, its tile and the sender. */
struct Inbox {
  State& s;
  const TileHealthConfig& cfg;
  bsp::TileId self;
  bsp::TileId source;
};

void take_booted(Inbox& in, const TileBootReport& boot) noexcept {
  on_booted(in.s, in.source, static_cast<std::uint32_t>(boot.cause));
}
void take_result_of(Inbox& in, const SelfTestResult& r) noexcept { take_result(in.s, in.cfg, r, in.self); }
void take_results_bad(Inbox& in, const ResultsBad& bad) noexcept { on_results_bad(in.s, in.cfg, in.source, bad); }
void take_park(Inbox& in, const ParkRequest& park) noexcept { on_park(in.s, in.source, park, in.self); }

/** The kinds the supervisor takes on the health channel; anything else there is dropped. */
constexpr std::array<msg::Handler<Inbox>, 4> kReportHandlers{{
    msg::on<kBootedMsg, &take_booted, Inbox>(),
    msg::on<kSelfTestResultMsg, &take_result_of, Inbox>(),
    msg::on<kResultsBadMsg, &take_results_bad, Inbox>(),
    msg::on<kParkMsg, &take_park, Inbox>(),
}};

/** Boot reports, self-test results, results-bad reports and park requests waiting on the health channel. */
void take_reports(State& s, const TileHealthConfig& cfg, bsp::TileId self) noexcept {
  udn::FtMessage m{};
  for (std::uint32_t i = 0; i < udn::kFtRxDepth && udn::endpoint_receive(udn::kFtChanHealth, m) == udn::FtError::kOk;
       ++i) {
    if (m.source >= bsp::kMaxTiles || m.data_words < 2U || m.data[1] != m.source) {
      continue;  // word 1 of every report is its sender's tile
    }
    Inbox in{s, cfg, self, m.source};
    (void)msg::dispatch(kReportHandlers, std::span<const std::uint32_t>(m.data.data(), m.data_words), in);
  }
}

/** Votes a round when all answered or its wait is over; opens the next every self_test_ticks. */
void run_self_tests(State& s, const TileHealthConfig& cfg, bsp::TileId self) noexcept {
  if (cfg.self_test_ticks == 0U) {
    return;
  }
  const k::Ticks now = k::now_ticks();
  if (s.round_open) {
    ask(s, self);  // a request the network refused before
  }
  const bool all_in = s.round_open && s.answered[0] && s.answered[1] && s.answered[2];
  if (s.round_open && (all_in || now - s.round_at >= cfg.self_test_wait_ticks)) {
    close_round(s, cfg, self);
  }
  if (!s.round_open && now - s.round_at >= cfg.self_test_ticks) {
    open_round(s, self);
    s.round_at = now;
  }
}

/** The supervisor's state, as ledger words (word 0, the CRC, and 1, the serial, left 0). */
std::array<std::uint32_t, ledger::kWords> ledger_words(const State& s, bsp::TileId self) noexcept {
  std::array<std::uint32_t, ledger::kWords> w{};
  w[ledger::kWriter] = self;
  std::uint64_t capped = 0U;
  for (bsp::TileId t = 0; t < bsp::kMaxTiles; ++t) {
    w[ledger::kResets + t] = s.wd[t].actions;
    capped |= s.wd[t].capped ? bit(t) : 0ULL;
  }
  const std::array<std::uint64_t, ledger::kMaskCount> masks{s.watched, s.view.spares, s.view.retired, s.view.parked,
                                                            s.booted,  s.cut_off,     s.adopted,      capped};
  for (std::size_t i = 0; i < masks.size(); ++i) {
    w[ledger::kMasks + 2U * i] = static_cast<std::uint32_t>(masks[i]);
    w[ledger::kMasks + 2U * i + 1U] = static_cast<std::uint32_t>(masks[i] >> 32U);
  }
  w[ledger::kParkSerial] = s.park_serial;
  const udn::RoleDirectory dir = udn::endpoint_roles();
  for (std::uint32_t slot = 0; slot < udn::kRoleSlots; ++slot) {
    w[ledger::kRoleTiles + slot] = dir.tile[slot];
    w[ledger::kRoleVersions + slot] = dir.version[slot];
  }
  udn::pack_fault_map(udn::endpoint_fault_map(),
                      std::span<std::uint32_t, udn::kFaultMapWords>(w.data() + ledger::kMap, udn::kFaultMapWords));
  return w;
}

/** Writes the ledger if the state changed since the last write (one pass of the supervisor). */
void ledger_write(const State& s, bsp::TileId self) noexcept {
  if (g_ledger == nullptr) {
    return;
  }
  std::array<std::uint32_t, ledger::kWords> w = ledger_words(s, self);
  bool same = g_ledger[ledger::kSerial] != 0U;
  for (std::size_t i = ledger::kWriter; i < ledger::kWords && same; ++i) {
    same = g_ledger[i] == w[i];
  }
  if (same) {
    return;
  }
  w[ledger::kSerial] = g_ledger[ledger::kSerial] + 1U;
  w[ledger::kCrc] = udn::crc32c_words(std::span<const std::uint32_t>(w).subspan(1U));
  for (std::size_t i = 0; i < ledger::kWords; ++i) {
    g_ledger[i] = w[i];
  }
}

/** The ledger's words if it was written and its CRC holds; false otherwise (the state starts from the configuration). */
bool ledger_read(std::array<std::uint32_t, ledger::kWords>& w) noexcept {
  if (g_ledger == nullptr) {
    return false;
  }
  for (std::size_t i = 0; i < ledger::kWords; ++i) {
    w[i] = g_ledger[i];
  }
  return w[ledger::kSerial] != 0U && w[ledger::kWriter] < bsp::kMaxTiles &&
         w[ledger::kCrc] == udn::crc32c_words(std::span<const std::uint32_t>(w).subspan(1U));
}

/** Takes the state the ledger holds: the tiles, the caps, the parked set and the directory's moves. */
void ledger_take(State& s, const std::array<std::uint32_t, ledger::kWords>& w) noexcept {
  std::array<std::uint64_t, ledger::kMaskCount> m{};
  for (std::size_t i = 0; i < m.size(); ++i) {
    m[i] = w[ledger::kMasks + 2U * i] | (std::uint64_t{w[ledger::kMasks + 2U * i + 1U]} << 32U);
  }
  s.watched = m[0];
  s.view.spares = m[1];
  s.view.retired = m[2];
  s.view.parked = m[3];
  s.booted = m[4];
  s.cut_off = m[5];
  s.adopted = m[6];
  for (bsp::TileId t = 0; t < bsp::kMaxTiles; ++t) {
    s.wd[t].actions = w[ledger::kResets + t];
    s.wd[t].capped = (m[7] & bit(t)) != 0ULL;
  }
  s.park_serial = w[ledger::kParkSerial];
  for (std::uint32_t slot = 0; slot < udn::kRoleSlots; ++slot) {
    const std::uint32_t version = w[ledger::kRoleVersions + slot];
    if (version != 0U) {
      (void)udn::endpoint_move_role(slot, w[ledger::kRoleTiles + slot], version);  // an older one is refused
    }
  }
  // The map it held: a standby's endpoint starts from the boot one, and its routes would cross the
  // switches already taken out (the neighbours' probes bring the map too, but only after a while).
  udn::FaultMap map{};
  if (udn::unpack_fault_map(std::span<const std::uint32_t>(w.data() + ledger::kMap, udn::kFaultMapWords), map)) {
    (void)udn::endpoint_install_map(map);  // an older one is refused
  }
  if (s.view.parked != 0ULL) {
    ++s.park_serial;
    (void)udn::endpoint_set_parked(s.view.parked, s.park_serial);
    net_health_set_parked(s.view.parked);
  }
}

/**
 * The supervisor's start: from its ledger when one holds (a restart, or the
 * standby taking over), else from the configuration. The standby (its boot
 * slot is the supervisor's own) also takes the watchdog line, gives up the
 * tile it replaces, and moves the role's slot to itself (told to every tile).
 */
void start_state(State& s, const TileHealthConfig& cfg, bsp::TileId self) noexcept {
  s.watched = cfg.watched;
  s.view.spares = cfg.spares;
  std::array<std::uint32_t, ledger::kWords> w{};
  const bool held = ledger_read(w);
  if (held) {
    (void)udn::endpoint_wait_ready(kLedgerWaitTicks);  // the moves and the parked set go to its endpoint
    ledger_take(s, w);
  }
  const bool standby = cfg.own_slot < udn::kRoleSlots && boot_slot(self) == cfg.own_slot;
  if (!standby || (held && w[ledger::kWriter] == self)) {
    return;  // its own tile, or the standby restarted: nothing to take over
  }
  bsp::watchdog_monitor_select();
  const bsp::TileId old = held ? static_cast<bsp::TileId>(w[ledger::kWriter]) : udn::endpoint_role_tile(cfg.own_slot, bsp::kNoTile);
  if (old < bsp::kMaxTiles) {
    s.replaced = old;
    s.view.retired |= bit(old);
    s.watched &= ~bit(old);
    s.view.pending &= ~bit(old);
  }
  s.watched |= bit(self);
  s.booted |= bit(self);
  s.view.spares &= ~bit(self);
  const udn::RoleDirectory dir = udn::endpoint_roles();
  const std::uint32_t version =
      (held && w[ledger::kRoleVersions + cfg.own_slot] > dir.version[cfg.own_slot] ? w[ledger::kRoleVersions + cfg.own_slot]
                                                                                   : dir.version[cfg.own_slot]) + 1U;
  (void)udn::endpoint_move_role(cfg.own_slot, self, version);
  s.to_tell[cfg.own_slot] = s.watched & ~bit(self);
  report(EventId::kSupervisorTookOver, self, old, held ? 1U : 0U, version);
}

}  // namespace

void tile_health_task_main(void* arg) noexcept {
  const auto* cfg = static_cast<const TileHealthConfig*>(arg);
  const bsp::TileId self = bsp::current_tile();
  if (cfg == nullptr || self >= bsp::kMaxTiles || cfg->max_resets == 0U || cfg->poll_ticks == 0U ||
      cfg->disagreements_to_fail == 0U) {
    return;
  }
  g_state[self] = nullptr;
  bsp::MemError err = bsp::MemError::kOk;
  auto* s = bsp::carve_control_array<State>(bsp::Region{self}, 1, kTileHealthCarve, &err, &kStateLayout);
  if (err != bsp::MemError::kOk || s == nullptr) {
    return;
  }
  ::new (s) State{};
  s->arriving.fill(kNoSlot);
  // A silent tile is one sample of 1: fatal at once, the action a reset, at most max_resets.
  s->spec = MonitorSpec{"watchdog", 0U, 1U, 1U, MonitorAction::kRestart, cfg->max_resets};
  g_state[self] = s;
  if (k::set_isr(bsp::Irq::kWatchdog, &watchdog_isr) != k::Status::kOk) {
    return;
  }
  const bsp::BootCause own = bsp::boot_cause();
  if (own != bsp::BootCause::kPowerOn) {
    ++s->view.rebooted;
    report(EventId::kTileRebooted, self, static_cast<std::uint32_t>(own));
  }
  start_state(*s, *cfg, self);
  s->booted |= bit(self);
  for (;;) {
    (void)s->expired.take(k::Timeout{cfg->poll_ticks});
    take_expiries(*s, *cfg, self);
    take_reports(*s, *cfg, self);
    check_timeouts(*s, *cfg);
    retire_cut_off(*s, *cfg, self);
    switch_off_parked(*s);
    tell_moves(*s);
    run_self_tests(*s, *cfg, self);
    ledger_write(*s, self);
    k::checkin();
  }
}

void tile_health_core_suspect(bsp::TileId tile) noexcept {
  const bsp::TileId self = bsp::current_tile();
  if (self < bsp::kMaxTiles && tile < bsp::kMaxTiles && g_state[self] != nullptr) {
    g_state[self]->suspects |= bit(tile);
  }
}

bsp::TileId tile_health_replaced() noexcept {
  const bsp::TileId self = bsp::current_tile();
  if (self >= bsp::kMaxTiles || g_state[self] == nullptr) {
    return bsp::kNoTile;
  }
  const bsp::TileId t = g_state[self]->replaced;
  return t < bsp::kMaxTiles ? t : bsp::kNoTile;
}

bool boot_slots_init() noexcept {
  bsp::MemError err = bsp::MemError::kOk;
  auto* slots = bsp::carve_array<std::uint32_t>(bsp::Region{bsp::Region::kDdr}, bsp::kMaxTiles, "fdir_boot_slots", &err);
  if (err != bsp::MemError::kOk || slots == nullptr) {
    g_boot_slots = nullptr;
    return false;
  }
  for (bsp::TileId t = 0; t < bsp::kMaxTiles; ++t) {
    slots[t] = kNoSlot;
  }
  g_boot_slots = slots;
  auto* book = bsp::carve_array<std::uint32_t>(bsp::Region{bsp::Region::kDdr}, ledger::kWords, "fdir_health_ledger", &err);
  if (err != bsp::MemError::kOk || book == nullptr) {
    g_ledger = nullptr;
    return false;
  }
  for (std::size_t i = 0; i < ledger::kWords; ++i) {
    book[i] = 0U;  // never written: a supervisor starts from its configuration
  }
  g_ledger = book;
  return true;
}

std::uint32_t boot_slot(bsp::TileId tile) noexcept {
  return (g_boot_slots == nullptr || tile >= bsp::kMaxTiles) ? kNoSlot : g_boot_slots[tile];
}

void ledger_roles_apply() noexcept {
  std::array<std::uint32_t, ledger::kWords> w{};
  if (!ledger_read(w)) {
    return;
  }
  for (std::uint32_t slot = 0; slot < udn::kRoleSlots; ++slot) {
    const std::uint32_t version = w[ledger::kRoleVersions + slot];
    if (version != 0U) {
      (void)udn::endpoint_move_role(slot, w[ledger::kRoleTiles + slot], version);  // an older one is refused
    }
  }
}

bool boot_slot_assign(bsp::TileId tile, std::uint32_t slot) noexcept {
  if (g_boot_slots == nullptr || tile >= bsp::kMaxTiles) {
    return false;
  }
  g_boot_slots[tile] = slot;
  return true;
}

TileHealthView tile_health_view(bsp::TileId tile) noexcept {
  if (tile >= bsp::kMaxTiles || g_state[tile] == nullptr) {
    return TileHealthView{};
  }
  return g_state[tile]->view;
}

const bsp::ControlLayout& tile_health_state_layout() noexcept { return kStateLayout; }

}  // namespace fdir
