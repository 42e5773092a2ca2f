/**
 * @file kernel_bench.cpp
 * @brief Host cost of the kernel: a context switch, an idle tile tick, and 64 tiles
 *        running a typical periodic load (emulated seconds per host second).
 */
#include "bsp_tile64/emu/board.hpp"
#include "kernel/kernel.hpp"

#include <benchmark/benchmark.h>

namespace {

constexpr bsp::Cycles kTick = bsp::kTile64.cycles_per_ms();
constexpr std::uint32_t kStack = 16U * 1024U;

void boot_all(k::TaskTable table, std::uint32_t tiles) {
  bsp::BoardConfig cfg = bsp::default_config(bsp::kTile64);
  cfg.powered_at_start = (tiles >= 64U) ? ~0ULL : ((1ULL << tiles) - 1U);
  cfg.monitor_tile = bsp::kNoTile;
  for (std::uint32_t t = 0; t < tiles; ++t) {
    cfg.boot[t] = &k::boot_entry;
    k::set_task_table(t, table, kTick);
  }
  if (bsp::board_init(cfg) != bsp::BoardError::kOk) {
    std::abort();
  }
}

void ping(void*) {
  for (;;) {
    bsp::consume(70);  // 0.1 us of work between switches
    k::yield();
  }
}

/** Two equal-priority tasks yielding to each other: each yield is one switch. */
void BM_ContextSwitch(benchmark::State& state) {
  static constexpr k::TaskSpec kTable[] = {
      {"a", &ping, nullptr, 3, 0, 0, kStack, k::Policy::kCooperative},
      {"b", &ping, nullptr, 3, 0, 0, kStack, k::Policy::kCooperative},
  };
  boot_all(kTable, 1);
  (void)bsp::run_for(2 * kTick);  // boot
  std::uint64_t before = 0;
  k::TaskStats s{};
  (void)k::task_stats(0, 0, &s);
  before = s.activations;
  for (auto _ : state) {
    (void)bsp::run_for(kTick);  // 10000 switches per emulated ms
  }
  (void)k::task_stats(0, 0, &s);
  state.counters["switches_per_s"] =
      benchmark::Counter(static_cast<double>(2U * (s.activations - before)), benchmark::Counter::kIsRate);
}

void sleeper(void*) {
  for (;;) {
    k::sleep(1000);
  }
}

/** One emulated second of 64 tiles whose kernels only tick (idle task). */
void BM_IdleTilesEmulatedSecond(benchmark::State& state) {
  static constexpr k::TaskSpec kTable[] = {
      {"sleep", &sleeper, nullptr, 3, 0, 0, kStack, k::Policy::kPreemptive},
  };
  for (auto _ : state) {
    boot_all(kTable, 64);
    (void)bsp::run_for(1000 * kTick);
  }
  state.counters["tile_ticks_per_s"] =
      benchmark::Counter(64.0 * 1000.0 * static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
}

void periodic_load(void*) {
  for (;;) {
    bsp::consume(3 * kTick);  // 30% of a 10 ms period
    (void)k::wait_period();
  }
}

void background_load(void*) {
  for (;;) {
    bsp::consume(kTick / 2);
    k::sleep(5);
  }
}

/** 64 tiles, each with a 100 Hz task at 30% load and a background task: emulated s per host s. */
void BM_PeriodicLoad64Tiles(benchmark::State& state) {
  static constexpr k::TaskSpec kTable[] = {
      {"periodic", &periodic_load, nullptr, 2, 10, 10, kStack, k::Policy::kPreemptive},
      {"bg", &background_load, nullptr, 5, 0, 0, kStack, k::Policy::kPreemptive},
  };
  for (auto _ : state) {
    boot_all(kTable, 64);
    (void)bsp::run_for(1000 * kTick);
  }
  state.counters["emulated_s_per_host_s"] =
      benchmark::Counter(static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
}

}  // namespace

BENCHMARK(BM_ContextSwitch)->Unit(benchmark::kMillisecond)->Iterations(20);
BENCHMARK(BM_IdleTilesEmulatedSecond)->Unit(benchmark::kMillisecond)->Iterations(3);
BENCHMARK(BM_PeriodicLoad64Tiles)->Unit(benchmark::kMillisecond)->Iterations(3);
BENCHMARK_MAIN();
