/**
 * @file board_test.cpp
 * @brief The deterministic driver: boot delay, timers, watchdog, power, barriers, events, determinism.
 */
#include "bsp_tile64/emu/board.hpp"

#include "board_fixture.hpp"
#include "bsp_tile64/faults/fault_injector.hpp"
#include "bsp_tile64/api/memory.hpp"
#include "bsp_tile64/api/port.hpp"
#include "bsp_tile64/emu/stack_paint.hpp"
#include "bsp_tile64/emu/trace.hpp"

#include <gtest/gtest.h>

#include <array>
#include <cstdint>
#include <span>
#include <vector>

namespace {

using board_test::idle_forever;
using board_test::kBootDelay;
using board_test::small_config;
using bsp::Cycles;
using bsp::TileId;

std::array<Cycles, bsp::kMaxTiles> g_boot_time{};
std::array<std::vector<Cycles>, bsp::kMaxTiles> g_irq_times{};
std::array<std::vector<bsp::Irq>, bsp::kMaxTiles> g_irq_kinds{};
std::uint64_t g_expired_seen = 0U;

void reset_records() {
  g_boot_time.fill(~Cycles{0});
  for (auto& v : g_irq_times) {
    v.clear();
  }
  for (auto& v : g_irq_kinds) {
    v.clear();
  }
  g_expired_seen = 0U;
}

void record_irq(TileId tile, bsp::Irq irq) {
  g_irq_times[tile].push_back(bsp::now());
  g_irq_kinds[tile].push_back(irq);
  if (irq == bsp::Irq::kWatchdog) {
    g_expired_seen |= bsp::watchdog_take_expired();
  }
}

void boot_idle(TileId tile) {
  g_boot_time[tile] = bsp::now();
  bsp::set_irq_handler(tile, record_irq);
  idle_forever();
}

TEST(Board, RejectsBadConfigurations) {
  bsp::BoardConfig c = small_config();
  c.quantum_cycles = c.tick_cycles + 1U;
  EXPECT_EQ(bsp::board_init(c), bsp::BoardError::kBadConfig);
  c = small_config();
  c.quantum_cycles = 0U;
  EXPECT_EQ(bsp::board_init(c), bsp::BoardError::kBadConfig);
  c = small_config();
  c.boot_stack_bytes = 1024U;
  EXPECT_EQ(bsp::board_init(c), bsp::BoardError::kBadConfig);
  c = bsp::default_config(bsp::kMaestro);
  c.monitor_tile = 49U;
  EXPECT_EQ(bsp::board_init(c), bsp::BoardError::kBadConfig);
  c.monitor_tile = 48U;
  EXPECT_EQ(bsp::board_init(c), bsp::BoardError::kOk);
  EXPECT_EQ(bsp::tile_count(), 49U);
  EXPECT_EQ(bsp::tick_cycles(), 342'000U);
}

TEST(Board, TileRunsOnlyAfterItsBootDelay) {
  reset_records();
  bsp::BoardConfig c = small_config();
  c.powered_at_start = 1ULL << 3U;
  c.boot[3] = boot_idle;
  c.boot[5] = boot_idle;
  ASSERT_EQ(bsp::board_init(c), bsp::BoardError::kOk);
  EXPECT_EQ(bsp::power_state(3), bsp::PowerState::kBooting);
  bsp::run_for(99U);
  EXPECT_EQ(g_boot_time[3], ~Cycles{0}) << "ran before its boot delay";
  EXPECT_EQ(bsp::power_state(3), bsp::PowerState::kBooting);
  bsp::run_for(2000U - 99U);
  EXPECT_EQ(g_boot_time[3], 100U);
  EXPECT_EQ(bsp::power_state(3), bsp::PowerState::kIdle);
  EXPECT_EQ(g_boot_time[5], ~Cycles{0}) << "tile 5 is off";
  EXPECT_EQ(bsp::power_state(5), bsp::PowerState::kOff);
  ASSERT_EQ(bsp::power_on(5), bsp::BoardError::kOk);  // at 2000
  bsp::run_for(2000U);
  EXPECT_EQ(g_boot_time[5], 2100U);
  EXPECT_EQ(bsp::tile_stats(5).boots, 1U);
  EXPECT_EQ(bsp::tile_time(5), 4000U);
}

void boot_timer(TileId tile) {
  g_boot_time[tile] = bsp::now();
  bsp::set_irq_handler(tile, record_irq);
  bsp::timer_start(700U);
  if (tile == 1U) {
    bsp::consume(100'000U);  // busy: the timer interrupts the work at its exact cycles
  }
  idle_forever();
}

TEST(Board, TimerFiresAtExactCyclesIdleOrBusy) {
  reset_records();
  bsp::BoardConfig c = small_config();
  c.powered_at_start = 0b11U;
  c.boot[0] = boot_timer;
  c.boot[1] = boot_timer;
  ASSERT_EQ(bsp::board_init(c), bsp::BoardError::kOk);
  bsp::run_for(5000U);
  const std::vector<Cycles> expected{800U, 1500U, 2200U, 2900U, 3600U, 4300U};
  EXPECT_EQ(g_irq_times[0], expected);
  EXPECT_EQ(g_irq_times[1], expected);
  EXPECT_EQ(bsp::tile_stats(0).irqs_taken, 6U);
  EXPECT_EQ(bsp::tile_stats(1).active_cycles, 4900U);  // busy from 100 to 5000
  EXPECT_EQ(bsp::tile_stats(0).active_cycles, 0U);
}

void boot_watchdog_unkicked(TileId tile) {
  bsp::watchdog_arm(3000U, false);
  boot_idle(tile);
}

void boot_watchdog_kicked(TileId tile) {
  bsp::watchdog_arm(3000U, false);
  for (int i = 0; i < 100; ++i) {
    bsp::consume(1000U);
    bsp::watchdog_kick();
  }
  boot_idle(tile);
}

TEST(Board, UnkickedWatchdogExpiresAtItsCycleAndIsReported) {
  reset_records();
  bsp::BoardConfig c = small_config();
  c.monitor_tile = 0U;
  c.powered_at_start = 0b1101U;
  c.boot[0] = boot_idle;
  c.boot[2] = boot_watchdog_unkicked;
  c.boot[3] = boot_watchdog_kicked;
  ASSERT_EQ(bsp::board_init(c), bsp::BoardError::kOk);
  bsp::run_for(50'000U);
  const auto expired = board_test::events_of(bsp::BoardEvent::kWatchdogExpired);
  ASSERT_EQ(expired.size(), 1U);
  EXPECT_EQ(expired[0].tile, 2U);
  EXPECT_EQ(expired[0].time, 3100U);  // armed at boot (100) + 3000
  EXPECT_EQ(bsp::tile_stats(2).watchdog_expiries, 1U);
  EXPECT_EQ(bsp::tile_stats(3).watchdog_expiries, 0U) << "a kicked watchdog expired";
  // The monitor learns of it at the next barrier (4000), as for every cross-tile effect.
  ASSERT_EQ(g_irq_times[0].size(), 1U);
  EXPECT_EQ(g_irq_times[0][0], 4000U);
  EXPECT_EQ(g_irq_kinds[0][0], bsp::Irq::kWatchdog);
  EXPECT_EQ(g_expired_seen, 1ULL << 2U);
}

void boot_takes_monitor(TileId tile) {
  bsp::consume(200U);
  bsp::watchdog_monitor_select();  // effective at the next barrier (1000)
  boot_idle(tile);
}

TEST(Board, AWatchdogMonitorSelectMovesTheInterruptLineAtTheNextBarrier) {
  reset_records();
  bsp::BoardConfig c = small_config();
  c.monitor_tile = 0U;
  c.powered_at_start = 0b1111U;
  c.boot[0] = boot_idle;
  c.boot[1] = boot_takes_monitor;
  c.boot[2] = boot_watchdog_unkicked;
  c.boot[3] = boot_idle;
  ASSERT_EQ(bsp::board_init(c), bsp::BoardError::kOk);
  EXPECT_EQ(bsp::watchdog_monitor(), 0U);
  bsp::run_for(50'000U);
  EXPECT_EQ(bsp::watchdog_monitor(), 1U);
  const auto selects = board_test::events_of(bsp::BoardEvent::kMonitorSelect);
  ASSERT_EQ(selects.size(), 1U);
  EXPECT_EQ(selects[0].tile, 1U);
  EXPECT_EQ(selects[0].a, 0U) << "the tile before";
  // Tile 2's expiry (3100) reaches the new monitor at the barrier after it; the old one hears nothing.
  ASSERT_EQ(g_irq_times[1].size(), 1U);
  EXPECT_EQ(g_irq_times[1][0], 4000U);
  EXPECT_EQ(g_irq_kinds[1][0], bsp::Irq::kWatchdog);
  EXPECT_TRUE(g_irq_times[0].empty());
}

void boot_watchdog_reset(TileId tile) {
  g_boot_time[tile] = bsp::now();
  bsp::watchdog_arm(2000U, true);
  idle_forever();
}

TEST(Board, WatchdogWithResetRebootsTheTileAfterTheBootDelay) {
  reset_records();
  bsp::BoardConfig c = small_config();
  c.monitor_tile = bsp::kNoTile;
  c.powered_at_start = 1U;
  c.boot[0] = boot_watchdog_reset;
  ASSERT_EQ(bsp::board_init(c), bsp::BoardError::kOk);
  bsp::run_for(5000U);
  // boot 100, expire 2100, boot 2200, expire 4200, boot 4300
  EXPECT_EQ(bsp::tile_stats(0).boots, 3U);
  EXPECT_EQ(bsp::tile_stats(0).resets, 2U);
  EXPECT_EQ(g_boot_time[0], 4300U);
  const auto resets = board_test::events_of(bsp::BoardEvent::kReset, 0U);
  ASSERT_EQ(resets.size(), 2U);
  EXPECT_EQ(resets[0].time, 2100U);
  EXPECT_EQ(resets[1].time, 4200U);
}

std::array<std::uint32_t, bsp::kMaxTiles> g_progress{};

void boot_kicker(TileId /*tile*/) {
  bsp::watchdog_arm(3000U, false);
  for (int i = 0; i < 1000; ++i) {
    bsp::consume(500U);
    bsp::watchdog_kick();
    ++g_progress[bsp::current_tile()];
  }
  idle_forever();
}

TEST(Board, HungTileStopsAndItsWatchdogSeesIt) {
  g_progress.fill(0U);
  bsp::BoardConfig c = small_config();
  c.powered_at_start = 0b10U;
  c.boot[1] = boot_kicker;
  ASSERT_EQ(bsp::board_init(c), bsp::BoardError::kOk);
  bsp::run_for(5000U);
  EXPECT_EQ(g_progress[1], 9U);  // kicks at 600 .. 4600
  ASSERT_EQ(bsp::hang_tile(1), bsp::BoardError::kOk);
  EXPECT_TRUE(bsp::tile_stopped(1));
  bsp::run_for(10'000U);
  EXPECT_EQ(g_progress[1], 9U) << "a hung tile made progress";
  EXPECT_EQ(bsp::tile_time(1), 15'000U) << "its clock keeps running";
  const auto expired = board_test::events_of(bsp::BoardEvent::kWatchdogExpired, 1U);
  ASSERT_EQ(expired.size(), 1U);
  EXPECT_EQ(expired[0].time, 7600U);  // last kick 4600 + 3000
}

void boot_raiser(TileId /*tile*/) {
  bsp::consume(250U);
  bsp::raise_irq(1U, bsp::Irq::kSoft);  // another tile: visible at the next barrier
  bsp::raise_irq(0U, bsp::Irq::kSoft);  // itself: pending at once
  bsp::set_irq_handler(0U, record_irq);
  bsp::consume(0U);
  idle_forever();
}

TEST(Board, CrossTileInterruptIsVisibleAtTheNextBarrierOnly) {
  reset_records();
  bsp::BoardConfig c = small_config();
  c.powered_at_start = 0b11U;
  c.boot[0] = boot_raiser;
  c.boot[1] = boot_idle;
  ASSERT_EQ(bsp::board_init(c), bsp::BoardError::kOk);
  bsp::run_for(3000U);
  ASSERT_EQ(g_irq_times[0].size(), 1U);
  EXPECT_EQ(g_irq_times[0][0], 350U);
  ASSERT_EQ(g_irq_times[1].size(), 1U);
  EXPECT_EQ(g_irq_times[1][0], 1000U);
  EXPECT_EQ(g_irq_kinds[1][0], bsp::Irq::kSoft);
}

std::vector<std::pair<Cycles, std::uint64_t>> g_callbacks;

void device_callback(TileId /*tile*/, Cycles cycle, std::uint64_t arg) { g_callbacks.emplace_back(cycle, arg); }

TEST(Board, ScheduledDeviceEventRaisesItsIrqAtTheExactCycle) {
  reset_records();
  g_callbacks.clear();
  bsp::BoardConfig c = small_config();
  c.powered_at_start = 1ULL << 4U;
  c.boot[4] = boot_idle;
  ASSERT_EQ(bsp::board_init(c), bsp::BoardError::kOk);
  ASSERT_EQ(bsp::schedule_event(2345U, 4U, bsp::Irq::kDevice, device_callback, 7U), bsp::BoardError::kOk);
  ASSERT_EQ(bsp::schedule_event(2345U, 4U, bsp::Irq::kCount, device_callback, 8U), bsp::BoardError::kOk);
  EXPECT_EQ(bsp::schedule_event(1U, 64U, bsp::Irq::kDevice, nullptr, 0U), bsp::BoardError::kBadTile);
  bsp::run_for(4000U);
  ASSERT_EQ(g_callbacks.size(), 2U);
  EXPECT_EQ(g_callbacks[0], std::make_pair(Cycles{2345U}, std::uint64_t{7U}));
  EXPECT_EQ(g_callbacks[1], std::make_pair(Cycles{2345U}, std::uint64_t{8U}));
  ASSERT_EQ(g_irq_times[4].size(), 1U);
  EXPECT_EQ(g_irq_times[4][0], 2345U);
  EXPECT_EQ(g_irq_kinds[4][0], bsp::Irq::kDevice);
}

std::vector<Cycles> g_hook_a;
std::vector<Cycles> g_hook_b;
void hook_a(Cycles at) { g_hook_a.push_back(at); }
void hook_b(Cycles at) {
  EXPECT_EQ(g_hook_a.size(), g_hook_b.size() + 1U) << "hooks run in registration order";
  g_hook_b.push_back(at);
}

TEST(Board, BarrierHooksRunAtEveryBarrierInOrder) {
  g_hook_a.clear();
  g_hook_b.clear();
  ASSERT_EQ(bsp::board_init(small_config()), bsp::BoardError::kOk);
  ASSERT_EQ(bsp::add_barrier_hook(hook_a), bsp::BoardError::kOk);
  ASSERT_EQ(bsp::add_barrier_hook(hook_b), bsp::BoardError::kOk);
  bsp::run_for(2500U);
  bsp::run_for(500U);
  const std::vector<Cycles> expected{0U, 1000U, 2000U, 2500U};
  EXPECT_EQ(g_hook_a, expected);
  EXPECT_EQ(g_hook_b, expected);
  for (std::size_t i = 2; i < bsp::kMaxBarrierHooks; ++i) {
    EXPECT_EQ(bsp::add_barrier_hook(hook_a), bsp::BoardError::kOk);
  }
  EXPECT_EQ(bsp::add_barrier_hook(hook_a), bsp::BoardError::kFull);
}

void boot_long_work(TileId tile) {
  bsp::consume(2500U);  // crosses two quantum ends
  g_boot_time[tile] = bsp::now();
  idle_forever();
}

TEST(Board, WorkCrossingQuantumEndsResumesAndFinishesExactly) {
  reset_records();
  bsp::BoardConfig c = small_config();
  c.powered_at_start = 1U;
  c.boot[0] = boot_long_work;
  ASSERT_EQ(bsp::board_init(c), bsp::BoardError::kOk);
  bsp::run_for(1500U);
  EXPECT_EQ(bsp::tile_time(0), 1500U);
  EXPECT_EQ(g_boot_time[0], ~Cycles{0});
  bsp::run_for(1500U);
  EXPECT_EQ(g_boot_time[0], 2600U);
}

bool stop_after_2500(void* /*arg*/) { return bsp::board_time() >= 2500U; }

TEST(Board, RunUntilStopsAtTheFirstBarrierWhereThePredicateHolds) {
  ASSERT_EQ(bsp::board_init(small_config()), bsp::BoardError::kOk);
  const bsp::RunResult r = bsp::run_until(stop_after_2500, nullptr, 1'000'000U);
  EXPECT_EQ(r.reason, bsp::StopReason::kPredicate);
  EXPECT_EQ(r.end_cycle, 3000U);
  bsp::request_stop();
  const bsp::RunResult s = bsp::run_until(nullptr, nullptr, 1'000'000U);
  EXPECT_EQ(s.reason, bsp::StopReason::kRequested);
  EXPECT_EQ(s.end_cycle, 3000U);
  const bsp::RunResult t = bsp::run_until(nullptr, nullptr, 1234U);
  EXPECT_EQ(t.reason, bsp::StopReason::kTimeReached);
  EXPECT_EQ(t.end_cycle, 4234U);
}

void boot_power_cycle(TileId tile) {
  ++g_progress[tile];
  if (tile == 0U) {
    bsp::consume(50U);
    bsp::power_off(1U);  // from a tile: applied at the next barrier
  }
  idle_forever();
}

TEST(Board, PowerOffFromATileTakesEffectAtTheBarrierAndPowerOnBootsAgain) {
  g_progress.fill(0U);
  bsp::BoardConfig c = small_config();
  c.powered_at_start = 0b11U;
  c.boot[0] = boot_power_cycle;
  c.boot[1] = boot_power_cycle;
  ASSERT_EQ(bsp::board_init(c), bsp::BoardError::kOk);
  bsp::run_for(2000U);  // tile 0 asks at 150; the barrier at 1000 applies it
  EXPECT_EQ(bsp::power_state(1), bsp::PowerState::kOff);
  EXPECT_EQ(bsp::region_used(bsp::Region{1}), 0U) << "switching off loses the RAM";
  ASSERT_EQ(bsp::power_on(1), bsp::BoardError::kOk);
  bsp::run_for(1000U);
  EXPECT_EQ(g_progress[1], 2U);
  EXPECT_EQ(bsp::tile_stats(1).boots, 2U);
  EXPECT_EQ(board_test::events_of(bsp::BoardEvent::kPowerOff, 1U).at(0).time, 1000U);
}

// ---------------------------------------------------------------- bare programs on every tile

constexpr std::size_t kProgStackBytes = std::size_t{16U} * 1024U;
std::array<TileId, bsp::kMaxTiles> g_tile_ids{};
constexpr int kProgIterations = 50;
std::array<bsp::Context, bsp::kMaxTiles> g_boot_save{};
std::array<bsp::Context, bsp::kMaxTiles> g_prog_ctx{};
std::array<std::byte*, bsp::kMaxTiles> g_prog_stack{};
std::array<Cycles, bsp::kMaxTiles> g_prog_done{};
std::array<std::uint32_t, bsp::kMaxTiles> g_prog_sum{};

void bare_program(void* arg) {
  const TileId tile = *static_cast<const TileId*>(arg);
  for (int i = 0; i < kProgIterations; ++i) {
    std::array<std::uint32_t, 512> scratch{};  // 2 KiB of real stack use
    for (std::size_t k = 0; k < scratch.size(); ++k) {
      scratch[k] = static_cast<std::uint32_t>(k * tile + static_cast<std::uint32_t>(i));
    }
    std::uint32_t sum = 0U;
    for (const std::uint32_t v : scratch) {
      sum += v;
    }
    g_prog_sum[tile] += sum;
    bsp::consume(1000U + tile);
  }
  g_prog_done[tile] = bsp::now();
  idle_forever();
}

void boot_bare(TileId tile) {
  const bsp::Carve c = bsp::carve(bsp::Region{tile}, kProgStackBytes, 16U, "program stack");
  if (c.error != bsp::MemError::kOk) {
    return;  // the test sees g_prog_done unset
  }
  bsp::stack_paint({c.ptr, kProgStackBytes});
  g_prog_stack[tile] = c.ptr;
  g_tile_ids[tile] = tile;
  bsp::context_init(g_prog_ctx[tile], c.ptr, kProgStackBytes, bare_program, &g_tile_ids[tile]);
  bsp::context_switch(g_boot_save[tile], g_prog_ctx[tile]);
}

TEST(Board, BareProgramOnItsOwnStackRunsOnAll64TilesWithMeasuredStackUse) {
  g_prog_done.fill(0U);
  g_prog_sum.fill(0U);
  bsp::BoardConfig c = small_config();
  c.powered_at_start = ~0ULL;
  for (auto& e : c.boot) {
    e = boot_bare;
  }
  ASSERT_EQ(bsp::board_init(c), bsp::BoardError::kOk);
  bsp::run_for(200'000U);
  for (TileId t = 0; t < 64U; ++t) {
    SCOPED_TRACE(t);
    EXPECT_EQ(g_prog_done[t], kBootDelay + Cycles{kProgIterations} * (1000U + t));
    std::uint32_t expect = 0U;
    for (int i = 0; i < kProgIterations; ++i) {
      for (std::uint32_t k = 0; k < 512U; ++k) {
        expect += k * t + static_cast<std::uint32_t>(i);
      }
    }
    EXPECT_EQ(g_prog_sum[t], expect);
    const std::size_t used = bsp::stack_high_water({g_prog_stack[t], kProgStackBytes});
    EXPECT_GT(used, 2048U) << "the 2 KiB scratch array lives on the program stack";
    EXPECT_LT(used, kProgStackBytes);
    EXPECT_GT(bsp::boot_stack_high_water(t), 0U);
    EXPECT_LT(bsp::boot_stack_high_water(t), c.boot_stack_bytes);
  }
}

// ---------------------------------------------------------------- determinism

void boot_busy(TileId tile) {
  bsp::set_irq_handler(tile, [](TileId t, bsp::Irq /*irq*/) {
    bsp::trace(bsp::kTraceKernelBase, t, bsp::now());
    bsp::raise_irq((t + 1U) % bsp::tile_count(), bsp::Irq::kSoft);
  });
  bsp::MemError err = bsp::MemError::kOk;
  auto* data = bsp::carve_array<std::uint32_t>(bsp::Region{tile}, 256U, "data", &err);
  bsp::timer_start(3000U + 17U * tile);
  bsp::watchdog_arm(20'000U, true);
  for (std::uint32_t i = 0;; ++i) {
    bsp::Work w{};
    w.int_ops = 100U + (i * 7U + tile) % 300U;
    w.flops = (data != nullptr) ? data[i % 256U] % 5U : 1U;
    bsp::consume(w);
    bsp::watchdog_kick();
  }
}

struct RunSummary {
  std::uint64_t hash;
  std::uint64_t events;
  std::size_t faults;
};

RunSummary run_busy_board(std::uint64_t seed) {
  bsp::BoardConfig c = small_config();
  c.seed = seed;
  c.powered_at_start = ~0ULL;
  for (auto& e : c.boot) {
    e = boot_busy;
  }
  EXPECT_EQ(bsp::board_init(c), bsp::BoardError::kOk);
  EXPECT_EQ(bsp::fault_set_rate(bsp::FaultKind::kSeu, 2000.0), bsp::FaultError::kOk);
  EXPECT_EQ(bsp::fault_set_rate(bsp::FaultKind::kCoreReset, 300.0), bsp::FaultError::kOk);
  EXPECT_EQ(bsp::fault_set_rate(bsp::FaultKind::kCoreHang, 100.0), bsp::FaultError::kOk);
  bsp::run_for(700'000U);
  return {bsp::trace_hash(), bsp::trace_count(), bsp::fault_log().size()};
}

TEST(Board, SameConfigAndSeedGiveTheSameTraceHashAndAnotherSeedChangesIt) {
  const RunSummary a = run_busy_board(42U);
  const RunSummary b = run_busy_board(42U);
  const RunSummary other = run_busy_board(43U);
  EXPECT_EQ(a.hash, b.hash);
  EXPECT_EQ(a.events, b.events);
  EXPECT_GT(a.events, 1000U) << "the run did real work";
  EXPECT_GT(a.faults, 50U) << "random faults were injected";
  EXPECT_NE(a.hash, other.hash);
}

}  // namespace

namespace {

std::array<Cycles, bsp::kMaxTiles> g_fpu_done{};

void boot_fpu(TileId tile) {
  bsp::Work w{};
  w.flops = 100U;
  bsp::consume(w);
  g_fpu_done[tile] = bsp::now();
  idle_forever();
}

TEST(Board, MaestroProfileRunsAll49TilesWithItsFpuCosts) {
  g_fpu_done.fill(0U);
  bsp::BoardConfig c = bsp::default_config(bsp::kMaestro);
  c.boot_delay_cycles = kBootDelay;
  c.boot.fill(boot_fpu);
  ASSERT_EQ(bsp::board_init(c), bsp::BoardError::kOk);
  EXPECT_EQ(bsp::power_on(49U), bsp::BoardError::kBadTile);
  bsp::run_for(bsp::kMaestro.cycles_per_ms());
  for (TileId t = 0; t < 49U; ++t) {
    EXPECT_EQ(g_fpu_done[t], kBootDelay + 300U) << "tile " << t;  // 100 flops x 3 cycles
  }
  for (TileId t = 49U; t < bsp::kMaxTiles; ++t) {
    EXPECT_EQ(g_fpu_done[t], 0U) << "tile " << t << " is outside the 7x7 grid";
  }
}

}  // namespace
