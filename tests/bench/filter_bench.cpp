/**
 * @file filter_bench.cpp
 * @brief Navigation filter cost: host time per propagation and per landmark update (one match,
 *        a batch of 150), the counted work, and that work in TILE64 cycles from the board's cost model.
 *
 * Run: make build/bench/filter_bench && build/bench/filter_bench
 * Counters: flops, fdivs per iteration as counted by the filter (bsp::Work);
 * tile64_cycles = bsp::cost_of(bsp::kTile64, work) (48 cycles per soft-float
 * add/mul, 200 per divide/sqrt, 2 per memory word: bsp_tile64/profile.hpp);
 * tile64_ms = those cycles at 700 MHz. The update benchmarks restore the
 * pre-update state each iteration (a 2 KB copy, BM_FilterRestore) so every
 * iteration sees the same covariance.
 */
#include "bsp_tile64/cost_model.hpp"
#include "bsp_tile64/profile.hpp"
#include "tests/trn/filter/truth_sim.hpp"
#include "trn/filter/ekf.hpp"
#include "trn/filter/nav_output.hpp"
#include "trn/filter/state_block.hpp"

#include <benchmark/benchmark.h>

#include <array>
#include <cstdint>

namespace {

trn::filter::Ekf g_ekf;
trn::filter::FilterState g_saved;
std::array<bsp::ImuSample, 1000> g_imu{};
std::array<trn::Match, trn::kMaxMatchesPerFrame> g_matches{};

/** A filter 5 s into a descent, with 150 fresh matches ready. */
void setup() {
  const bsp::CameraModel cam{};
  trn::filter::FilterConfig cfg;
  (void)g_ekf.configure(cfg, cam);
  filter_test::TruthSim truth(61, true, cfg.imu);
  bsp::Rng rng(61, bsp::StreamId::kTest, 10);
  (void)g_ekf.init(filter_test::perturbed_estimate(truth, rng, 50.0, 0.5, 2e-3));
  for (std::size_t i = 0; i < g_imu.size(); ++i) {
    g_imu[i] = truth.next_imu();
    if (i < 500U) {
      (void)g_ekf.propagate(g_imu[i]);
    }
    if (i + 1U == 500U) {  // the image is taken at the filter's time
      truth.make_matches(rng, cam, static_cast<int>(g_matches.size()), 0.5, g_matches.data());
    }
  }
  g_saved = g_ekf.state();
  (void)g_ekf.take_work();
}

void report(benchmark::State& st, const bsp::Work& w, std::uint64_t iters) {
  const double n = static_cast<double>(iters);
  const bsp::Work per{w.int_ops / iters, w.int_macs / iters, w.flops / iters, w.fdivs / iters, w.mem_words / iters};
  const double cycles = static_cast<double>(bsp::cost_of(bsp::kTile64, per));
  st.counters["flops"] = static_cast<double>(w.flops) / n;
  st.counters["fdivs"] = static_cast<double>(w.fdivs) / n;
  st.counters["tile64_cycles"] = cycles;
  st.counters["tile64_ms"] = cycles / static_cast<double>(bsp::kTile64.cycles_per_ms());
}

void BM_FilterPropagate(benchmark::State& st) {
  setup();
  std::size_t k = 500;
  for (auto _ : st) {
    benchmark::DoNotOptimize(g_ekf.propagate(g_imu[k]));
    k = k + 1 < g_imu.size() ? k + 1 : 500;
  }
  report(st, g_ekf.take_work(), static_cast<std::uint64_t>(st.iterations()));
}
BENCHMARK(BM_FilterPropagate);

void BM_FilterRestore(benchmark::State& st) {
  setup();
  for (auto _ : st) {
    benchmark::DoNotOptimize(g_ekf.restore(g_saved));
  }
}
BENCHMARK(BM_FilterRestore);

void bench_update(benchmark::State& st, std::uint32_t n) {
  setup();
  trn::filter::UpdateReport rep;
  std::uint64_t accepted = 0;
  for (auto _ : st) {
    (void)g_ekf.restore(g_saved);
    benchmark::DoNotOptimize(g_ekf.update(g_matches.data(), n, rep));
    accepted += rep.accepted;
  }
  const auto iters = static_cast<std::uint64_t>(st.iterations());
  report(st, g_ekf.take_work(), iters);
  st.counters["accepted"] = static_cast<double>(accepted) / static_cast<double>(iters);
}

void BM_FilterUpdateOneMatch(benchmark::State& st) { bench_update(st, 1U); }
BENCHMARK(BM_FilterUpdateOneMatch);

void BM_FilterUpdateBatch150(benchmark::State& st) { bench_update(st, 150U); }
BENCHMARK(BM_FilterUpdateBatch150);

void BM_FilterStateBlockAndOutput(benchmark::State& st) {
  setup();
  static trn::filter::StateBlock block;
  trn::filter::NavOutputBytes out{};
  for (auto _ : st) {
    benchmark::DoNotOptimize(trn::filter::write_state_block(g_ekf.state(), block));
    trn::filter::write_nav_output(trn::filter::make_nav_output(g_ekf.state(), g_ekf.config()), out);
    benchmark::DoNotOptimize(out.data());
  }
}
BENCHMARK(BM_FilterStateBlockAndOutput);

}  // namespace

BENCHMARK_MAIN();
