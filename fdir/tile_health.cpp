/**
 * @file tile_health.cpp
 * @brief The health agent of every tile and the tile-health supervisor (see tile_health.hpp).
 */
#include "fdir/tile_health.hpp"

#include "bsp_tile64/board.hpp"
#include "bsp_tile64/memory.hpp"
#include "fdir/event_log.hpp"
#include "fdir/health_table.hpp"
#include "kernel/kernel.hpp"
#include "udn/endpoint.hpp"

#include <array>
#include <new>

namespace fdir {
namespace {

// ------------------------------------------------------------------ agent

/** Ticks of the watched task furthest past its budget; 0 when all are within. */
struct Overdue {
  k::TaskId task = k::kNoTask;
  std::uint32_t late = 0U;
  std::uint32_t budget = 0U;
};

Overdue find_overdue(bsp::TileId self, k::Ticks now) noexcept {
  Overdue o{};
  const std::uint32_t n = k::task_count(self);
  for (std::uint32_t i = 0; i < n && i < k::config::kMaxTasks; ++i) {
    k::TaskStats st{};
    if (k::task_stats(self, static_cast<k::TaskId>(i), &st) != k::Status::kOk || st.watch_ticks == 0U) {
      continue;
    }
    const k::Ticks since = now >= st.last_checkin ? now - st.last_checkin : 0U;
    if (since > st.watch_ticks && since - st.watch_ticks > o.late) {
      o.task = static_cast<k::TaskId>(i);
      o.late = static_cast<std::uint32_t>(since - st.watch_ticks);
      o.budget = st.watch_ticks;
    }
  }
  return o;
}

// ------------------------------------------------------------------ supervisor

struct State {
  k::Semaphore expired{0, 1};  ///< given by the watchdog interrupt
  MonitorSpec spec{};
  std::array<MonitorState, bsp::kMaxTiles> wd{};
  std::array<k::Ticks, bsp::kMaxTiles> reset_at{};
  std::uint64_t booted = 0U;  ///< tiles that reported a boot at least once
  TileHealthView view{};
};

std::array<State*, bsp::kMaxTiles> g_state{};

void watchdog_isr(bsp::TileId tile) noexcept {
  if (tile < bsp::kMaxTiles && g_state[tile] != nullptr) {
    (void)g_state[tile]->expired.give_from_isr();
  }
}

constexpr std::uint64_t bit(bsp::TileId t) noexcept { return 1ULL << t; }

std::uint32_t ms_since(k::Ticks then) noexcept {
  const k::Ticks now = k::now_ticks();
  const k::Ticks d = now >= then ? now - then : 0U;
  const bsp::Cycles per_ms = bsp::kTile64.cycles_per_ms();
  const bsp::Cycles cycles = static_cast<bsp::Cycles>(d) * bsp::tick_cycles();
  return static_cast<std::uint32_t>(per_ms == 0U ? d : cycles / per_ms);
}

void on_expired(State& s, const TileHealthConfig& cfg, bsp::TileId self, bsp::TileId t) noexcept {
  ++s.view.expiries;
  report(EventId::kWatchdogExpired, t, 0U, s.view.expiries);
  if (t == self || (cfg.watched & bit(t)) == 0ULL || (s.view.pending & bit(t)) != 0ULL) {
    return;  // its own (the hardware resets it), not ours, or already being reset
  }
  const MonitorResult r = monitor_sample(s.spec, s.wd[t], t, 1U);
  if (!r.act) {
    return;  // past the cap: the tile is left as it is (kActionCapped was written)
  }
  if (bsp::reset_tile(t) != bsp::BoardError::kOk) {
    report(EventId::kTileLost, t, 1U);
    return;
  }
  ++s.view.resets;
  s.view.pending |= bit(t);
  s.reset_at[t] = k::now_ticks();
  report(EventId::kTileReset, t, 0U, s.wd[t].actions, s.spec.max_actions);
}

void on_booted(State& s, bsp::TileId t, std::uint32_t cause) noexcept {
  if ((s.view.pending & bit(t)) != 0ULL) {
    s.view.pending &= ~bit(t);
    ++s.view.recovered;
    monitor_clear(s.wd[t]);
    report(EventId::kTileRecovered, t, cause, ms_since(s.reset_at[t]));
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
      ++s.view.lost;
      report(EventId::kTileLost, t, 0U, ms_since(s.reset_at[t]));
    }
  }
}

}  // namespace

void health_agent_main(void* arg) noexcept {
  const auto* cfg = static_cast<const HealthAgentConfig*>(arg);
  const bsp::TileId self = bsp::current_tile();
  if (cfg == nullptr || self >= bsp::kMaxTiles || cfg->watchdog_ticks < 2U * kAgentPeriodTicks) {
    return;  // no kicks: the hardware watchdog is never armed, the neighbours' probes still see the tile
  }
  const bsp::BootCause cause = bsp::boot_cause();
  // The supervisor's own tile has nobody above it: its watchdog resets it.
  const bool own_supervisor = cfg->supervisor == self;
  bsp::watchdog_arm(static_cast<bsp::Cycles>(cfg->watchdog_ticks) * bsp::tick_cycles(), own_supervisor);
  bool reported = cfg->supervisor == bsp::kNoTile || own_supervisor;
  bool overdue_written = false;
  const std::array<std::uint32_t, kBootedWords> boot{kMsgBooted, self, static_cast<std::uint32_t>(cause)};
  for (;;) {
    const Overdue o = find_overdue(self, k::now_ticks());
    if (o.task == k::kNoTask) {
      bsp::watchdog_kick();
      overdue_written = false;
    } else if (!overdue_written) {
      report(EventId::kTaskOverdue, o.task, self, o.late, o.budget);
      overdue_written = true;
    }
    if (!reported && udn::endpoint_ready()) {
      reported = udn::endpoint_send(cfg->supervisor, udn::kFtChanHealth, boot, 0U) == udn::FtError::kOk;
    }
    (void)k::wait_period();
  }
}

void tile_health_task_main(void* arg) noexcept {
  const auto* cfg = static_cast<const TileHealthConfig*>(arg);
  const bsp::TileId self = bsp::current_tile();
  if (cfg == nullptr || self >= bsp::kMaxTiles || cfg->max_resets == 0U || cfg->poll_ticks == 0U) {
    return;
  }
  g_state[self] = nullptr;
  bsp::MemError err = bsp::MemError::kOk;
  auto* s = bsp::carve_array<State>(bsp::Region{self}, 1, "tile_health", &err);
  if (err != bsp::MemError::kOk || s == nullptr) {
    return;
  }
  ::new (s) State{};
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
  s->booted |= bit(self);
  udn::FtMessage m{};
  for (;;) {
    (void)s->expired.take(k::Timeout{cfg->poll_ticks});
    const std::uint64_t expired = bsp::watchdog_take_expired();
    for (bsp::TileId t = 0; t < bsp::kMaxTiles; ++t) {
      if ((expired & bit(t)) != 0ULL) {
        on_expired(*s, *cfg, self, t);
      }
    }
    for (std::uint32_t i = 0;
         i < udn::kFtRxDepth && udn::endpoint_receive(udn::kFtChanHealth, m) == udn::FtError::kOk; ++i) {
      if (m.data_words == kBootedWords && m.data[0] == kMsgBooted && m.data[1] == m.source &&
          m.source < bsp::kMaxTiles) {
        on_booted(*s, m.source, m.data[2]);
      }
    }
    check_timeouts(*s, *cfg);
    k::checkin();
  }
}

TileHealthView tile_health_view(bsp::TileId tile) noexcept {
  if (tile >= bsp::kMaxTiles || g_state[tile] == nullptr) {
    return TileHealthView{};
  }
  return g_state[tile]->view;
}

}  // namespace fdir
