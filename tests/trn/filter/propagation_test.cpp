/**
 * @file propagation_test.cpp
 * @brief Strapdown propagation follows the truth with a perfect IMU, and with LN-200-class errors
 *        its drift is consistent with the propagated covariance.
 */
#include "tests/trn/filter/truth_sim.hpp"
#include "trn/filter/ekf.hpp"

#include <gtest/gtest.h>

#include <array>

#include <cstdio>

namespace {

using filter_test::TruthSim;
using filter_test::Vec3;
using trn::filter::Ekf;
using trn::filter::FilterStatus;

Ekf g_ekf;  // the filter lives in static storage, as on a tile

TEST(FilterPropagation, PerfectImuFollowsTheTruthFor60Seconds) {
  trn::filter::FilterConfig cfg;
  ASSERT_EQ(g_ekf.configure(cfg, bsp::CameraModel{}), FilterStatus::kOk);
  TruthSim truth(1, false, cfg.imu);
  trn::filter::InitialEstimate est;
  est.x.p_m = truth.p();
  est.x.v_mps = truth.v();
  est.x.q_mb = truth.q();
  ASSERT_EQ(g_ekf.init(est), FilterStatus::kOk);
  for (int k = 0; k < 6000; ++k) {
    ASSERT_EQ(g_ekf.propagate(truth.next_imu()), FilterStatus::kOk);
  }
  const auto& s = g_ekf.state();
  const double ep = (truth.p() - s.x.p_m).norm();
  const double ev = (truth.v() - s.x.v_mps).norm();
  const double eth = trn::filter::quat_log(s.x.q_mb.conjugate() * truth.q()).norm();
  std::printf("perfect IMU, 60 s: |dp| %.3e m, |dv| %.3e m/s, |dth| %.3e rad\n", ep, ev, eth);
  // Bounds from the discretization alone (one increment per 10 ms, no coning
  // or sculling terms beyond rotation compensation); measured 1.3 mm,
  // 4e-5 m/s, 1e-10 rad, bounds kept near 10x that.
  EXPECT_LT(ep, 0.01);
  EXPECT_LT(ev, 2e-4);
  EXPECT_LT(eth, 1e-8);
  EXPECT_EQ(s.c.propagations, 6000U);
  EXPECT_NEAR(s.t_s, 60.0, 1e-9);
}

TEST(FilterPropagation, Ln200DriftIsConsistentWithTheCovarianceOver20Runs) {
  constexpr int kRuns = 20;
  constexpr int kSteps = 6000;  // 60 s
  trn::filter::FilterConfig cfg;
  double sum_p = 0.0;
  double sum_v = 0.0;
  double sum_th = 0.0;
  for (int run = 0; run < kRuns; ++run) {
    const std::uint64_t seed = 1000U + static_cast<std::uint64_t>(run);
    SCOPED_TRACE(testing::Message() << "seed " << seed);
    ASSERT_EQ(g_ekf.configure(cfg, bsp::CameraModel{}), FilterStatus::kOk);
    TruthSim truth(seed, true, cfg.imu);
    bsp::Rng init_rng(seed, bsp::StreamId::kTest, 1);
    ASSERT_EQ(g_ekf.init(filter_test::perturbed_estimate(truth, init_rng, 1.0, 0.05, 1e-4)), FilterStatus::kOk);
    for (int k = 0; k < kSteps; ++k) {
      ASSERT_EQ(g_ekf.propagate(truth.next_imu()), FilterStatus::kOk);
    }
    const filter_test::Nees3 n = filter_test::nees(truth, g_ekf.state());
    sum_p += n.p;
    sum_v += n.v;
    sum_th += n.th;
  }
  const double lo = filter_test::chi2_quantile(0.025, 3.0 * kRuns) / kRuns;
  const double hi = filter_test::chi2_quantile(0.975, 3.0 * kRuns) / kRuns;
  std::printf("propagation only, %d runs x 60 s: mean NEES p %.2f v %.2f th %.2f, 95%% bounds [%.3f, %.3f]\n",
              kRuns, sum_p / kRuns, sum_v / kRuns, sum_th / kRuns, lo, hi);
  EXPECT_GT(sum_p / kRuns, lo);
  EXPECT_LT(sum_p / kRuns, hi);
  EXPECT_GT(sum_v / kRuns, lo);
  EXPECT_LT(sum_v / kRuns, hi);
  EXPECT_GT(sum_th / kRuns, lo);
  EXPECT_LT(sum_th / kRuns, hi);
}

TEST(FilterPropagation, ChiSquareQuantilesMatchTheTables) {
  // Table values for 60 dof: 40.482 and 83.298; 2 dof at 99.9 %: 13.816.
  EXPECT_NEAR(filter_test::chi2_quantile(0.025, 60.0), 40.482, 2e-3);
  EXPECT_NEAR(filter_test::chi2_quantile(0.975, 60.0), 83.298, 2e-3);
  EXPECT_NEAR(filter_test::chi2_quantile(0.999, 2.0), trn::filter::FilterConfig{}.gate_chi2, 1e-6);
}

TEST(FilterPropagation, InvalidSampleIsCountedAndNotIntegrated) {
  trn::filter::FilterConfig cfg;
  ASSERT_EQ(g_ekf.configure(cfg, bsp::CameraModel{}), FilterStatus::kOk);
  TruthSim truth(2, false, cfg.imu);
  bsp::ImuSample s = truth.next_imu();
  EXPECT_EQ(g_ekf.propagate(s), FilterStatus::kNotInitialized);
  ASSERT_EQ(g_ekf.init(trn::filter::InitialEstimate{}), FilterStatus::kOk);
  s.status = 1U;
  EXPECT_EQ(g_ekf.propagate(s), FilterStatus::kImuInvalid);
  EXPECT_EQ(g_ekf.state().c.imu_rejected, 1U);
  EXPECT_EQ(g_ekf.state().c.propagations, 0U);
  s.status = 0U;
  EXPECT_EQ(g_ekf.propagate(s), FilterStatus::kOk);
  s.seq += 3U;  // two samples lost
  s.t_s += 3.0 * cfg.imu_dt_s;
  EXPECT_EQ(g_ekf.propagate(s), FilterStatus::kOk);
  EXPECT_EQ(g_ekf.state().c.imu_gaps, 1U);
  // Bridged: the two lost intervals are integrated with this sample's increments, then the sample.
  EXPECT_EQ(g_ekf.state().c.propagations, 4U);
  EXPECT_EQ(g_ekf.state().t_s, s.t_s);
  // A gap longer than the bridge: kMaxBridgedSamples of it integrated, the rest left out.
  s.seq += 1U + 20U;
  s.t_s += 21.0 * cfg.imu_dt_s;
  EXPECT_EQ(g_ekf.propagate(s), FilterStatus::kOk);
  EXPECT_EQ(g_ekf.state().c.imu_gaps, 2U);
  EXPECT_EQ(g_ekf.state().c.propagations, 4U + trn::filter::kMaxBridgedSamples + 1U);
}

TEST(FilterPropagation, CountedWorkEqualsThePublishedBudgetConstants) {
  trn::filter::FilterConfig cfg;
  const bsp::CameraModel cam{};
  ASSERT_EQ(g_ekf.configure(cfg, cam), FilterStatus::kOk);
  TruthSim truth(3, false, cfg.imu);
  bsp::Rng rng(3, bsp::StreamId::kTest, 11);
  // A position known to 3 m: one linearization per match (a loose one iterates, below).
  ASSERT_EQ(g_ekf.init(filter_test::perturbed_estimate(truth, rng, 3.0, 0.1, 1e-3)), FilterStatus::kOk);
  ASSERT_FALSE(g_ekf.position_loose());
  ASSERT_EQ(g_ekf.propagate(truth.next_imu()), FilterStatus::kOk);
  EXPECT_EQ(g_ekf.take_work().flops, trn::filter::kFlopsPerPropagation);
  trn::Match m{};
  truth.make_matches(rng, cam, 1, 0.5, &m);
  trn::filter::UpdateReport rep;
  ASSERT_EQ(g_ekf.update(&m, 1, rep), FilterStatus::kOk);
  ASSERT_EQ(rep.accepted, 1U);
  // The update's row checks compute a row's exact tolerance only when its sum cancels: a bounded extra.
  const std::uint64_t match_flops = g_ekf.take_work().flops;
  EXPECT_GE(match_flops, trn::filter::kFlopsPerMatch);
  EXPECT_LE(match_flops, trn::filter::kFlopsPerMatch + trn::filter::kFlopsUpdateTolerances);
  EXPECT_EQ(g_ekf.take_work().flops, 0U);  // taking the work clears it
  // A match measured 0.3 s before the state: history, mapping, lag noise on top.
  truth.make_matches(rng, cam, 1, 0.5, &m);
  for (int k = 0; k < 30; ++k) {
    ASSERT_EQ(g_ekf.propagate(truth.next_imu()), FilterStatus::kOk);
  }
  (void)g_ekf.take_work();
  ASSERT_EQ(g_ekf.update(&m, 1, rep), FilterStatus::kOk);
  ASSERT_EQ(rep.accepted, 1U);
  const std::uint64_t lagged_flops = g_ekf.take_work().flops;
  EXPECT_GE(lagged_flops, trn::filter::kFlopsPerLaggedMatch);
  EXPECT_LE(lagged_flops, trn::filter::kFlopsPerLaggedMatch + trn::filter::kFlopsUpdateTolerances);
}

// A batch of one image's matches computes the image's pose once and injects its correction once: each
// match after the first costs kFlopsPerFurtherMatch (kFlopsPerFurtherLaggedMatch from the past).
TEST(FilterPropagation, FurtherMatchesOfABatchCostThePublishedMarginalBudget) {
  constexpr std::uint64_t kSeed = 4;
  SCOPED_TRACE(testing::Message() << "seed " << kSeed);
  trn::filter::FilterConfig cfg;
  const bsp::CameraModel cam{};
  ASSERT_EQ(g_ekf.configure(cfg, cam), FilterStatus::kOk);
  TruthSim truth(kSeed, false, cfg.imu);
  bsp::Rng rng(kSeed, bsp::StreamId::kTest, 11);
  ASSERT_EQ(g_ekf.init(filter_test::perturbed_estimate(truth, rng, 3.0, 0.1, 1e-3)), FilterStatus::kOk);
  ASSERT_EQ(g_ekf.propagate(truth.next_imu()), FilterStatus::kOk);
  constexpr std::uint32_t kN = 5;
  std::array<trn::Match, kN> m{};
  truth.make_matches(rng, cam, static_cast<int>(kN), 0.5, m.data());
  (void)g_ekf.take_work();
  trn::filter::UpdateReport rep;
  ASSERT_EQ(g_ekf.update(m.data(), kN, rep), FilterStatus::kOk);
  ASSERT_EQ(rep.accepted, kN);
  const std::uint64_t now = g_ekf.take_work().flops;
  const std::uint64_t now_base = trn::filter::kFlopsPerMatch + (kN - 1U) * trn::filter::kFlopsPerFurtherMatch;
  EXPECT_GE(now, now_base);
  EXPECT_LE(now, now_base + kN * trn::filter::kFlopsUpdateTolerances);
  truth.make_matches(rng, cam, static_cast<int>(kN), 0.5, m.data());
  for (int k = 0; k < 30; ++k) {
    ASSERT_EQ(g_ekf.propagate(truth.next_imu()), FilterStatus::kOk);
  }
  (void)g_ekf.take_work();
  ASSERT_EQ(g_ekf.update(m.data(), kN, rep), FilterStatus::kOk);
  ASSERT_EQ(rep.accepted, kN);
  const std::uint64_t past = g_ekf.take_work().flops;
  const std::uint64_t past_base =
      trn::filter::kFlopsPerLaggedMatch + (kN - 1U) * trn::filter::kFlopsPerFurtherLaggedMatch;
  EXPECT_GE(past, past_base);
  EXPECT_LE(past, past_base + kN * trn::filter::kFlopsUpdateTolerances);
}

// While some position sigma exceeds kLooseSigmaM every match is an iterated update: it is linearized again at
// the state it lands on (more than one match's work, at most kCoarseIterations of them).
TEST(FilterPropagation, ALoosePositionIteratesEachMatch) {
  trn::filter::FilterConfig cfg;
  const bsp::CameraModel cam{};
  ASSERT_EQ(g_ekf.configure(cfg, cam), FilterStatus::kOk);
  TruthSim truth(3, false, cfg.imu);
  bsp::Rng rng(3, bsp::StreamId::kTest, 11);
  ASSERT_EQ(g_ekf.init(filter_test::perturbed_estimate(truth, rng, 10.0, 0.1, 1e-3)), FilterStatus::kOk);
  ASSERT_TRUE(g_ekf.position_loose()) << "10 m > kLooseSigmaM";
  ASSERT_EQ(g_ekf.propagate(truth.next_imu()), FilterStatus::kOk);
  (void)g_ekf.take_work();
  trn::Match m{};
  truth.make_matches(rng, cam, 1, 0.5, &m);
  trn::filter::UpdateReport rep;
  ASSERT_EQ(g_ekf.update(&m, 1, rep), FilterStatus::kOk);
  ASSERT_EQ(rep.accepted, 1U);
  const std::uint64_t flops = g_ekf.take_work().flops;
  EXPECT_GT(flops, trn::filter::kFlopsPerMatch + trn::filter::kFlopsUpdateTolerances) << "linearized more than once";
  EXPECT_LE(flops, trn::filter::kCoarseIterations *
                       (trn::filter::kFlopsPerMatch + trn::filter::kFlopsUpdateTolerances + 100U));
}

}  // namespace
