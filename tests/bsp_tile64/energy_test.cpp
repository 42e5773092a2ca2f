/**
 * @file energy_test.cpp
 * @brief The energy meter (BSP-EN-01..06): per-state cycles are exact and add up to the tile's time,
 *        joules follow the documented power model, power-off stops the core's share, a reset boots again.
 */
#include "bsp_tile64/emu/energy.hpp"

#include "board_fixture.hpp"
#include "bsp_tile64/emu/board.hpp"
#include "bsp_tile64/api/memory.hpp"
#include "bsp_tile64/api/port.hpp"
#include "bsp_tile64/api/power.hpp"

#include <gtest/gtest.h>

#include <cstddef>
#include <cstdint>

namespace {

using board_test::idle_forever;
using board_test::kBootDelay;
using board_test::small_config;
using bsp::Cycles;
using bsp::TileId;

// The documented model at the TILE64's 700 MHz, written out here (docs/BOARD.md), not read from the code.
constexpr double kClockHz = 700e6;
constexpr double kOffW = 0.010;         // the switch alone
constexpr double kActiveW = 0.2025;     // a whole tile: 170 + 130 * (700 - 600) / 400 mW
constexpr double kIdleW = 0.058125;     // switch + a quarter of the core's 192.5 mW
constexpr double kBootingW = kActiveW;  // booting draws the active power

double expected_j(Cycles off, Cycles booting, Cycles idle, Cycles active) {
  return (static_cast<double>(off) * kOffW + static_cast<double>(booting) * kBootingW +
          static_cast<double>(idle) * kIdleW + static_cast<double>(active) * kActiveW) /
         kClockHz;
}

/** Every tile of the grid: its per-state cycles sum to its time exactly. */
void expect_every_tile_adds_up() {
  for (TileId t = 0; t < bsp::tile_count(); ++t) {
    EXPECT_EQ(bsp::tile_energy(t).cycles.total(), bsp::tile_time(t)) << "tile " << t;
  }
}

void boot_work_then_idle(TileId /*tile*/) {
  bsp::consume(1234U);
  idle_forever();
}

// BSP-EN-01: a tile off, booted, active then idle: each state's cycles are exact and add up.
TEST(Energy, OffBootingActiveIdleCyclesAreExactAndAddUp) {
  bsp::BoardConfig c = small_config();
  c.boot[3] = boot_work_then_idle;
  ASSERT_EQ(bsp::board_init(c), bsp::BoardError::kOk);
  bsp::run_for(2000U);
  ASSERT_EQ(bsp::power_on(3), bsp::BoardError::kOk);  // at 2000: boots at 2100, works to 3334
  bsp::run_for(4000U);
  const bsp::TileEnergy e = bsp::tile_energy(3);
  EXPECT_EQ(e.cycles.off, 2000U);
  EXPECT_EQ(e.cycles.booting, kBootDelay);
  EXPECT_EQ(e.cycles.active, 1234U);
  EXPECT_EQ(e.cycles.idle, 6000U - 2000U - kBootDelay - 1234U);
  EXPECT_EQ(e.cycles.total(), 6000U);
  EXPECT_DOUBLE_EQ(e.joules, expected_j(2000U, kBootDelay, 6000U - 3334U, 1234U));
  expect_every_tile_adds_up();
  // A tile never switched on spent every cycle off: its switch's energy only.
  EXPECT_EQ(bsp::tile_energy(5).cycles.off, 6000U);
  EXPECT_DOUBLE_EQ(bsp::tile_energy(5).joules, expected_j(6000U, 0U, 0U, 0U));
}

// BSP-EN-02: the model's numbers are the documented ones and follow the board's profile.
TEST(Energy, ModelConstantsAreTheDocumentedOnes) {
  ASSERT_EQ(bsp::board_init(small_config()), bsp::BoardError::kOk);
  const bsp::PowerModel m = bsp::power_model();
  EXPECT_EQ(m.clock_hz, 700'000'000U);
  EXPECT_EQ(m.tile_active_uw, 202'500U);
  EXPECT_EQ(m.switch_uw, 10'000U);
  EXPECT_EQ(m.core_active_uw, 192'500U);
  EXPECT_EQ(m.core_idle_uw, 48'125U);
  EXPECT_EQ(m.core_booting_uw, 192'500U);
  EXPECT_EQ(m.core_off_uw, 0U);
  EXPECT_EQ(bsp::tile_uw(m, bsp::PowerState::kOff), 10'000U);
  EXPECT_EQ(bsp::tile_uw(m, bsp::PowerState::kIdle), 58'125U);
  // The band's ends, and below it proportional to the clock (the Maestro's 342 MHz).
  EXPECT_EQ(bsp::tile_active_uw_at(600'000'000U), 170'000U);
  EXPECT_EQ(bsp::tile_active_uw_at(1'000'000'000U), 300'000U);
  EXPECT_EQ(bsp::tile_active_uw_at(342'000'000U), 96'900U);
  EXPECT_EQ(bsp::tile_active_uw_at(1'200'000'000U), 360'000U);
  ASSERT_EQ(bsp::board_init(bsp::default_config(bsp::kMaestro)), bsp::BoardError::kOk);
  EXPECT_EQ(bsp::power_model().clock_hz, 342'000'000U);
  EXPECT_EQ(bsp::power_model().tile_active_uw, 96'900U);
}

void boot_busy(TileId /*tile*/) {
  for (;;) {
    bsp::consume(333U);
  }
}

// BSP-EN-03: switching a tile off stops its core's energy; its switch goes on drawing.
TEST(Energy, SwitchingOffStopsTheCoresEnergy) {
  bsp::BoardConfig c = small_config();
  c.powered_at_start = 1ULL << 7U;
  c.boot[7] = boot_busy;
  ASSERT_EQ(bsp::board_init(c), bsp::BoardError::kOk);
  bsp::run_for(3000U);
  const bsp::TileEnergy on = bsp::tile_energy(7);
  EXPECT_EQ(on.cycles.active, 3000U - kBootDelay);
  ASSERT_EQ(bsp::power_off(7), bsp::BoardError::kOk);
  bsp::run_for(5000U);
  const bsp::TileEnergy off = bsp::tile_energy(7);
  EXPECT_EQ(bsp::power_state(7), bsp::PowerState::kOff);
  EXPECT_EQ(off.cycles.active, on.cycles.active) << "no core cycle after the switch-off";
  EXPECT_EQ(off.cycles.off, 5000U);
  EXPECT_NEAR(off.joules - on.joules, 5000.0 * kOffW / kClockHz, 1e-18) << "the switch's share only";
  expect_every_tile_adds_up();
}

void boot_unkicked_reset(TileId /*tile*/) {
  bsp::watchdog_arm(500U, true);  // never kicked: a reset 500 cycles after every boot
  idle_forever();
}

// BSP-EN-04: a reset, commanded or by the watchdog at its exact cycle, passes through booting for the boot delay.
TEST(Energy, AResetPassesThroughBooting) {
  bsp::BoardConfig c = small_config();
  c.powered_at_start = 1ULL << 2U;
  c.boot[2] = boot_unkicked_reset;
  ASSERT_EQ(bsp::board_init(c), bsp::BoardError::kOk);
  // Boots at 100, 700, 1300, 1900, 2500: reset at 600, 1200, 1800, 2400.
  bsp::run_for(2950U);
  EXPECT_EQ(bsp::tile_stats(2).resets, 4U);
  const bsp::TileEnergy w = bsp::tile_energy(2);
  EXPECT_EQ(w.cycles.booting, 5U * kBootDelay);
  EXPECT_EQ(w.cycles.idle, 2950U - 5U * kBootDelay);
  EXPECT_EQ(w.cycles.active, 0U);
  EXPECT_EQ(w.cycles.off, 0U);
  // A reset commanded from the host at 2950 acts at once: booting from there.
  ASSERT_EQ(bsp::reset_tile(2), bsp::BoardError::kOk);
  EXPECT_EQ(bsp::power_state(2), bsp::PowerState::kBooting);
  bsp::run_for(60U);
  EXPECT_EQ(bsp::tile_stats(2).resets, 5U);
  EXPECT_EQ(bsp::tile_energy(2).cycles.booting, 5U * kBootDelay + 60U);
  EXPECT_EQ(bsp::tile_energy(2).cycles.idle, w.cycles.idle);
  expect_every_tile_adds_up();
}

void take_tick_with_work(TileId /*tile*/, bsp::Irq /*irq*/) { bsp::consume(100U); }

void boot_ticking(TileId tile) {
  bsp::set_irq_handler(tile, take_tick_with_work);
  bsp::timer_start(700U);
  idle_forever();
}

// BSP-EN-05: work done in a handler taken inside wait_for_interrupt() is active, the waiting idle.
TEST(Energy, HandlerWorkInsideWaitIsActive) {
  bsp::BoardConfig c = small_config();
  c.powered_at_start = 1ULL << 4U;
  c.boot[4] = boot_ticking;
  ASSERT_EQ(bsp::board_init(c), bsp::BoardError::kOk);
  bsp::run_for(5000U);  // ticks at 800, 1500, 2200, 2900, 3600, 4300
  const bsp::TileEnergy e = bsp::tile_energy(4);
  EXPECT_EQ(e.cycles.active, 6U * 100U);
  EXPECT_EQ(e.cycles.active, bsp::tile_stats(4).active_cycles);
  EXPECT_EQ(e.cycles.idle, 5000U - kBootDelay - 600U);
  EXPECT_EQ(e.cycles.booting, kBootDelay);
}

bsp::Context g_waiting{};  // the boot context, saved where its handler switches away
bsp::Context g_worker{};
bool g_switched = false;
Cycles g_worker_done = 0U;
constexpr std::size_t kWorkerStackBytes = std::size_t{16U} * 1024U;

void worker_main(void* /*arg*/) {
  bsp::consume(2500U);
  g_worker_done = bsp::now();
  bsp::context_switch(g_worker, g_waiting);  // back into the handler, which returns into the wait
  idle_forever();
}

void switch_once(TileId /*tile*/, bsp::Irq /*irq*/) {
  if (!g_switched) {
    g_switched = true;
    bsp::context_switch(g_waiting, g_worker);
  }
}

void boot_wait_then_work(TileId tile) {
  const bsp::Carve c = bsp::carve(bsp::Region{tile}, kWorkerStackBytes, 16U, "worker stack");
  ASSERT_EQ(c.error, bsp::MemError::kOk);
  bsp::context_init(g_worker, c.ptr, kWorkerStackBytes, worker_main, nullptr);
  bsp::set_irq_handler(tile, switch_once);
  bsp::timer_start(700U);
  idle_forever();
}

// BSP-EN-05: a context an interrupt taken in wait_for_interrupt() switches to is active, as the kernel's tasks are.
TEST(Energy, AContextSwitchedToFromAWaitIsActive) {
  g_switched = false;
  g_worker_done = 0U;
  bsp::BoardConfig c = small_config();
  c.powered_at_start = 1ULL << 8U;
  c.boot[8] = boot_wait_then_work;
  ASSERT_EQ(bsp::board_init(c), bsp::BoardError::kOk);
  bsp::run_for(2000U);  // the first tick (800) switches to the worker: it works from 800 to 3300
  EXPECT_EQ(bsp::metered_state(8), bsp::PowerState::kActive) << "the worker is inside consume()";
  bsp::run_for(3000U);
  EXPECT_EQ(g_worker_done, 3300U);
  EXPECT_EQ(bsp::metered_state(8), bsp::PowerState::kIdle);
  const bsp::TileEnergy e = bsp::tile_energy(8);
  EXPECT_EQ(e.cycles.active, 2500U);
  EXPECT_EQ(e.cycles.idle, 5000U - kBootDelay - 2500U);
  EXPECT_EQ(bsp::metered_state(9), bsp::PowerState::kOff);
  ASSERT_EQ(bsp::power_on(9), bsp::BoardError::kOk);
  EXPECT_EQ(bsp::metered_state(9), bsp::PowerState::kBooting);
}

// BSP-EN-06: a hung core keeps its clock: charged active until it is reset; the chip is the sum of its tiles.
TEST(Energy, AHungCoreIsChargedActiveAndTheChipIsTheSumOfItsTiles) {
  bsp::BoardConfig c = small_config();
  c.powered_at_start = (1ULL << 1U) | (1ULL << 6U);
  c.boot[1] = boot_busy;
  c.boot[6] = boot_work_then_idle;
  ASSERT_EQ(bsp::board_init(c), bsp::BoardError::kOk);
  bsp::run_for(2000U);
  ASSERT_EQ(bsp::hang_tile(1), bsp::BoardError::kOk);
  bsp::run_for(3000U);
  EXPECT_TRUE(bsp::tile_stopped(1));
  EXPECT_EQ(bsp::tile_energy(1).cycles.active, 5000U - kBootDelay);
  EXPECT_LT(bsp::tile_stats(1).active_cycles, 5000U - kBootDelay) << "consume() stopped at the hang";
  double sum = 0.0;
  for (TileId t = 0; t < bsp::tile_count(); ++t) {
    sum += bsp::tile_energy(t).joules;
  }
  EXPECT_EQ(bsp::chip_energy_j(), sum) << "same terms, same order";
  const double expected = expected_j(62U * 5000U, 2U * kBootDelay, 5000U - kBootDelay - 1234U,
                                     1234U + 5000U - kBootDelay);
  EXPECT_NEAR(bsp::chip_energy_j(), expected, expected * 1e-12);
  EXPECT_EQ(bsp::tile_energy(bsp::kMaxTiles).joules, 0.0) << "a bad id has no meter";
  EXPECT_STREQ(bsp::power_state_name(bsp::PowerState::kBooting), "booting");
  expect_every_tile_adds_up();
}

}  // namespace
