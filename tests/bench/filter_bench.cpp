/**
 * @file filter_bench.cpp
 * @brief Navigation filter cost: host time per propagation and per landmark update (one match at
 *        the state's time, one measured 0.5 s earlier, a lagged batch of 150, a 100 Hz job of one
 *        propagation and 15 lagged matches), the counted work, and that work in TILE64 cycles.
 *
 * Run: make build/bench/filter_bench && build/bench/filter_bench
 * Counters: flops, fdivs per iteration as counted by the filter (bsp::Work);
 * tile64_cycles = bsp::cost_of(bsp::kTile64, work) (48 cycles per soft-float
 * add/mul, 200 per divide/sqrt, 2 per memory word: bsp_tile64/emu/profile.hpp);
 * tile64_ms = those cycles at 700 MHz. The update benchmarks restore the
 * pre-update state each iteration (an 18 KB copy with the pose history,
 * BM_FilterRestore, whose time is included) so every iteration sees the same
 * covariance.
 */
#include "bsp_tile64/emu/cost_model.hpp"
#include "bsp_tile64/emu/profile.hpp"
#include "tests/trn/filter/truth_sim.hpp"
#include "trn/filter/ekf.hpp"
#include "trn/filter/nav_output.hpp"
#include "trn/filter/state_block.hpp"

#include <benchmark/benchmark.h>

#include <array>
#include <cmath>
#include <cstdint>

namespace {

trn::filter::Ekf g_ekf;
trn::filter::FilterState g_saved;
std::array<bsp::ImuSample, 1000> g_imu{};
std::array<trn::Match, trn::kMaxMatchesPerFrame> g_matches{};  // taken at the state's time
std::array<trn::Match, trn::kMaxMatchesPerFrame> g_lagged{};   // taken 0.5 s before it
std::array<trn::Match, trn::kMaxMatchesPerFrame> g_fix{};      // an image at 4.5 s, applied at once (tight)
constexpr std::size_t kStateSample = 550;

/**
 * A filter 5.5 s into a descent; matches of an image at 5.0 s and of one at 5.5 s ready.
 * @p tight: an image at 4.5 s was applied (position sigma below a metre, the
 * flight's state after its first frames); otherwise none was (sigma ~50 m:
 * every match an iterated update, Ekf::position_loose(), as right after the fix).
 */
void setup(bool tight = true) {
  const bsp::CameraModel cam{};
  trn::filter::FilterConfig cfg;
  (void)g_ekf.configure(cfg, cam);
  filter_test::TruthSim truth(61, true, cfg.imu);
  bsp::Rng rng(61, bsp::StreamId::kTest, 10);
  (void)g_ekf.init(filter_test::perturbed_estimate(truth, rng, 50.0, 0.5, 2e-3));
  for (std::size_t i = 0; i < g_imu.size(); ++i) {
    g_imu[i] = truth.next_imu();
    if (i < kStateSample) {
      (void)g_ekf.propagate(g_imu[i]);
    }
    if (i + 1U == 450U && tight) {
      truth.make_matches(rng, cam, static_cast<int>(g_fix.size()), 0.5, g_fix.data());
      trn::filter::UpdateReport rep;
      (void)g_ekf.update(g_fix.data(), static_cast<std::uint32_t>(g_fix.size()), rep);
    }
    if (i + 1U == 500U) {
      truth.make_matches(rng, cam, static_cast<int>(g_lagged.size()), 0.5, g_lagged.data());
    }
    if (i + 1U == kStateSample) {
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
  std::size_t k = kStateSample;
  for (auto _ : st) {
    benchmark::DoNotOptimize(g_ekf.propagate(g_imu[k]));
    k = k + 1 < g_imu.size() ? k + 1 : kStateSample;
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

/** Restores the saved state, then (optionally) one propagation and @p n updates from @p m. */
void bench_update(benchmark::State& st, const trn::Match* m, std::uint32_t n, bool propagate, bool tight = true) {
  setup(tight);
  trn::filter::UpdateReport rep;
  std::uint64_t accepted = 0;
  for (auto _ : st) {
    (void)g_ekf.restore(g_saved);
    if (propagate) {
      benchmark::DoNotOptimize(g_ekf.propagate(g_imu[kStateSample]));
    }
    benchmark::DoNotOptimize(g_ekf.update(m, n, rep));
    accepted += rep.accepted;
  }
  const auto iters = static_cast<std::uint64_t>(st.iterations());
  report(st, g_ekf.take_work(), iters);
  st.counters["accepted"] = static_cast<double>(accepted) / static_cast<double>(iters);
  st.counters["pos_sigma_m"] = std::sqrt(g_saved.p(trn::filter::kIdxP, trn::filter::kIdxP));
}

void BM_FilterUpdateOneMatch(benchmark::State& st) { bench_update(st, g_matches.data(), 1U, false); }
BENCHMARK(BM_FilterUpdateOneMatch);

void BM_FilterUpdateOneLaggedMatch(benchmark::State& st) { bench_update(st, g_lagged.data(), 1U, false); }
BENCHMARK(BM_FilterUpdateOneLaggedMatch);

void BM_FilterUpdateLaggedBatch150(benchmark::State& st) { bench_update(st, g_lagged.data(), 150U, false); }
BENCHMARK(BM_FilterUpdateLaggedBatch150);

/** What one 100 Hz job of the filter task computes: a propagation and 15 lagged matches. */
void BM_FilterJobPropagateAnd15Lagged(benchmark::State& st) { bench_update(st, g_lagged.data(), 15U, true); }
BENCHMARK(BM_FilterJobPropagateAnd15Lagged);

/** The same job while the position is loose (no image applied yet): each match an iterated update. */
void BM_FilterJobPropagateAnd15LaggedLoose(benchmark::State& st) {
  bench_update(st, g_lagged.data(), 15U, true, false);
}
BENCHMARK(BM_FilterJobPropagateAnd15LaggedLoose);

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
