/**
 * @file update_abft_test.cpp
 * @brief Checked products of the Kalman update (trn/filter/covariance.*): every element of each of
 *        the three products, corrupted through the update's sdc channel, is found on its row and
 *        recomputed, and the update is the clean one bit for bit; a product still wrong is not
 *        applied; no false alarm over random updates with the filter's conditioning.
 */
#include "bsp_tile64/faults/fault_injector.hpp"
#include "tests/fdir/fdir_fixture.hpp"
#include "trn/filter/covariance.hpp"

#include <gtest/gtest.h>

#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <random>

namespace {

using trn::filter::CovWork;
using trn::filter::GateResult;
using trn::filter::Mat15;
using trn::filter::Meas2;
using trn::filter::Vec15;

/** Per-state standard deviations of the filter's error state: position, velocity, attitude, biases. */
constexpr std::array<double, 15> kSigma{3000.0, 3000.0, 300.0, 5.0, 5.0, 2.0, 1e-2, 1e-2, 3e-2,
                                        1e-5,   1e-5,   1e-5,  1e-3, 1e-3, 1e-3};
/** A gate no residual fails: these tests are about the products. */
constexpr double kOpenGate = 1e300;

/**
 * A covariance with the filter's scales and random correlations; position and velocity shrunk by
 * 10^[-3, 0] (from the 3 km start to a converged state).
 */
Mat15 covariance(std::mt19937_64& rng) {
  std::normal_distribution<double> g(0.0, 1.0);
  std::uniform_real_distribution<double> shrink(-3.0, 0.0);
  Mat15 l;
  for (int i = 0; i < 15; ++i) {
    for (int j = 0; j < 15; ++j) {
      l(i, j) = g(rng);
    }
  }
  Mat15 corr = l * l.transpose() + 0.1 * Mat15::Identity();
  const Vec15 d = corr.diagonal().cwiseSqrt().cwiseInverse();
  corr = d.asDiagonal() * corr * d.asDiagonal();
  const double k = std::pow(10.0, shrink(rng));
  Vec15 s;
  for (int i = 0; i < 15; ++i) {
    s(i) = kSigma[static_cast<std::size_t>(i)] * (i < 6 ? k : 1.0);
  }
  Mat15 p = s.asDiagonal() * corr * s.asDiagonal();
  trn::filter::symmetrize(p);
  return p;
}

/**
 * A bearing measurement with the filter's scales: about 0.5 px per metre of position, 1200 px per
 * radian of attitude, 0.2 to 4 px^2 of noise; measured up to 2.5 s before the state when lagged.
 */
Meas2 measurement(std::mt19937_64& rng, bool lagged) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Meas2 m;
  for (int i = 0; i < 2; ++i) {
    for (int j = 0; j < 3; ++j) {
      m.hp(i, j) = 0.5 * u(rng);
      m.hth(i, j) = 1200.0 * u(rng);
    }
    m.r(i) = 2.0 * u(rng);
    m.r_var(i) = 2.1 + 1.9 * u(rng);
  }
  if (lagged) {
    m.lag_s = 1.25 * (1.0 + u(rng));
    m.d = trn::filter::lag_noise(trn::filter::ImuSpec{}, m.lag_s);
  }
  return m;
}

/** Whether @p a and @p b are the same doubles bit for bit (-0.0 and 0.0 differ; a NaN equals its own bits). */
template <typename M>
bool same_bits(const M& a, const M& b) {
  for (Eigen::Index i = 0; i < a.size(); ++i) {
    if (std::bit_cast<std::uint64_t>(a.data()[i]) != std::bit_cast<std::uint64_t>(b.data()[i])) {
      return false;
    }
  }
  return true;
}

/** What one corrupted update did. */
struct Outcome {
  bool fault_applied = false;
  fdir::AbftResult r{};
  bool accepted = false;
  bool same_p = false;
  bool same_dx = false;
};

/** One site's sweep: every element of its product flipped at one bit, each in its own update. */
struct Sweep {
  Mat15 p0 = Mat15::Identity();
  Meas2 m{};
  Mat15 p_clean = Mat15::Identity();
  Vec15 dx_clean = Vec15::Zero();
  Mat15 p = Mat15::Identity();
  Vec15 dx = Vec15::Zero();
  CovWork w{};
  std::uint32_t site = 0U;
  int elements = 0;
  std::array<int, 225> index{};  ///< the swept elements (column-major), in order
  std::uint32_t bit = 0U;
  std::array<Outcome, 225> out{};
};
Sweep g_sweep{};

/** On the tile: for each element, arm an sdc of it on the update's channel, then update a copy of P. */
void sweep_body() {
  Sweep& s = g_sweep;
  bsp::Work work{};
  s.w.update_sdc_sites = 1U << (s.site - trn::filter::kAbftSitePht);
  for (int e = 0; e < s.elements; ++e) {
    bsp::FaultSpec f{};
    f.cycle = bsp::now();
    f.kind = bsp::FaultKind::kSdc;
    f.tile = 0U;
    f.channel = trn::filter::kFilterUpdateProductChannel;
    f.bit = 64U * static_cast<std::uint32_t>(s.index[static_cast<std::size_t>(e)]) + s.bit;
    if (bsp::fault_plan_add(f) != bsp::FaultError::kOk) {
      return;  // the test sees the outcomes left unapplied
    }
    k::sleep(1);  // the plan entry is armed at the next barrier
    const std::size_t before = bsp::fault_log().size();
    s.p = s.p0;
    s.dx.setZero();
    const GateResult g = trn::filter::kalman_update(s.p, s.m, kOpenGate, s.dx, s.w, work);
    Outcome& o = s.out[static_cast<std::size_t>(e)];
    o.fault_applied = before > 0U && bsp::fault_log()[before - 1U].status == bsp::FaultStatus::kApplied;
    o.r = s.w.last_update[s.site - trn::filter::kAbftSitePht];
    o.accepted = g.accepted;
    o.same_p = same_bits(s.p, s.p_clean);
    o.same_dx = same_bits(s.dx, s.dx_clean);
  }
}

/** Flips bit @p bit of every element of site @p site's product, one update each, and checks each. */
void expect_every_element_corrected(std::uint32_t site, int elements, std::uint32_t bit, bool lagged) {
  const std::uint64_t seed = 100U * site + bit;
  SCOPED_TRACE(testing::Message() << "site " << site << " bit " << bit << ", operands drawn with seed " << seed);
  std::mt19937_64 rng(seed);
  g_sweep = Sweep{};
  Sweep& s = g_sweep;
  s.p0 = covariance(rng);
  s.m = measurement(rng, lagged);
  s.site = site;
  s.bit = bit;
  // The symmetric product is computed (and used) on its upper triangle only: those elements.
  s.elements = 0;
  for (int e = 0; e < elements; ++e) {
    if (site != trn::filter::kAbftSiteKpht || e % 15 <= e / 15) {
      s.index[static_cast<std::size_t>(s.elements)] = e;
      ++s.elements;
    }
  }
  bsp::Work work{};
  s.p_clean = s.p0;
  ASSERT_TRUE(trn::filter::kalman_update(s.p_clean, s.m, kOpenGate, s.dx_clean, s.w, work).accepted);
  fdir_test::run_on_tile0(&sweep_body, static_cast<std::uint32_t>(elements + 10));
  for (int n = 0; n < s.elements; ++n) {
    const Outcome& o = s.out[static_cast<std::size_t>(n)];
    const int e = s.index[static_cast<std::size_t>(n)];
    SCOPED_TRACE(testing::Message() << "element " << e << " (row " << e % 15 << ", column " << e / 15 << ")");
    ASSERT_TRUE(o.fault_applied);
    EXPECT_EQ(o.r.verdict, fdir::AbftVerdict::kCorrected);
    EXPECT_EQ(o.r.bad_rows, 1U);
    EXPECT_EQ(o.r.row, e % 15) << "the row is located";
    EXPECT_EQ(o.r.col, -1) << "rows only: no column";
    EXPECT_EQ(o.r.recomputes, 1U);
    EXPECT_TRUE(o.accepted);
    EXPECT_TRUE(o.same_p) << "the update's covariance is the clean one, bit for bit";
    EXPECT_TRUE(o.same_dx);
  }
  const std::vector<fdir::Event> ev = fdir_test::events_of(0);
  ASSERT_EQ(ev.size(), static_cast<std::size_t>(s.elements));
  EXPECT_EQ(ev[0].id, fdir::EventId::kAbftCorrected);
  EXPECT_EQ(ev[0].subject, site);
  EXPECT_EQ(ev[0].cause, fdir::kAbftColNotChecked) << "row 0, no column checked";
}

/** Elements of each site's product: 15 x 2 or 15 x 15. */
constexpr std::array<int, 3> kElements{30, 30, 225};
/** The exponent's top and lowest bits (a factor 2^(+-1024) and 2), the mantissa's top one. */
constexpr std::array<std::uint32_t, 3> kBits{62U, 52U, 51U};

// FDIR-AB-06: every single element of each of the update's three products (P H^T, the gain,
// K (P H^T)^T), with an exponent or top mantissa bit flipped where the
// product is published, fails its row's checksum; the product is computed again and the update's
// covariance and correction are the clean ones, bit for bit.
TEST(UpdateAbft, EveryElementOfTheThreeProductsIsFoundAndTheUpdateIsTheCleanOne) {
  for (std::uint32_t i = 0; i < trn::filter::kUpdateSites; ++i) {
    for (const std::uint32_t bit : kBits) {
      expect_every_element_corrected(trn::filter::kAbftSitePht + i, kElements[i], bit, (bit + i) % 2U == 0U);
    }
  }
}

/** A failing update on the tile: P with a NaN its P H^T reads (the product is wrong every time). */
struct Failing {
  Mat15 p = Mat15::Identity();
  Mat15 p_before = Mat15::Identity();
  Vec15 dx = Vec15::Zero();
  Meas2 m{};
  CovWork w{};
  GateResult g{};
};
Failing g_fail{};

// A product still wrong after its recomputations is reported abft_failed and not applied: the
// measurement is dropped, P and dx untouched.
TEST(UpdateAbft, AProductStillWrongIsReportedAndNotApplied) {
  constexpr std::uint64_t kSeed = 11;
  SCOPED_TRACE(testing::Message() << "operands drawn with seed " << kSeed);
  std::mt19937_64 rng(kSeed);
  g_fail = Failing{};
  g_fail.p = covariance(rng);
  g_fail.p(7, 4) = std::numeric_limits<double>::quiet_NaN();
  g_fail.p_before = g_fail.p;
  g_fail.m = measurement(rng, false);
  fdir_test::run_on_tile0([] {
    bsp::Work work{};
    g_fail.dx.setConstant(7.0);
    g_fail.g = trn::filter::kalman_update(g_fail.p, g_fail.m, kOpenGate, g_fail.dx, g_fail.w, work);
  });
  EXPECT_TRUE(g_fail.g.check_failed);
  EXPECT_FALSE(g_fail.g.accepted);
  EXPECT_EQ(g_fail.w.last_update[0].verdict, fdir::AbftVerdict::kFailed);
  EXPECT_EQ(g_fail.w.last_update[0].recomputes, fdir::kAbftMaxRecompute);
  EXPECT_EQ(g_fail.w.last_update[0].row, 7);
  EXPECT_TRUE(same_bits(g_fail.p, g_fail.p_before)) << "P untouched";
  EXPECT_TRUE((g_fail.dx.array() == 7.0).all()) << "dx untouched";
  const std::vector<fdir::Event> ev = fdir_test::events_of(0);
  ASSERT_EQ(ev.size(), 1U);
  EXPECT_EQ(ev[0].id, fdir::EventId::kAbftFailed);
  EXPECT_EQ(ev[0].subject, trn::filter::kAbftSitePht);
}

// An update that would leave a variance at zero (a noiseless measurement of two position axes,
// numbers exact in binary) is refused: P and dx untouched, not accepted.
TEST(KalmanUpdate, AnUpdateThatWouldLeaveAVarianceNonPositiveIsRefused) {
  static CovWork w{};
  Mat15 p = Mat15::Identity();
  p(0, 0) = 4.0;
  p(1, 1) = 16.0;
  const Mat15 p0 = p;
  Meas2 m{};
  m.hp(0, 0) = 1.0;
  m.hp(1, 1) = 1.0;
  m.r_var.setZero();
  Vec15 dx = Vec15::Constant(7.0);
  bsp::Work work{};
  const GateResult g = trn::filter::kalman_update(p, m, kOpenGate, dx, w, work);
  EXPECT_TRUE(g.variance_lost);
  EXPECT_FALSE(g.accepted);
  EXPECT_FALSE(g.check_failed);
  EXPECT_TRUE(same_bits(p, p0));
  EXPECT_TRUE(same_bits(dx, Vec15::Constant(7.0).eval()));
  // The same with a little noise is applied, and the variances it shrinks stay positive.
  m.r_var = trn::filter::Vec2(1.0, 1.0);
  const GateResult ok = trn::filter::kalman_update(p, m, kOpenGate, dx, w, work);
  EXPECT_TRUE(ok.accepted);
  EXPECT_NEAR(p(0, 0), 0.8, 1e-12);  // 4 - 16 / 5
  EXPECT_GT(p(1, 1), 0.0);
}

// FDIR-AB-07: no false alarm over random updates with the filter's conditioning (covariances over
// 12 orders of magnitude, position shrunk up to 1000 times, bearing Jacobians, lagged and not):
// 2 x 10^5 updates, three checked products each, in an optimised build (make test).
TEST(UpdateAbft, NoFalseAlarmOverRandomUpdatesWithTheFiltersConditioning) {
#ifdef __OPTIMIZE__
  constexpr int kUpdates = 200'000;
#else
  constexpr int kUpdates = 5'000;
#endif
  constexpr int kFresh = 100;  // a new covariance every kFresh updates, new measurements every one
  constexpr std::uint64_t kSeed = 2027;
  SCOPED_TRACE(testing::Message() << "operands drawn with seed " << kSeed);
  std::mt19937_64 rng(kSeed);
  static CovWork w{};
  static Mat15 p0;
  static Mat15 p;
  Vec15 dx;
  bsp::Work work{};
  std::uint64_t alarms = 0U;
  std::uint64_t accepted = 0U;
  for (int n = 0; n < kUpdates; ++n) {
    if (n % kFresh == 0) {
      p0 = covariance(rng);
    }
    const Meas2 m = measurement(rng, n % 2 == 1);
    p = p0;
    const GateResult g = trn::filter::kalman_update(p, m, kOpenGate, dx, w, work);
    accepted += g.accepted ? 1U : 0U;
    for (const fdir::AbftResult& r : w.last_update) {
      alarms += r.bad_rows + r.bad_cols;
    }
  }
  EXPECT_EQ(accepted, static_cast<std::uint64_t>(kUpdates));
  EXPECT_EQ(alarms, 0U) << "over " << 3 * kUpdates << " products";
}

}  // namespace
