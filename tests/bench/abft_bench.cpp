/**
 * @file abft_bench.cpp
 * @brief Cost of a checked matrix product (fdir/abft.hpp) against the plain one, n x n times
 *        n x n for n = 15 (the filter's covariance), 21, 64 and 256: host time, and the counted
 *        work in TILE64 cycles.
 *
 * Run: make build/bench/abft_bench && build/bench/abft_bench
 * BM_PlainN: c = a b (Eigen's lazy product at the fixed sizes 15 and 21, its
 * blocked product at 64 and 256), work charged as 2 n^3 flops and 2 n^2 (2 + n)
 * memory words (every operand word read n times, the result written).
 * BM_CheckedN: the same product through fdir::abft_product (the product, the
 * references and tolerances from the operands, the check).
 * Counters: tile64_cycles per product (bsp::cost_of(bsp::kTile64, work)) and
 * overhead_pct, the checked product's emulated cycles over the plain one's.
 * The host overhead is the ratio of the two benchmarks' times.
 */
#include "bsp_tile64/cost_model.hpp"
#include "bsp_tile64/profile.hpp"
#include "fdir/abft.hpp"

#include <benchmark/benchmark.h>

#include <cstdint>
#include <random>

namespace {

/** Operands of an n x n product; dynamic (256 x 256 is past Eigen's fixed-size limit), sized once. */
struct Operands {
  Eigen::MatrixXd a;
  Eigen::MatrixXd b;
  Eigen::MatrixXd c;
  fdir::AbftSums<Eigen::Dynamic, Eigen::Dynamic, Eigen::Dynamic> s;
};

Operands make_operands(int n) {
  Operands o;
  o.a.resize(n, n);
  o.b.resize(n, n);
  o.c.resize(n, n);
  fdir::abft_resize(o.s, n, n, n);
  std::mt19937_64 rng(static_cast<std::uint64_t>(n));
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < n; ++j) {
      o.a(i, j) = u(rng) + (i == j ? 1.0 : 0.0);
      o.b(i, j) = u(rng) * 1e3;
    }
  }
  return o;
}

bsp::Work plain_work(int n_) {
  const auto n = static_cast<std::uint64_t>(n_);
  return bsp::Work{0U, 0U, 2U * n * n * n, 0U, 2U * n * n * (2U + n)};
}

/**
 * The fixed-size kernel the filter would use at n = 15 and 21 (Eigen picks
 * other code for fixed sizes), the dynamic one above that.
 */
template <int N>
void plain_fixed(benchmark::State& st) {
  static const Operands o = make_operands(N);  // the same values as the dynamic sizes get
  static const Eigen::Matrix<double, N, N> a = o.a;
  static const Eigen::Matrix<double, N, N> b = o.b;
  static Eigen::Matrix<double, N, N> c;
  for (auto _ : st) {
    c.noalias() = a.lazyProduct(b);
    benchmark::DoNotOptimize(c.data());
    benchmark::ClobberMemory();
  }
  st.counters["tile64_cycles"] = static_cast<double>(bsp::cost_of(bsp::kTile64, plain_work(N)));
}

template <int N>
void checked_fixed(benchmark::State& st) {
  static const Operands o = make_operands(N);  // the same values as the dynamic sizes get
  static const Eigen::Matrix<double, N, N> a = o.a;
  static const Eigen::Matrix<double, N, N> b = o.b;
  static Eigen::Matrix<double, N, N> c;
  static fdir::AbftSums<N, N, N> s{};
  bsp::Work w{};
  std::uint64_t iters = 0U;
  std::uint64_t bad = 0U;
  for (auto _ : st) {
    const fdir::AbftResult r = fdir::abft_product(a, b, c, fdir::AbftSite{}, fdir::AbftDense{}, s, w);
    bad += r.bad_rows + r.bad_cols;
    benchmark::DoNotOptimize(c.data());
    benchmark::ClobberMemory();
    ++iters;
  }
  const std::uint64_t k = iters == 0U ? 1U : iters;
  const bsp::Work per{w.int_ops / k, 0U, w.flops / k, 0U, w.mem_words / k};
  const double plain = static_cast<double>(bsp::cost_of(bsp::kTile64, plain_work(N)));
  const double check = static_cast<double>(bsp::cost_of(bsp::kTile64, per));
  st.counters["tile64_cycles"] = plain + check;
  st.counters["overhead_pct"] = 100.0 * check / plain;
  st.counters["false_alarms"] = static_cast<double>(bad);
}

void plain_dynamic(benchmark::State& st, int n) {
  static Operands o;
  o = make_operands(n);
  for (auto _ : st) {
    o.c.noalias() = o.a * o.b;  // Eigen's blocked product (GEMM): the fastest plain one at these sizes
    benchmark::DoNotOptimize(o.c.data());
    benchmark::ClobberMemory();
  }
  st.counters["tile64_cycles"] = static_cast<double>(bsp::cost_of(bsp::kTile64, plain_work(n)));
}

void checked_dynamic(benchmark::State& st, int n) {
  static Operands o;
  o = make_operands(n);
  bsp::Work w{};
  std::uint64_t iters = 0U;
  std::uint64_t bad = 0U;
  for (auto _ : st) {
    const fdir::AbftResult r = fdir::abft_product(
        o.a, o.b, o.c, fdir::AbftSite{}, [](const auto& a, const auto& b, auto& c) { c.noalias() = a * b; }, o.s, w);
    bad += r.bad_rows + r.bad_cols;
    benchmark::DoNotOptimize(o.c.data());
    benchmark::ClobberMemory();
    ++iters;
  }
  const std::uint64_t k = iters == 0U ? 1U : iters;
  const bsp::Work per{w.int_ops / k, 0U, w.flops / k, 0U, w.mem_words / k};
  const double plain = static_cast<double>(bsp::cost_of(bsp::kTile64, plain_work(n)));
  const double check = static_cast<double>(bsp::cost_of(bsp::kTile64, per));
  st.counters["tile64_cycles"] = plain + check;
  st.counters["overhead_pct"] = 100.0 * check / plain;
  st.counters["false_alarms"] = static_cast<double>(bad);
}

void BM_Plain15(benchmark::State& st) { plain_fixed<15>(st); }
void BM_Checked15(benchmark::State& st) { checked_fixed<15>(st); }
void BM_Plain21(benchmark::State& st) { plain_fixed<21>(st); }
void BM_Checked21(benchmark::State& st) { checked_fixed<21>(st); }
void BM_Plain64(benchmark::State& st) { plain_dynamic(st, 64); }
void BM_Checked64(benchmark::State& st) { checked_dynamic(st, 64); }
void BM_Plain256(benchmark::State& st) { plain_dynamic(st, 256); }
void BM_Checked256(benchmark::State& st) { checked_dynamic(st, 256); }
BENCHMARK(BM_Plain15);
BENCHMARK(BM_Checked15);
BENCHMARK(BM_Plain21);
BENCHMARK(BM_Checked21);
BENCHMARK(BM_Plain64);
BENCHMARK(BM_Checked64);
BENCHMARK(BM_Plain256);
BENCHMARK(BM_Checked256);

}  // namespace

BENCHMARK_MAIN();
