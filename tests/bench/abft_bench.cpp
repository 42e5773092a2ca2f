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
 *
 * Checked correlation (trn/vision/correlator.hpp), the same way:
 * BM_CorrelatePlain/T/W runs a T x T template over a W x W window as the
 * correlator did before its checks (statistics, integral image, surface,
 * peak); BM_CorrelateChecked/T/W runs correlate() (the same, the dot-product
 * checksum, the surface digest, the peak's nine scores computed again, and an
 * unarmed publication per dot product and per surface). 21/49: a fine search
 * of radius 14; 21/27: the refinement (radius 3); 64/256: the coarse stage.
 */
#include "bsp_tile64/emu/cost_model.hpp"
#include "bsp_tile64/emu/profile.hpp"
#include "fdir/abft.hpp"
#include "trn/vision/correlator.hpp"

#include <benchmark/benchmark.h>

#include <cstdint>
#include <random>
#include <vector>

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

template <int N, bool RowsOnly = false>
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
    const fdir::AbftResult r = fdir::abft_product(a, b, c, fdir::AbftSite{0U, 0U, RowsOnly}, fdir::AbftDense{}, s, w);
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

void checked_dynamic(benchmark::State& st, int n, bool rows_only = false) {
  static Operands o;
  o = make_operands(n);
  bsp::Work w{};
  std::uint64_t iters = 0U;
  std::uint64_t bad = 0U;
  for (auto _ : st) {
    const fdir::AbftResult r = fdir::abft_product(
        o.a, o.b, o.c, fdir::AbftSite{0U, 0U, rows_only}, [](const auto& a, const auto& b, auto& c) { c.noalias() = a * b; },
        o.s, w);
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
// Row checksums only (what the Kalman update uses): about half the check, the column not located.
void BM_RowsChecked15(benchmark::State& st) { checked_fixed<15, true>(st); }
void BM_RowsChecked21(benchmark::State& st) { checked_fixed<21, true>(st); }
void BM_RowsChecked64(benchmark::State& st) { checked_dynamic(st, 64, true); }
void BM_RowsChecked256(benchmark::State& st) { checked_dynamic(st, 256, true); }
namespace tv = trn::vision;

/** A template cut at (5, 7) from a smooth random window: a clear peak, as in flight. */
struct CorrelationCase {
  std::int32_t t = 0;
  std::int32_t w = 0;
  std::vector<std::uint8_t> tmpl;
  std::vector<std::uint8_t> win;
  tv::ConstImageU8 tv_tmpl() const { return {tmpl.data(), t, t, t}; }
  tv::ConstImageU8 tv_win() const { return {win.data(), w, w, w}; }
};

CorrelationCase make_correlation_case(std::int32_t t, std::int32_t w) {
  CorrelationCase c{t, w, std::vector<std::uint8_t>(static_cast<std::size_t>(t) * static_cast<std::size_t>(t)),
                    std::vector<std::uint8_t>(static_cast<std::size_t>(w) * static_cast<std::size_t>(w))};
  std::mt19937_64 rng(7U);  // fixed seed: the same inputs every run
  std::uniform_int_distribution<int> d(0, 63);
  for (auto& v : c.win) v = static_cast<std::uint8_t>(d(rng) + d(rng) + d(rng) + d(rng));
  for (std::int32_t y = 0; y < t; ++y)
    for (std::int32_t x = 0; x < t; ++x)
      c.tmpl[static_cast<std::size_t>(y) * static_cast<std::size_t>(t) + static_cast<std::size_t>(x)] =
          c.win[static_cast<std::size_t>(7 + y) * static_cast<std::size_t>(w) + static_cast<std::size_t>(5 + x)];
  return c;
}

tv::CorrelatorWorkspace<256>& correlator_ws() {
  static tv::CorrelatorWorkspace<256> ws;
  return ws;
}

/** The correlation as before its checks; its work into @p work. */
bool correlate_plain(const CorrelationCase& c, bsp::Work& work) {
  const std::int32_t s = c.w - c.t + 1;
  tv::CorrelatorWorkspace<256>& ws = correlator_ws();
  tv::TemplateStats st;
  tv::IntegralRef integral;
  std::int32_t flat = 0;
  const tv::ImageF32 surf{ws.surface, s, s, s};
  if (tv::template_stats(c.tv_tmpl(), st, work) != tv::Status::kOk ||
      tv::build_integral(c.tv_win(), ws.sum, ws.sum_sq, ws.kEntries, integral, work) != tv::Status::kOk ||
      tv::ncc_surface(c.tv_tmpl(), st, c.tv_win(), integral, surf, tv::ImageU8{ws.flags, s, s, s}, flat, work) !=
          tv::Status::kOk) {
    return false;
  }
  const tv::Peak p = tv::find_peak(surf.as_const(), tv::QualityParams{}, work);
  benchmark::DoNotOptimize(p);
  return true;
}

void BM_CorrelatePlain(benchmark::State& state) {
  const CorrelationCase c = make_correlation_case(static_cast<std::int32_t>(state.range(0)),
                                                  static_cast<std::int32_t>(state.range(1)));
  bsp::Work work;
  for (auto _ : state) {
    work = bsp::Work{};
    if (!correlate_plain(c, work)) {
      state.SkipWithError("correlation failed");
      break;
    }
  }
  state.counters["tile64_cycles"] = static_cast<double>(bsp::cost_of(bsp::kTile64, work));
}

void BM_CorrelateChecked(benchmark::State& state) {
  const CorrelationCase c = make_correlation_case(static_cast<std::int32_t>(state.range(0)),
                                                  static_cast<std::int32_t>(state.range(1)));
  bsp::Work plain;
  if (!correlate_plain(c, plain)) {
    state.SkipWithError("correlation failed");
    return;
  }
  bsp::Work work;
  for (auto _ : state) {
    work = bsp::Work{};
    tv::MatchResult r;
    if (tv::correlate(c.tv_tmpl(), c.tv_win(), tv::QualityParams{}, correlator_ws().buffers(), r, work) !=
            tv::Status::kOk ||
        r.recomputes != 0U) {
      state.SkipWithError("checked correlation failed or recomputed");
      break;
    }
    benchmark::DoNotOptimize(r);
  }
  const double p = static_cast<double>(bsp::cost_of(bsp::kTile64, plain));
  const double k = static_cast<double>(bsp::cost_of(bsp::kTile64, work));
  state.counters["tile64_cycles"] = k;
  state.counters["overhead_pct"] = 100.0 * (k / p - 1.0);
}

BENCHMARK(BM_CorrelatePlain)->Args({21, 49})->Args({21, 27})->Args({64, 256})->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_CorrelateChecked)->Args({21, 49})->Args({21, 27})->Args({64, 256})->Unit(benchmark::kMicrosecond);

BENCHMARK(BM_Plain15);
BENCHMARK(BM_Checked15);
BENCHMARK(BM_Plain21);
BENCHMARK(BM_Checked21);
BENCHMARK(BM_Plain64);
BENCHMARK(BM_Checked64);
BENCHMARK(BM_Plain256);
BENCHMARK(BM_Checked256);
BENCHMARK(BM_RowsChecked15);
BENCHMARK(BM_RowsChecked21);
BENCHMARK(BM_RowsChecked64);
BENCHMARK(BM_RowsChecked256);

}  // namespace

BENCHMARK_MAIN();
