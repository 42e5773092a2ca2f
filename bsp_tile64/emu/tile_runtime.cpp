/**
 * @file tile_runtime.cpp
 * @brief The tile side of the port: time, work, interrupts, timer and watchdog of the running tile.
 *
 * Everything here runs on a tile's context (or, for event delivery, in the
 * driver on behalf of a tile that is not running). Time advances only in
 * consume() and wait_for_interrupt(), in steps that stop at the next event of
 * the tile and at the quantum end, so interrupts are taken at their exact cycle.
 */
#include "bsp_tile64/emu/board_state.hpp"
#include "bsp_tile64/emu/cost_model.hpp"
#include "bsp_tile64/api/port.hpp"

#include <bit>
#include <cstdint>

namespace bsp {
namespace detail {
namespace {

constexpr std::uint32_t irq_bit(Irq irq) noexcept { return 1U << static_cast<std::uint32_t>(irq); }

bool powered(const Tile& t) noexcept { return t.power == PowerState::kActive || t.power == PowerState::kIdle; }

void expire_watchdog(Tile& t) noexcept {
  Board& b = board();
  t.wd_armed = false;
  ++t.stats.watchdog_expiries;
  board_trace(t.wd_deadline, t.id, BoardEvent::kWatchdogExpired, b.config.monitor_tile, t.wd_reset ? 1U : 0U);
  // The monitor sees the expiry at the next barrier, like any cross-tile effect.
  b.wd_expired_deferred |= 1ULL << t.id;
  if (b.config.monitor_tile != kNoTile) {
    b.irq_deferred[b.config.monitor_tile] |= irq_bit(Irq::kWatchdog);
  }
  if (t.wd_reset) {
    t.reset_pending = true;
    t.reset_reason = ResetReason::kWatchdog;
  }
}

void deliver_one(Tile& t, const Event& e) noexcept {
  if (e.callback != nullptr) {
    e.callback(t.id, e.cycle, e.arg);
  }
  if (e.irq != Irq::kCount && powered(t)) {
    t.pending |= irq_bit(e.irq);
  }
}

void yield_to_driver(Tile& t) noexcept { switch_raw(*t.current, board().host_ctx); }

/** Takes pending interrupts in Irq order, masked while each handler runs. */
void dispatch(Tile& t) noexcept {
  for (std::uint32_t n = 0; n < kMaxDispatch; ++n) {
    if (t.pending == 0U || t.masked || t.stopped || t.reset_pending) {
      return;
    }
    const auto index = static_cast<std::uint32_t>(std::countr_zero(t.pending));
    t.pending &= ~(1U << index);
    if (t.handler == nullptr) {
      board_trace(t.time, t.id, BoardEvent::kIrqDropped, index, 0U);
      continue;
    }
    ++t.stats.irqs_taken;
    board_trace(t.time, t.id, BoardEvent::kIrqTaken, index, 0U);
    t.masked = true;
    t.handler(t.id, static_cast<Irq>(index));
    t.masked = false;
  }
}

/** Delivers what is due, leaves the tile if it was stopped or reset, takes interrupts. */
void service(Tile& t) noexcept {
  deliver_due(t);
  if (t.reset_pending) {
    switch_abandon(board().host_ctx);  // the driver resets the tile; this context is gone
  }
  if (t.stopped) {
    yield_to_driver(t);  // never resumed: a stopped tile's contexts are not run
  }
  dispatch(t);
}

}  // namespace

bool push_event(const Event& e) noexcept {
  Board& b = board();
  if (e.tile == b.processing && e.cycle < b.q_end && !b.in_barrier) {
    if (b.tile[e.tile].local.insert(e)) {
      return true;
    }
    board_trace(current_time(), e.tile, BoardEvent::kEventLate, e.cycle, 0U);
  }
  if (!b.queue.push(e)) {
    board_trace(current_time(), e.tile, BoardEvent::kQueueFull, e.cycle, 0U);
    return false;
  }
  return true;
}

void deliver_due(Tile& t) noexcept {
  // The timer is the tile's own register, not a queued event: its expiry only sets the pending bit.
  // Like an event, an expiry at the quantum's end belongs to the next quantum.
  if (t.timer_period != 0U && t.timer_at <= t.time && t.timer_at < board().q_end) {
    t.timer_at += t.timer_period;
    if (powered(t)) {
      t.pending |= irq_bit(Irq::kTimer);
    }
  }
  for (std::size_t n = 0; n < 4U * kLocalEventCapacity; ++n) {
    if (t.local.empty() || t.local.front().cycle > t.time) {
      break;
    }
    const Event e = t.local.front();
    t.local.pop_front();
    deliver_one(t, e);
  }
  if (t.wd_armed && !t.wd_failed && t.wd_deadline <= t.time) {
    expire_watchdog(t);
  }
}

Cycles next_wake(const Tile& t) noexcept {
  Cycles next = ~Cycles{0};
  if (!t.local.empty()) {
    next = t.local.front().cycle;
  }
  if (t.timer_period != 0U && t.timer_at < next) {
    next = t.timer_at;
  }
  if (t.wd_armed && !t.wd_failed && t.wd_deadline < next) {
    next = t.wd_deadline;
  }
  if (t.power == PowerState::kBooting && t.boot_at < next) {
    next = t.boot_at;
  }
  return next;
}

void on_context_start() noexcept {
  Tile* t = running_tile();
  if (t != nullptr) {
    t->masked = false;  // a new context starts with interrupts enabled
  }
}

void on_context_return() noexcept {
  Tile* t = running_tile();
  if (t == nullptr) {
    __builtin_trap();  // a host-driven context returned: there is nothing to return to
  }
  t->stopped = true;
  board_trace(t->time, t->id, BoardEvent::kHalt, 0U, 0U);
  switch_abandon(board().host_ctx);
}

}  // namespace detail

TileId current_tile() noexcept { return detail::board().running; }

Cycles now() noexcept { return detail::current_time(); }

void consume(Cycles cycles) noexcept {
  detail::Tile* t = detail::running_tile();
  if (t == nullptr) {
    return;
  }
  const detail::Board& b = detail::board();
  Cycles remaining = cycles;
  for (std::uint64_t n = 0; n < detail::kMaxLoopSteps; ++n) {
    detail::service(*t);
    if (remaining == 0U) {
      return;
    }
    if (t->time >= b.q_end) {
      detail::yield_to_driver(*t);
      continue;
    }
    const Cycles wake = detail::next_wake(*t);
    const Cycles limit = wake < b.q_end ? wake : b.q_end;
    const Cycles room = limit > t->time ? limit - t->time : 0U;
    const Cycles step = remaining < room ? remaining : room;
    // Executing: active, even in a handler taken inside wait_for_interrupt() (the flag still says kIdle).
    detail::advance_to(*t, PowerState::kActive, t->time + step);
    t->stats.active_cycles += step;
    remaining -= step;
  }
}

void consume(const Work& work) noexcept { consume(cost_of(work)); }

Cycles cost_of(const Work& work) noexcept { return cost_of(detail::board().config.profile, work); }

void wait_for_interrupt() noexcept {
  detail::Tile* t = detail::running_tile();
  if (t == nullptr) {
    return;
  }
  const detail::Board& b = detail::board();
  for (std::uint64_t n = 0; n < detail::kMaxLoopSteps; ++n) {
    const std::uint64_t taken = t->stats.irqs_taken;
    detail::service(*t);
    if (t->stats.irqs_taken != taken || t->pending != 0U) {
      t->power = PowerState::kActive;  // woken: taken, or pending while masked
      return;
    }
    t->power = PowerState::kIdle;
    if (t->time >= b.q_end) {
      detail::yield_to_driver(*t);
      continue;
    }
    const Cycles wake = detail::next_wake(*t);
    detail::advance_to(*t, PowerState::kIdle, wake < b.q_end ? wake : b.q_end);
  }
}

void set_irq_handler(TileId tile, IrqHandler handler) noexcept {
  if (detail::valid_tile(tile)) {
    detail::board().tile[tile].handler = handler;
  }
}

void raise_irq(TileId tile, Irq irq) noexcept {
  if (!detail::valid_tile(tile) || irq >= Irq::kCount) {
    return;
  }
  detail::Board& b = detail::board();
  detail::Tile& d = b.tile[tile];
  if (b.in_barrier || tile == b.processing) {
    if (detail::powered(d)) {
      d.pending |= detail::irq_bit(irq);
    }
    return;
  }
  b.irq_deferred[tile] |= detail::irq_bit(irq);
}

bool mask_irqs(bool masked) noexcept {
  detail::Tile* t = detail::running_tile();
  if (t == nullptr) {
    return false;
  }
  const bool previous = t->masked;
  t->masked = masked;
  if (previous && !masked) {
    detail::dispatch(*t);  // as on hardware, a pending interrupt is taken at the unmask
  }
  return previous;
}

void timer_start(Cycles period) noexcept {
  detail::Tile* t = detail::running_tile();
  if (t == nullptr) {
    return;
  }
  t->timer_period = period;
  t->timer_at = t->time + period;
}

void timer_next(Cycles at) noexcept {
  detail::Tile* t = detail::running_tile();
  if (t == nullptr || t->timer_period == 0U) {
    return;
  }
  t->timer_at = at > t->time ? at : t->time;
}

void watchdog_arm(Cycles timeout, bool reset_on_expiry) noexcept {
  detail::Tile* t = detail::running_tile();
  if (t == nullptr) {
    return;
  }
  t->wd_timeout = timeout;
  t->wd_reset = reset_on_expiry;
  t->wd_armed = timeout != 0U;
  t->wd_deadline = t->time + timeout;
}

void watchdog_kick() noexcept {
  detail::Tile* t = detail::running_tile();
  if (t == nullptr || t->wd_timeout == 0U) {
    return;
  }
  t->wd_armed = true;
  t->wd_deadline = t->time + t->wd_timeout;
}

std::uint64_t watchdog_take_expired() noexcept {
  detail::Board& b = detail::board();
  const std::uint64_t expired = b.wd_expired;
  b.wd_expired = 0U;
  return expired;
}

BootCause boot_cause() noexcept {
  const detail::Tile* t = detail::running_tile();
  return t == nullptr ? BootCause::kPowerOn : t->boot_cause;
}

std::uint32_t boot_count() noexcept {
  const detail::Tile* t = detail::running_tile();
  return t == nullptr ? 0U : t->stats.boots;
}

void trace(std::uint16_t kind, std::uint64_t a, std::uint64_t b) noexcept {
  trace_record(detail::current_time(), detail::board().running, kind, a, b);
}

Cycles tick_cycles() noexcept { return detail::board().config.tick_cycles; }

TileId tile_count() noexcept { return detail::board().tiles; }

}  // namespace bsp
