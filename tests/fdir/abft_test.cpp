/**
 * @file abft_test.cpp
 * @brief Checked matrix products (fdir/abft.hpp): every wrong element of a product of the filter's
 *        sizes is found and located, a transient fault is corrected by recomputation (bit for bit
 *        the clean product), a persistent one is reported failed, and products with the filter's
 *        conditioning raise no false alarm.
 */
#include "fdir/abft.hpp"

#include "bsp_tile64/api/port.hpp"  // BSP_ASAN

#include "fdir/event_log.hpp"
#include "tests/fdir/fdir_fixture.hpp"

#include <gtest/gtest.h>

#include <bit>
#include <cstdint>
#include <limits>
#include <random>

namespace {

/** Per-state standard deviations of the filter's error state: position, velocity, attitude, biases. */
constexpr std::array<double, 15> kSigma{3000.0, 3000.0, 300.0, 5.0, 5.0, 2.0, 1e-2, 1e-2, 3e-2,
                                        1e-5,   1e-5,   1e-5,  1e-3, 1e-3, 1e-3};

/** A covariance with the filter's scales (12 orders of magnitude) and random correlations. */
template <int N>
Eigen::Matrix<double, N, N> covariance(std::mt19937_64& rng) {
  std::normal_distribution<double> g(0.0, 1.0);
  Eigen::Matrix<double, N, N> l;
  for (int i = 0; i < N; ++i) {
    for (int j = 0; j < N; ++j) {
      l(i, j) = g(rng);
    }
  }
  Eigen::Matrix<double, N, N> corr = l * l.transpose() + 0.1 * Eigen::Matrix<double, N, N>::Identity();
  const Eigen::Matrix<double, N, 1> d = corr.diagonal().cwiseSqrt().cwiseInverse();
  corr = d.asDiagonal() * corr * d.asDiagonal();
  Eigen::Matrix<double, N, 1> s;
  for (int i = 0; i < N; ++i) {
    s(i) = kSigma[static_cast<std::size_t>(i) % kSigma.size()];
  }
  return s.asDiagonal() * corr * s.asDiagonal();
}

/** A measurement Jacobian's transpose: position and attitude rows, the rest zero. */
Eigen::Matrix<double, 15, 2> jacobian_t(std::mt19937_64& rng) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Eigen::Matrix<double, 15, 2> ht = Eigen::Matrix<double, 15, 2>::Zero();
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 2; ++j) {
      ht(i, j) = 1e-3 * u(rng);
      ht(6 + i, j) = u(rng);
    }
  }
  return ht;
}

/** A transition matrix near identity, like the filter's over 10 ms (dt-sized couplings, some large). */
template <int N>
Eigen::Matrix<double, N, N> transition(std::mt19937_64& rng) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Eigen::Matrix<double, N, N> f = Eigen::Matrix<double, N, N>::Identity();
  for (int i = 0; i < N; ++i) {
    for (int j = 0; j < N; ++j) {
      f(i, j) += (i != j ? 0.01 : 0.0) * u(rng) * (((i + j) % 5 == 0) ? 100.0 : 1.0);
    }
  }
  return f;
}

template <int M, int K, int N>
void expect_every_element_located(const Eigen::Matrix<double, M, K>& a, const Eigen::Matrix<double, K, N>& b) {
  fdir::AbftSums<M, K, N> s{};
  bsp::Work w{};
  fdir::abft_sums(a, b, s, w);
  fdir::abft_tolerances(a, b, s, w);
  const Eigen::Matrix<double, M, 1> row_tol = s.row_tol;
  const Eigen::Matrix<double, 1, N> col_tol = s.col_tol;
  const Eigen::Matrix<double, M, N> clean = a.lazyProduct(b);
  ASSERT_EQ(fdir::abft_check(a, b, clean, s, w).bad_rows, 0U);
  for (int i = 0; i < M; ++i) {
    for (int j = 0; j < N; ++j) {
      // An error of a thousand times the round-off the check allows at that element.
      Eigen::Matrix<double, M, N> c = clean;
      c(i, j) += 1e3 * std::max(row_tol(i), col_tol(j));
      fdir::AbftResult r = fdir::abft_check(a, b, c, s, w);
      EXPECT_EQ(r.bad_rows, 1U) << i << "," << j;
      EXPECT_EQ(r.bad_cols, 1U) << i << "," << j;
      EXPECT_EQ(r.row, i);
      EXPECT_EQ(r.col, j);
      // Every flip of an exponent bit of a non-zero element, and of the top mantissa bit.
      for (int bit = 51; bit < 63; ++bit) {
        if (clean(i, j) == 0.0) {
          continue;
        }
        c = clean;
        const auto u = std::bit_cast<std::uint64_t>(c(i, j)) ^ (std::uint64_t{1} << bit);
        c(i, j) = std::bit_cast<double>(u);
        r = fdir::abft_check(a, b, c, s, w);
        EXPECT_EQ(r.bad_rows, 1U) << i << "," << j << " bit " << bit;
        EXPECT_EQ(r.bad_cols, 1U) << i << "," << j << " bit " << bit;
        EXPECT_EQ(r.row, i);
        EXPECT_EQ(r.col, j);
      }
    }
  }
}

// FDIR-AB-01: every single wrong element is found and located, at each of the filter's product shapes.
TEST(Abft, EveryWrongElementIsLocatedAtTheFiltersSizes) {
  constexpr std::uint64_t kSeed = 17;
  SCOPED_TRACE(testing::Message() << "operands drawn with seed " << kSeed);
  std::mt19937_64 rng(kSeed);
  const Eigen::Matrix<double, 15, 15> p = covariance<15>(rng);
  const Eigen::Matrix<double, 15, 15> f = transition<15>(rng);
  expect_every_element_located(f, p);                                // F P
  const Eigen::Matrix<double, 15, 15> fp = f * p;
  expect_every_element_located<15, 15, 15>(fp, f.transpose());       // (F P) F^T
  const Eigen::Matrix<double, 15, 2> ht = jacobian_t(rng);
  expect_every_element_located<15, 15, 2>(p, ht);                    // P H^T
  const Eigen::Matrix<double, 15, 2> k = p * ht * 1e-4;
  expect_every_element_located<15, 2, 15>(k, (p * ht).transpose());  // K (P H^T)^T
  const Eigen::Matrix<double, 21, 21> p21 = covariance<21>(rng);
  expect_every_element_located<21, 21, 21>(transition<21>(rng), p21);
}

// Rows only (thin products): every wrong element fails exactly its row, which is located; no column
// is checked or located, and a clean product costs abft_rows_flops.
TEST(Abft, RowsOnlyLocatesTheRowOfEveryWrongElement) {
  constexpr std::uint64_t kSeed = 19;
  SCOPED_TRACE(testing::Message() << "operands drawn with seed " << kSeed);
  std::mt19937_64 rng(kSeed);
  const Eigen::Matrix<double, 15, 15> p = covariance<15>(rng);
  const Eigen::Matrix<double, 15, 2> ht = jacobian_t(rng);
  const Eigen::Matrix<double, 15, 2> k = p * ht * 1e-4;
  const Eigen::Matrix<double, 2, 15> pht_t = (p * ht).transpose();
  fdir::AbftSums<15, 2, 15> s{};
  bsp::Work w{};
  fdir::abft_sums(k, pht_t, s, w, true);
  const Eigen::Matrix<double, 15, 15> clean = k.lazyProduct(pht_t);
  fdir::AbftResult r = fdir::abft_check(k, pht_t, clean, s, w, true);
  EXPECT_EQ(r.bad_rows, 0U);
  EXPECT_EQ(w.flops, fdir::abft_rows_flops(15, 2, 15)) << "a clean product computes no tolerance";
  for (int i = 0; i < 15; ++i) {
    for (int j = 0; j < 15; ++j) {
      Eigen::Matrix<double, 15, 15> c = clean;
      c(i, j) = std::bit_cast<double>(std::bit_cast<std::uint64_t>(c(i, j)) ^ (std::uint64_t{1} << 52U));
      r = fdir::abft_check(k, pht_t, c, s, w, true);
      EXPECT_EQ(r.bad_rows, 1U) << i << "," << j;
      EXPECT_EQ(r.bad_cols, 0U);
      EXPECT_EQ(r.row, i);
      EXPECT_EQ(r.col, -1);
    }
  }
}

// A non-finite element fails its row and column.
TEST(Abft, ANonFiniteElementIsFound) {
  constexpr std::uint64_t kSeed = 3;
  SCOPED_TRACE(testing::Message() << "operands drawn with seed " << kSeed);
  std::mt19937_64 rng(kSeed);
  const Eigen::Matrix<double, 15, 15> p = covariance<15>(rng);
  const Eigen::Matrix<double, 15, 15> f = transition<15>(rng);
  fdir::AbftSums<15, 15, 15> s{};
  bsp::Work w{};
  fdir::abft_sums(f, p, s, w);
  Eigen::Matrix<double, 15, 15> c = f.lazyProduct(p);
  c(4, 9) = std::numeric_limits<double>::quiet_NaN();
  fdir::AbftResult r = fdir::abft_check(f, p, c, s, w);
  EXPECT_EQ(r.row, 4);
  EXPECT_EQ(r.col, 9);
  c(4, 9) = std::numeric_limits<double>::infinity();
  r = fdir::abft_check(f, p, c, s, w);
  EXPECT_EQ(r.bad_rows, 1U);
  EXPECT_EQ(r.bad_cols, 1U);
  EXPECT_GT(w.flops, 0U) << "the checks are charged";
}

/** A kernel with a fault in its first @p faulty calls: element (i, j) comes out with bit 60 flipped. */
struct FaultyKernel {
  int faulty;
  int i;
  int j;
  int calls = 0;
  template <typename A, typename B, typename C>
  void operator()(const A& a, const B& b, C& c) {
    c.noalias() = a.lazyProduct(b);
    if (calls++ < faulty) {
      c(i, j) = std::bit_cast<double>(std::bit_cast<std::uint64_t>(c(i, j)) ^ (std::uint64_t{1} << 60U));
    }
  }
};

struct ProductRun {
  Eigen::Matrix<double, 15, 15> f;
  Eigen::Matrix<double, 15, 15> p;
  Eigen::Matrix<double, 15, 15> c1;
  Eigen::Matrix<double, 15, 15> c2;
  fdir::AbftSums<15, 15, 15> s;
  fdir::AbftResult fine;
  fdir::AbftResult once;
  fdir::AbftResult always;
};
ProductRun g_run{};

// FDIR-AB-02: a transient fault is corrected by computing the product again (bit for bit the clean
// one) and reported with the element it located; a persistent one is reported failed after the
// bounded recomputations.
TEST(Abft, ATransientFaultIsRecomputedAndAPersistentOneReportedFailed) {
  constexpr std::uint64_t kSeed = 5;
  SCOPED_TRACE(testing::Message() << "operands drawn with seed " << kSeed);
  std::mt19937_64 rng(kSeed);
  g_run.p = covariance<15>(rng);
  g_run.f = transition<15>(rng);
  const Eigen::Matrix<double, 15, 15> clean = g_run.f.lazyProduct(g_run.p);
  fdir_test::run_on_tile0([] {
    bsp::Work w{};
    ProductRun& r = g_run;
    r.fine = fdir::abft_product(r.f, r.p, r.c1, fdir::AbftSite{7U, 0U}, fdir::AbftDense{}, r.s, w);
    FaultyKernel k1{1, 3, 11};
    r.once = fdir::abft_product(r.f, r.p, r.c1, fdir::AbftSite{7U, 0U}, k1, r.s, w);
    FaultyKernel k2{100, 2, 2};
    r.always = fdir::abft_product(r.f, r.p, r.c2, fdir::AbftSite{8U, 0U}, k2, r.s, w);
  });
  EXPECT_EQ(g_run.fine.verdict, fdir::AbftVerdict::kClean);
  EXPECT_EQ(g_run.once.verdict, fdir::AbftVerdict::kCorrected);
  EXPECT_EQ(g_run.once.row, 3);
  EXPECT_EQ(g_run.once.col, 11);
  EXPECT_EQ(g_run.once.recomputes, 1U);
  bool same = true;
  for (Eigen::Index e = 0; e < clean.size(); ++e) {
    same = same && std::bit_cast<std::uint64_t>(g_run.c1.data()[e]) == std::bit_cast<std::uint64_t>(clean.data()[e]);
  }
  EXPECT_TRUE(same) << "the clean product, bit for bit";
  EXPECT_EQ(g_run.always.verdict, fdir::AbftVerdict::kFailed);
  EXPECT_EQ(g_run.always.recomputes, fdir::kAbftMaxRecompute);
  const std::vector<fdir::Event> ev = fdir_test::events_of(0);
  ASSERT_EQ(ev.size(), 2U) << "a clean product says nothing";
  EXPECT_EQ(ev[0].id, fdir::EventId::kAbftCorrected);
  EXPECT_EQ(ev[0].subject, 7U);
  EXPECT_EQ(ev[0].cause, (3U << 16U) | 11U);
  EXPECT_EQ(ev[0].b, 1U);
  EXPECT_EQ(ev[1].id, fdir::EventId::kAbftFailed);
  EXPECT_EQ(ev[1].subject, 8U);
  EXPECT_EQ(ev[1].cause, (2U << 16U) | 2U);
}

struct RowsFirstRun {
  Eigen::Matrix<double, 15, 15> f;
  Eigen::Matrix<double, 15, 15> p;
  Eigen::Matrix<double, 15, 15> c;
  Eigen::Matrix<double, 15, 15> clean;  ///< the same kernel, no fault, into the same matrix
  fdir::AbftSums<15, 15, 15> s;
  fdir::AbftResult clean_result;
  fdir::AbftResult once;
  bsp::Work clean_work{};
};
RowsFirstRun g_rf{};

// FDIR-AB-02b: a rows-first site (the filter's propagation) pays a rows-only check on a clean product,
// and on a wrong one checks the columns too: the element is located as by the full check, and the
// product computed again, bit for bit the clean one.
TEST(Abft, RowsFirstCostsTheRowsWhenCleanAndLocatesTheElementWhenWrong) {
  constexpr std::uint64_t kSeed = 6;
  SCOPED_TRACE(testing::Message() << "operands drawn with seed " << kSeed);
  std::mt19937_64 rng(kSeed);
  g_rf.p = covariance<15>(rng);
  g_rf.f = transition<15>(rng);
  fdir_test::run_on_tile0([] {
    RowsFirstRun& r = g_rf;
    const fdir::AbftSite site{9U, 0U, false, true};
    FaultyKernel k0{0, 4, 12};
    r.clean_result = fdir::abft_product(r.f, r.p, r.c, site, k0, r.s, r.clean_work);
    r.clean = r.c;
    bsp::Work w{};
    FaultyKernel k1{1, 4, 12};
    r.once = fdir::abft_product(r.f, r.p, r.c, site, k1, r.s, w);
  });
  EXPECT_EQ(g_rf.clean_result.verdict, fdir::AbftVerdict::kClean);
  EXPECT_EQ(g_rf.clean_work.flops, fdir::abft_rows_first_flops(15, 15, 15));
  EXPECT_LT(fdir::abft_rows_first_flops(15, 15, 15), fdir::abft_clean_flops(15, 15, 15));
  EXPECT_EQ(g_rf.once.verdict, fdir::AbftVerdict::kCorrected);
  EXPECT_EQ(g_rf.once.row, 4);
  EXPECT_EQ(g_rf.once.col, 12) << "the columns are checked once a row failed";
  EXPECT_EQ(g_rf.once.bad_rows, 1U);
  EXPECT_EQ(g_rf.once.bad_cols, 1U);
  EXPECT_EQ(g_rf.once.recomputes, 1U);
  bool same = true;
  for (Eigen::Index e = 0; e < g_rf.clean.size(); ++e) {
    same = same && std::bit_cast<std::uint64_t>(g_rf.c.data()[e]) == std::bit_cast<std::uint64_t>(g_rf.clean.data()[e]);
  }
  EXPECT_TRUE(same) << "the clean product, bit for bit";
  const std::vector<fdir::Event> ev = fdir_test::events_of(0);
  ASSERT_EQ(ev.size(), 1U);
  EXPECT_EQ(ev[0].id, fdir::EventId::kAbftCorrected);
  EXPECT_EQ(ev[0].cause, (4U << 16U) | 12U);
}

// FDIR-AB-03: no false alarm over random products with the filter's conditioning (covariances over
// 12 orders of magnitude, transitions near identity): F P, (F P) F^T and P H^T. A million of each
// in an optimised build (make test); the unoptimised coverage build and the sanitizer build, which
// look for other defects than a rare false alarm, check fewer.
TEST(Abft, NoFalseAlarmOverRandomProductsWithTheFiltersConditioning) {
#if defined(__OPTIMIZE__) && !BSP_ASAN
  constexpr int kProducts = 1'000'000;
#else
  constexpr int kProducts = 20'000;
#endif
  constexpr int kFresh = 1000;  // new operands every kFresh products, scaled in between
  constexpr std::uint64_t kSeed = 2026;
  SCOPED_TRACE(testing::Message() << "operands drawn with seed " << kSeed);
  std::mt19937_64 rng(kSeed);
  std::uniform_real_distribution<double> scale(0.5, 2.0);
  static fdir::AbftSums<15, 15, 15> s{};
  static fdir::AbftSums<15, 15, 2> s2{};
  bsp::Work w{};
  Eigen::Matrix<double, 15, 15> p = covariance<15>(rng);
  Eigen::Matrix<double, 15, 15> f = transition<15>(rng);
  Eigen::Matrix<double, 15, 2> ht = jacobian_t(rng);
  std::uint64_t alarms = 0U;
  for (int n = 0; n < kProducts; ++n) {
    if (n % kFresh == 0) {
      p = covariance<15>(rng);
      f = transition<15>(rng);
      ht = jacobian_t(rng);
    } else {
      const double k = scale(rng);
      p *= k;  // the same structure at another scale: other round-off
      f(0, 3) = 0.01 * k;
    }
    const Eigen::Matrix<double, 15, 15> fp = f.lazyProduct(p);
    fdir::abft_sums(f, p, s, w);
    const fdir::AbftResult r1 = fdir::abft_check(f, p, fp, s, w);
    const Eigen::Matrix<double, 15, 15> ft = f.transpose();
    const Eigen::Matrix<double, 15, 15> fpf = fp.lazyProduct(ft);
    fdir::abft_sums(fp, ft, s, w);
    const fdir::AbftResult r2 = fdir::abft_check(fp, ft, fpf, s, w);
    const Eigen::Matrix<double, 15, 2> pht = p.lazyProduct(ht);
    fdir::abft_sums(p, ht, s2, w);
    const fdir::AbftResult r3 = fdir::abft_check(p, ht, pht, s2, w);
    alarms += r1.bad_rows + r1.bad_cols + r2.bad_rows + r2.bad_cols + r3.bad_rows + r3.bad_cols;
  }
  EXPECT_EQ(alarms, 0U) << "over " << 3 * kProducts << " products";
}

}  // namespace
