/**
 * @file board.cpp
 * @brief The one static board and its deterministic driver: quanta, barriers, tiles in fixed order, power.
 */
#include "bsp_tile64/emu/board.hpp"

#include "bsp_tile64/emu/board_state.hpp"
#include "bsp_tile64/api/memory.hpp"
#include "bsp_tile64/emu/stack_paint.hpp"
#include "bsp_tile64/emu/trace.hpp"

#include <array>
#include <cstdint>
#include <span>

namespace bsp {
namespace detail {

Board g_board{};

namespace {

/** Events that did not fit a tile's list at a barrier wait here to be queued again. */
std::array<Event, kEventCapacity> g_overflow{};

/**
 * Steps of one tile in one quantum. Each step ends at the quantum end or at a
 * reset or boot; a reset-boot cycle takes at least the boot delay, so only a
 * pathological configuration (tiny boot delay, immediate watchdog) comes near.
 */
constexpr std::uint32_t kMaxTileSteps = 1U << 20U;

void clear_tile(Tile& t, TileId id) noexcept {
  t.id = id;
  t.time = 0U;
  t.boot_at = 0U;
  t.power = PowerState::kOff;
  t.stopped = false;
  t.reset_pending = false;
  t.reset_reason = ResetReason::kCommand;
  t.boot_cause = BootCause::kPowerOn;
  t.masked = true;
  t.pending = 0U;
  t.handler = nullptr;
  t.timer_period = 0U;
  t.timer_at = 0U;
  t.wd_armed = false;
  t.wd_reset = false;
  t.wd_failed = false;
  t.wd_timeout = 0U;
  t.wd_deadline = 0U;
  t.current = nullptr;
  t.boot_stack = nullptr;
  t.local.clear();
  t.stats = TileStats{};
  t.state_cycles.fill(0U);
  t.charged = PowerState::kOff;
}

/** Contexts, timer, watchdog and interrupts go; the RAM region is emptied. */
void discard_tile_state(Tile& t) noexcept {
  t.current = nullptr;
  t.boot_stack = nullptr;
  t.stopped = false;
  t.reset_pending = false;
  t.masked = true;
  t.pending = 0U;
  t.handler = nullptr;
  t.timer_period = 0U;
  t.wd_armed = false;
  t.wd_timeout = 0U;
  const std::span<std::byte> ram = region_span(Region{t.id});
  unpoison(ram.data(), ram.size());
  static_cast<void>(region_reset(Region{t.id}));  // cannot fail: the id is inside the grid
}

void boot_main(void* arg) {
  const Tile* t = static_cast<const Tile*>(arg);
  const BootEntry entry = g_board.config.boot[t->id];
  entry(t->id);  // start_boot() runs a context only when there is an entry
}

void start_boot(Tile& t) noexcept {
  ++t.stats.boots;
  t.pending = 0U;
  t.masked = true;
  if (g_board.config.boot[t.id] == nullptr) {
    t.power = PowerState::kIdle;  // no program: the tile idles with no context
    board_trace(t.time, t.id, BoardEvent::kBoot, t.stats.boots, 0U);
    return;
  }
  const std::size_t bytes = g_board.config.boot_stack_bytes;
  const Carve c = carve_stack(Region{t.id}, bytes, 16U, "board boot stack");
  if (c.error != MemError::kOk) {
    board_trace(t.time, t.id, BoardEvent::kBootFailed, static_cast<std::uint64_t>(c.error), 0U);
    t.power = PowerState::kActive;
    t.stopped = true;
    return;
  }
  stack_paint({c.ptr, bytes});
  t.boot_stack = c.ptr;
  context_init(t.boot_ctx, c.ptr, bytes, boot_main, &t);
  t.current = &t.boot_ctx;
  t.power = PowerState::kActive;
  board_trace(t.time, t.id, BoardEvent::kBoot, t.stats.boots, 1U);
}

void do_power_on(Tile& t) noexcept {
  if (t.power != PowerState::kOff) {
    return;  // already on: switching on is idempotent
  }
  t.power = PowerState::kBooting;
  t.boot_cause = BootCause::kPowerOn;
  t.boot_at = t.time + g_board.config.boot_delay_cycles;
  board_trace(t.time, t.id, BoardEvent::kPowerOn, t.boot_at, 0U);
}

void do_power_off(Tile& t) noexcept {
  discard_tile_state(t);
  t.power = PowerState::kOff;
  board_trace(t.time, t.id, BoardEvent::kPowerOff, 0U, 0U);
}

void do_reset(Tile& t, ResetReason reason) noexcept {
  discard_tile_state(t);
  ++t.stats.resets;
  t.power = PowerState::kBooting;
  t.boot_cause = reason == ResetReason::kCommand    ? BootCause::kCommand
                 : reason == ResetReason::kWatchdog ? BootCause::kWatchdog
                                                    : BootCause::kOther;
  t.boot_at = t.time + g_board.config.boot_delay_cycles;
  board_trace(t.time, t.id, BoardEvent::kReset, static_cast<std::uint64_t>(reason), t.boot_at);
}

void do_hang(Tile& t) noexcept {
  if (!t.stopped) {
    t.stopped = true;
    board_trace(t.time, t.id, BoardEvent::kHang, 0U, 0U);
  }
}

void apply(const DeferredCommand& c) noexcept {
  Tile& t = g_board.tile[c.tile];
  switch (c.cmd) {
    case Command::kPowerOn:
      do_power_on(t);
      break;
    case Command::kPowerOff:
      do_power_off(t);
      break;
    case Command::kReset:
      do_reset(t, c.reason);
      break;
    case Command::kHang:
      do_hang(t);
      break;
    case Command::kMonitor:
      board_trace(t.time, t.id, BoardEvent::kMonitorSelect, g_board.config.monitor_tile, 0U);
      g_board.config.monitor_tile = t.id;
      break;
  }
}

/** Host (or barrier): apply now; running tile: defer to the next barrier. */
BoardError command(Command cmd, TileId tile, ResetReason reason) noexcept {
  if (!valid_tile(tile)) {
    return BoardError::kBadTile;
  }
  Board& b = g_board;
  const DeferredCommand c{cmd, tile, reason};
  if (b.processing == kNoTile) {
    apply(c);
    return BoardError::kOk;
  }
  if (b.processing == tile && (cmd == Command::kHang || cmd == Command::kReset)) {
    Tile& t = b.tile[tile];  // an event of the tile itself: effective at once, at its exact cycle
    if (cmd == Command::kHang) {
      do_hang(t);
    } else {
      t.reset_pending = true;
      t.reset_reason = reason;
    }
    return BoardError::kOk;
  }
  if (b.command_count >= kMaxDeferredCommands) {
    return BoardError::kFull;
  }
  b.commands[b.command_count++] = c;
  return BoardError::kOk;
}

void distribute(Cycles q_end) noexcept {
  Board& b = g_board;
  std::size_t over = 0U;
  for (std::size_t n = 0; n < kEventCapacity; ++n) {
    if (b.queue.empty() || b.queue.top().cycle >= q_end) {
      break;
    }
    const Event e = b.queue.top();
    b.queue.pop();
    if (!b.tile[e.tile].local.insert(e)) {
      board_trace(b.now, e.tile, BoardEvent::kEventLate, e.cycle, 1U);
      g_overflow[over++] = e;
    }
  }
  for (std::size_t i = 0; i < over; ++i) {
    static_cast<void>(b.queue.push(g_overflow[i]));  // they came out of this queue: room is there
  }
}

void barrier(Cycles q_start, Cycles q_end) noexcept {
  Board& b = g_board;
  b.in_barrier = true;
  b.q_end = q_end;
  for (std::size_t i = 0; i < b.command_count; ++i) {
    apply(b.commands[i]);
  }
  b.command_count = 0U;
  for (TileId i = 0; i < b.tiles; ++i) {
    Tile& t = b.tile[i];
    if (t.power == PowerState::kActive || t.power == PowerState::kIdle) {
      t.pending |= b.irq_deferred[i];
    }
    b.irq_deferred[i] = 0U;
  }
  b.wd_expired |= b.wd_expired_deferred;
  b.wd_expired_deferred = 0U;
  injector_barrier(q_start, q_end);
  for (std::size_t i = 0; i < b.hook_count; ++i) {
    b.hooks[i](q_start);
  }
  distribute(q_end);
  b.in_barrier = false;
}

bool runnable(const Tile& t) noexcept {
  return (t.power == PowerState::kActive || t.power == PowerState::kIdle) && !t.stopped && t.current != nullptr;
}

/** An idle tile with nothing to do before the quantum end would only yield again: skip the switches. */
bool can_skip(const Tile& t, Cycles q_end) noexcept {
  const bool wd_due = t.wd_armed && !t.wd_failed && t.wd_deadline <= q_end;
  const bool timer_due = t.timer_period != 0U && t.timer_at < q_end;
  return t.power == PowerState::kIdle && t.pending == 0U && t.local.empty() && !wd_due && !timer_due;
}

void resume(Tile& t) noexcept {
  g_board.running = t.id;
  switch_raw(g_board.host_ctx, *t.current);
  g_board.running = kNoTile;
}

/** Advances a tile that runs no context (off, booting, stopped, idle without program). */
void advance_passive(Tile& t, Cycles q_end) noexcept {
  for (std::uint64_t n = 0; n < kMaxLoopSteps; ++n) {
    deliver_due(t);
    if (t.reset_pending) {
      return;
    }
    if (t.power == PowerState::kBooting && t.boot_at <= t.time && t.time < q_end) {
      start_boot(t);
      return;
    }
    if (t.time >= q_end) {
      return;
    }
    const Cycles wake = next_wake(t);
    // Off, booting, stopped or without a program: the cycles go to the state the tile is in.
    advance_to(t, t.power, wake < q_end ? wake : q_end);
  }
}

void run_tile(Tile& t, Cycles q_end) noexcept {
  g_board.processing = t.id;
  for (std::uint32_t n = 0; n < kMaxTileSteps; ++n) {
    if (runnable(t)) {
      if (can_skip(t, q_end)) {
        advance_to(t, PowerState::kIdle, q_end);
      } else {
        resume(t);
      }
    } else {
      advance_passive(t, q_end);
    }
    if (t.reset_pending) {
      do_reset(t, t.reset_reason);
      continue;
    }
    if (t.time >= q_end) {
      break;
    }
  }
  g_board.processing = kNoTile;
}

RunResult run_core(Cycles end, StopPredicate stop, void* arg) noexcept {
  Board& b = g_board;
  const Cycles quantum = b.config.quantum_cycles;
  const Cycles max_quanta = (end - b.now) / quantum + 2U;
  for (Cycles q = 0; q < max_quanta && b.now < end; ++q) {
    if (b.stop_requested) {
      b.stop_requested = false;
      return {b.now, StopReason::kRequested};
    }
    if (stop != nullptr && stop(arg)) {
      return {b.now, StopReason::kPredicate};
    }
    // Quanta are aligned to multiples of the quantum, so a run cut in pieces keeps its barriers.
    const Cycles boundary = (b.now / quantum + 1U) * quantum;
    const Cycles q_end = boundary < end ? boundary : end;
    barrier(b.now, q_end);
    for (TileId i = 0; i < b.tiles; ++i) {
      run_tile(b.tile[i], q_end);
    }
    b.now = q_end;
  }
  return {b.now, StopReason::kTimeReached};
}

bool config_ok(const BoardConfig& c) noexcept {
  const TileId tiles = c.profile.tiles();
  return tiles != 0U && tiles <= kMaxTiles && c.quantum_cycles != 0U && c.quantum_cycles <= c.tick_cycles &&
         c.boot_stack_bytes >= kMinStackBytes && c.boot_stack_bytes % 16U == 0U &&
         (c.monitor_tile == kNoTile || c.monitor_tile < tiles);
}

}  // namespace

void board_trace(Cycles time, TileId tile, BoardEvent kind, std::uint64_t a, std::uint64_t b) noexcept {
  trace_record(time, tile, static_cast<std::uint16_t>(kind), a, b);
}

}  // namespace detail

BoardConfig default_config(const ChipProfile& profile) noexcept {
  BoardConfig c{};
  c.profile = profile;
  c.tick_cycles = profile.cycles_per_ms();
  c.quantum_cycles = c.tick_cycles;
  c.boot_delay_cycles = c.tick_cycles;
  return c;
}

BoardError board_init(const BoardConfig& config) noexcept {
  if (!detail::config_ok(config)) {
    return BoardError::kBadConfig;
  }
  detail::Board& b = detail::g_board;
  b.config = config;
  b.tiles = config.profile.tiles();
  b.now = 0U;
  b.q_end = 0U;
  b.running = kNoTile;
  b.processing = kNoTile;
  b.in_barrier = false;
  b.stop_requested = false;
  b.seq = 0U;
  b.wd_expired = 0U;
  b.wd_expired_deferred = 0U;
  b.irq_deferred.fill(0U);
  b.command_count = 0U;
  b.hook_count = 0U;
  b.queue.clear();
  trace_reset();
  detail::board_trace(0U, kNoTile, BoardEvent::kInit, config.seed, b.tiles);
  for (TileId i = 0; i < kMaxTiles; ++i) {
    detail::clear_tile(b.tile[i], i);
    if (i < b.tiles) {
      detail::discard_tile_state(b.tile[i]);
    }
  }
  detail::injector_reset(config.seed);
  for (TileId i = 0; i < b.tiles; ++i) {
    if (((config.powered_at_start >> i) & 1U) != 0U) {
      detail::do_power_on(b.tile[i]);
    }
  }
  return BoardError::kOk;
}

const BoardConfig& board_config() noexcept { return detail::g_board.config; }

RunResult run_for(Cycles cycles) noexcept {
  const Cycles now = detail::g_board.now;
  const Cycles end = (cycles > ~Cycles{0} - now) ? ~Cycles{0} : now + cycles;
  return detail::run_core(end, nullptr, nullptr);
}

RunResult run_until(StopPredicate stop, void* arg, Cycles max_cycles) noexcept {
  const Cycles now = detail::g_board.now;
  const Cycles end = (max_cycles > ~Cycles{0} - now) ? ~Cycles{0} : now + max_cycles;
  return detail::run_core(end, stop, arg);
}

void request_stop() noexcept { detail::g_board.stop_requested = true; }

Cycles board_time() noexcept { return detail::g_board.now; }

Cycles tile_time(TileId tile) noexcept { return detail::valid_tile(tile) ? detail::g_board.tile[tile].time : 0U; }

PowerState power_state(TileId tile) noexcept {
  return detail::valid_tile(tile) ? detail::g_board.tile[tile].power : PowerState::kOff;
}

bool tile_stopped(TileId tile) noexcept { return detail::valid_tile(tile) && detail::g_board.tile[tile].stopped; }

TileStats tile_stats(TileId tile) noexcept {
  return detail::valid_tile(tile) ? detail::g_board.tile[tile].stats : TileStats{};
}

BoardError power_on(TileId tile) noexcept {
  return detail::command(detail::Command::kPowerOn, tile, ResetReason::kCommand);
}

BoardError power_off(TileId tile) noexcept {
  return detail::command(detail::Command::kPowerOff, tile, ResetReason::kCommand);
}

BoardError reset_tile(TileId tile) noexcept { return reset_tile_for(tile, ResetReason::kCommand); }

BoardError reset_tile_for(TileId tile, ResetReason reason) noexcept {
  return detail::command(detail::Command::kReset, tile, reason);
}

void watchdog_monitor_select() noexcept {
  const detail::Tile* t = detail::running_tile();
  if (t != nullptr && detail::g_board.config.monitor_tile != t->id) {
    (void)detail::command(detail::Command::kMonitor, t->id, ResetReason::kCommand);
  }
}

TileId watchdog_monitor() noexcept { return detail::g_board.config.monitor_tile; }

BoardError hang_tile(TileId tile) noexcept { return detail::command(detail::Command::kHang, tile, ResetReason::kFault); }

BoardError set_watchdog_failed(TileId tile, bool failed) noexcept {
  if (!detail::valid_tile(tile)) {
    return BoardError::kBadTile;
  }
  detail::g_board.tile[tile].wd_failed = failed;  // a peripheral's own state: takes effect at once
  return BoardError::kOk;
}

BoardError schedule_event(Cycles cycle, TileId tile, Irq irq, EventCallback callback, std::uint64_t arg) noexcept {
  if (!detail::valid_tile(tile)) {
    return BoardError::kBadTile;
  }
  detail::Board& b = detail::g_board;
  const Event e{cycle, tile, EventKind::kDevice, irq, b.seq++, callback, arg};
  return detail::push_event(e) ? BoardError::kOk : BoardError::kFull;
}

BoardError add_barrier_hook(BarrierHook hook) noexcept {
  detail::Board& b = detail::g_board;
  if (hook == nullptr) {
    return BoardError::kBadState;
  }
  if (b.hook_count >= kMaxBarrierHooks) {
    return BoardError::kFull;
  }
  b.hooks[b.hook_count++] = hook;
  return BoardError::kOk;
}

std::size_t boot_stack_high_water(TileId tile) noexcept {
  if (!detail::valid_tile(tile) || detail::g_board.tile[tile].boot_stack == nullptr) {
    return 0U;
  }
  const detail::Tile& t = detail::g_board.tile[tile];
  return stack_high_water({t.boot_stack, detail::g_board.config.boot_stack_bytes});
}

}  // namespace bsp
