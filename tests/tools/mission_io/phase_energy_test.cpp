/**
 * @file phase_energy_test.cpp
 * @brief Energy per phase (tools/common/mission/phase_energy.*): boundaries snapshotted at their cycle, phases that
 *        add up to the flight exactly, runs cut at boundaries that emulate as one, bad windows refused,
 *        and the summary's energy figures.
 */
#include "tools/common/mission/phase_energy.hpp"

#include "bsp_tile64/emu/board.hpp"
#include "bsp_tile64/emu/energy.hpp"
#include "bsp_tile64/api/port.hpp"
#include "bsp_tile64/api/power.hpp"
#include "bsp_tile64/emu/trace.hpp"
#include "tests/support/heap_probe.hpp"
#include "tools/common/mission/run_folder.hpp"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <utility>
#include <vector>

namespace {

constexpr bsp::Cycles kQuantum = 1000U;
constexpr bsp::Cycles kStep = 7000U;  ///< the host's step: not a divisor of the boundaries
constexpr bsp::Cycles kEnd = 49'000U;
constexpr std::uint32_t kTiles = 64U;

double seconds(bsp::Cycles c) { return static_cast<double>(c) / static_cast<double>(bsp::kTile64.clock_hz); }

void tick_work(bsp::TileId /*tile*/, bsp::Irq /*irq*/) { bsp::consume(400U); }

void boot_ticking(bsp::TileId tile) {
  bsp::set_irq_handler(tile, tick_work);
  bsp::timer_start(1500U);
  for (;;) {
    bsp::wait_for_interrupt();
  }
}

void boot_busy(bsp::TileId /*tile*/) {
  for (;;) {
    bsp::consume(333U);
  }
}

/** Tiles 0, 1 and 3 take a tick with work, tile 2 works without a break; the rest stay off. */
void init_board() {
  bsp::BoardConfig c = bsp::default_config(bsp::kTile64);
  c.quantum_cycles = kQuantum;
  c.tick_cycles = 10U * kQuantum;
  c.boot_delay_cycles = 100U;
  c.powered_at_start = 0b1111U;
  c.boot[0] = boot_ticking;
  c.boot[1] = boot_ticking;
  c.boot[2] = boot_busy;
  c.boot[3] = boot_ticking;
  c.seed = 11U;
  ASSERT_EQ(bsp::board_init(c), bsp::BoardError::kOk);
}

/** Starts 0, 12 300 (rounds to 12 000), 31 700 (rounds to 32 000) and one after the end of the flight. */
std::vector<tools::PhaseWindow> windows() {
  return {{"cruise", 0.0}, {"approach", seconds(12'300U)}, {"landing", seconds(31'700U)}, {"after", 1.0}};
}

/** The host's action during the flight: tile 3 is switched off after the step that ends at 21 000. */
void host_action(bsp::Cycles now) {
  if (now == 21'000U) {
    ASSERT_EQ(bsp::power_off(3U), bsp::BoardError::kOk);
  }
}

/** Flies to kEnd in host steps of kStep, cut at the phase boundaries; finishes the meter. */
void fly_with_phases(tools::PhaseEnergy& e) {
  for (bsp::Cycles target = kStep; target <= kEnd; target += kStep) {
    EXPECT_EQ(tools::run_with_phases(target, e).reason, bsp::StopReason::kTimeReached);
    host_action(bsp::board_time());
  }
  e.finish(bsp::board_time());
}

tools::PhaseEnergy init_meter() {
  tools::PhaseEnergy e;
  std::string error;
  EXPECT_TRUE(e.init(windows(), bsp::power_model(), kQuantum, kTiles, error)) << error;
  return e;
}

// TOOLS-EN-01: each boundary is snapshotted at its cycle (the start rounded to the quantum), a phase after
// the end of the flight is empty.
TEST(PhaseEnergy, BoundariesAreSnapshotAtTheirCycle) {
  init_board();
  tools::PhaseEnergy e = init_meter();
  fly_with_phases(e);
  ASSERT_EQ(e.phases(), 4U);
  EXPECT_TRUE(e.finished());
  const std::array<bsp::Cycles, 3> starts{0U, 12'000U, 32'000U};
  for (std::size_t p = 0; p < starts.size(); ++p) {
    EXPECT_EQ(e.start_cycle(p), starts[p]) << e.window(p).name;
    EXPECT_EQ(e.taken_cycle(p), starts[p]) << e.window(p).name;
  }
  EXPECT_EQ(e.start_cycle(3), bsp::kTile64.clock_hz);
  EXPECT_EQ(e.taken_cycle(3), kEnd) << "not reached: closed at the end";
  for (bsp::TileId t = 0; t < kTiles; ++t) {
    EXPECT_EQ(e.tile_cycles(3, t).total(), 0U);
    EXPECT_EQ(e.tile_cycles(0, t).total(), 12'000U) << "every tile's phase is as long as the phase";
    EXPECT_EQ(e.tile_cycles(1, t).total(), 20'000U);
    EXPECT_EQ(e.tile_cycles(2, t).total(), kEnd - 32'000U);
  }
  EXPECT_EQ(e.tile_cycles(2, 3U).off, kEnd - 32'000U) << "tile 3 is off for the whole landing";
  EXPECT_EQ(e.tile_cycles(2, 2U).active, kEnd - 32'000U) << "tile 2 works all along";
  EXPECT_EQ(e.phase_j(3), 0.0);
}

// TOOLS-EN-02: the phases' cycles add up to the flight's exactly, per tile and state; their joules to the chip's.
TEST(PhaseEnergy, PhasesAddUpToTheFlight) {
  init_board();
  tools::PhaseEnergy e = init_meter();
  fly_with_phases(e);
  double phases_j = 0.0;
  for (std::size_t p = 0; p < e.phases(); ++p) {
    phases_j += e.phase_j(p);
  }
  for (bsp::TileId t = 0; t < kTiles; ++t) {
    bsp::StateCycles sum{0U, 0U, 0U, 0U};
    double tile_j = 0.0;
    for (std::size_t p = 0; p < e.phases(); ++p) {
      const bsp::StateCycles c = e.tile_cycles(p, t);
      sum = bsp::StateCycles{sum.off + c.off, sum.booting + c.booting, sum.idle + c.idle, sum.active + c.active};
      tile_j += e.tile_j(p, t);
    }
    const bsp::TileEnergy whole = bsp::tile_energy(t);
    EXPECT_EQ(sum.off, whole.cycles.off) << t;
    EXPECT_EQ(sum.booting, whole.cycles.booting) << t;
    EXPECT_EQ(sum.idle, whole.cycles.idle) << t;
    EXPECT_EQ(sum.active, whole.cycles.active) << t;
    EXPECT_NEAR(tile_j, whole.joules, whole.joules * 1e-12) << t;
  }
  EXPECT_GT(e.phase_j(1), 0.0);
  EXPECT_NEAR(phases_j, bsp::chip_energy_j(), bsp::chip_energy_j() * 1e-12);
}

// TOOLS-EN-03: cutting the runs at the boundaries changes nothing in the emulation (trace hash, meters).
TEST(PhaseEnergy, CutRunsEmulateAsOne) {
  init_board();
  tools::PhaseEnergy e = init_meter();
  fly_with_phases(e);
  const std::uint64_t cut_hash = bsp::trace_hash();
  std::array<bsp::StateCycles, kTiles> cut{};
  for (bsp::TileId t = 0; t < kTiles; ++t) {
    cut[t] = bsp::tile_energy(t).cycles;
  }
  init_board();
  for (bsp::Cycles target = kStep; target <= kEnd; target += kStep) {
    (void)bsp::run_for(target - bsp::board_time());
    host_action(bsp::board_time());
  }
  EXPECT_EQ(bsp::trace_hash(), cut_hash);
  for (bsp::TileId t = 0; t < kTiles; ++t) {
    EXPECT_EQ(bsp::tile_energy(t).cycles.active, cut[t].active) << t;
    EXPECT_EQ(bsp::tile_energy(t).cycles.idle, cut[t].idle) << t;
    EXPECT_EQ(bsp::tile_energy(t).cycles.off, cut[t].off) << t;
  }
}

// TOOLS-EN-04: a caller that steps over a boundary gets the snapshot at the end of that step; step() allocates nothing.
TEST(PhaseEnergy, AStepOverABoundarySnapshotsAtItsEnd) {
  init_board();
  tools::PhaseEnergy e = init_meter();
  std::uint64_t allocs = 0U;
  for (bsp::Cycles target = kStep; target <= kEnd; target += kStep) {
    (void)bsp::run_for(target - bsp::board_time());
    allocs += test_support::count_allocs([&e] { e.step(bsp::board_time()); });
  }
  allocs += test_support::count_allocs([&e] { e.finish(bsp::board_time()); });
  EXPECT_EQ(allocs, 0U);
  EXPECT_EQ(e.taken_cycle(1), 14'000U) << "the first step end at or after 12 000";
  EXPECT_EQ(e.taken_cycle(2), 35'000U);
  EXPECT_EQ(e.tile_cycles(0, 5U).total(), 14'000U);
}

// TOOLS-EN-05: windows that cannot be phases are refused with a reason.
TEST(PhaseEnergy, BadWindowsAreRefused) {
  const bsp::PowerModel m = bsp::power_model_for(bsp::kTile64);
  const auto refused = [&m](std::vector<tools::PhaseWindow> w, const std::string& why) {
    tools::PhaseEnergy e;
    std::string error;
    EXPECT_FALSE(e.init(std::move(w), m, kQuantum, kTiles, error)) << why;
    EXPECT_NE(error.find(why), std::string::npos) << error;
  };
  refused({}, "none given");
  refused({{"late", 1.0}}, "must start at 0 s");
  refused({{"a", 0.0}, {"a", 1.0}}, "used twice");
  refused({{"a", 0.0}, {"", 1.0}}, "no name");
  refused({{"a", 0.0}, {"b", std::numeric_limits<double>::quiet_NaN()}}, "not a time");
  refused({{"a", 0.0}, {"b", seconds(400U)}}, "does not start at least one quantum after 'a'");
  refused({{"a", 0.0}, {"b", 2.0}, {"c", 1.0}}, "does not start at least one quantum after 'b'");
  tools::PhaseEnergy e;
  std::string error;
  EXPECT_FALSE(e.init({{"a", 0.0}}, m, 0U, kTiles, error));
  EXPECT_TRUE(e.init({{"descent", 0.0}}, m, kQuantum, kTiles, error)) << error;
  EXPECT_EQ(e.next_boundary(0U), std::numeric_limits<bsp::Cycles>::max()) << "one phase: nothing to stop at";
}

// TOOLS-EN-06: the summary's energy figures: the chip's total, its mean power, by phase, role and state.
TEST(PhaseEnergy, SummaryFiguresAddUp) {
  init_board();
  tools::PhaseEnergy e = init_meter();
  fly_with_phases(e);
  std::vector<std::string> roles(kTiles, "spare");
  roles[0] = "io";
  roles[1] = "vision";
  roles[2] = "vision";
  tools::Summary s;
  tools::add_energy_summary(e, roles, seconds(kEnd), s);
  std::string json;
  std::string error;
  ASSERT_TRUE(tools::summary_json(s, json, error)) << error;
  const double total = bsp::chip_energy_j();
  ASSERT_EQ(s.extra.size(), 2U);
  EXPECT_EQ(s.extra[0], std::make_pair(std::string("energy_j"), total));
  EXPECT_EQ(s.extra[1].first, "mean_power_w");
  EXPECT_DOUBLE_EQ(s.extra[1].second, total / seconds(kEnd));
  ASSERT_EQ(s.objects.size(), 3U);
  const auto sum_of = [](const std::vector<std::pair<std::string, double>>& v) {
    double x = 0.0;
    for (const auto& kv : v) {
      x += kv.second;
    }
    return x;
  };
  EXPECT_EQ(s.objects[0].first, "energy_j_by_phase");
  ASSERT_EQ(s.objects[0].second.size(), 4U);
  EXPECT_EQ(s.objects[0].second[1].first, "approach");
  EXPECT_NEAR(sum_of(s.objects[0].second), total, total * 1e-12);
  EXPECT_EQ(s.objects[1].first, "energy_j_by_role");
  ASSERT_EQ(s.objects[1].second.size(), 3U) << "io, vision, spare: in order of first appearance";
  EXPECT_EQ(s.objects[1].second[1].first, "vision");
  EXPECT_NEAR(s.objects[1].second[1].second, bsp::tile_energy(1).joules + bsp::tile_energy(2).joules, 1e-15);
  EXPECT_NEAR(sum_of(s.objects[1].second), total, total * 1e-12);
  EXPECT_EQ(s.objects[2].first, "energy_j_by_state");
  EXPECT_NEAR(sum_of(s.objects[2].second), total, total * 1e-12);
  EXPECT_GT(s.objects[2].second[0].second, 0.0) << "the switches of the tiles that are off";
}

}  // namespace
