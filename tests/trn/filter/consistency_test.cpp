/**
 * @file consistency_test.cpp
 * @brief With landmark updates the filter is consistent (averaged NEES within 95 % chi-square
 *        bounds over 20 seeded runs) and converges; gross outliers are gated, counted, not applied.
 */
#include "tests/trn/filter/truth_sim.hpp"
#include "trn/filter/ekf.hpp"
#include "trn/filter/state_block.hpp"

#include <gtest/gtest.h>

#include <array>
#include <bit>
#include <cstdio>
#include <cstdlib>

namespace {

using filter_test::TruthSim;
using filter_test::Vec3;
using trn::filter::Ekf;
using trn::filter::FilterStatus;
using trn::filter::UpdateReport;

Ekf g_ekf;
std::array<trn::Match, trn::kMaxMatchesPerFrame> g_matches{};

constexpr int kRuns = 20;
/** Seeds kSeedBase .. kSeedBase+19; TRN_FILTER_SEED_BASE reruns the test on another set. */
const std::uint64_t kSeedBase =
    std::getenv("TRN_FILTER_SEED_BASE") != nullptr ? std::strtoull(std::getenv("TRN_FILTER_SEED_BASE"), nullptr, 10)
                                                   : 2000U;
constexpr int kSeconds = 30;
constexpr int kMatchesPerFrame = 20;
constexpr double kPixelSigma = 0.5;

struct NeesSeries {
  std::array<filter_test::Nees3, kSeconds> sum{};
};

/** One seeded run: 1 Hz frames of kMatchesPerFrame bearings; NEES summed at each frame. */
void run_once(std::uint64_t seed, NeesSeries& acc, double& final_pos_err_m) {
  SCOPED_TRACE(testing::Message() << "seed " << seed << " (base " << kSeedBase << ")");
  trn::filter::FilterConfig cfg;
  const bsp::CameraModel cam{};
  ASSERT_EQ(g_ekf.configure(cfg, cam), FilterStatus::kOk);
  TruthSim truth(seed, true, cfg.imu);
  bsp::Rng rng(seed, bsp::StreamId::kTest, 2);
  ASSERT_EQ(g_ekf.init(filter_test::perturbed_estimate(truth, rng, 50.0, 0.5, 2e-3)), FilterStatus::kOk);
  for (int sec = 0; sec < kSeconds; ++sec) {
    for (int k = 0; k < 100; ++k) {
      ASSERT_EQ(g_ekf.propagate(truth.next_imu()), FilterStatus::kOk);
    }
    truth.make_matches(rng, cam, kMatchesPerFrame, kPixelSigma, g_matches.data());
    UpdateReport rep;
    ASSERT_EQ(g_ekf.update(g_matches.data(), kMatchesPerFrame, rep), FilterStatus::kOk);
    EXPECT_EQ(rep.rejected_invalid, 0U);
    const filter_test::Nees3 n = filter_test::nees(truth, g_ekf.state());
    acc.sum[static_cast<std::size_t>(sec)].p += n.p;
    acc.sum[static_cast<std::size_t>(sec)].v += n.v;
    acc.sum[static_cast<std::size_t>(sec)].th += n.th;
  }
  final_pos_err_m = (truth.p() - g_ekf.state().x.p_m).norm();
}

TEST(FilterConsistency, AveragedNeesOf20RunsStaysInside95PercentBounds) {
  NeesSeries acc;
  double worst_err_m = 0.0;
  for (int run = 0; run < kRuns; ++run) {
    double err_m = 0.0;
    run_once(kSeedBase + static_cast<std::uint64_t>(run), acc, err_m);
    ASSERT_FALSE(HasFatalFailure());
    worst_err_m = err_m > worst_err_m ? err_m : worst_err_m;
  }
  // N runs: N * (average NEES of a 3-dof block) is chi-square with 3N dof.
  const double lo = filter_test::chi2_quantile(0.025, 3.0 * kRuns) / kRuns;
  const double hi = filter_test::chi2_quantile(0.975, 3.0 * kRuns) / kRuns;
  int inside[3] = {0, 0, 0};
  double mean[3] = {0.0, 0.0, 0.0};
  for (const filter_test::Nees3& s : acc.sum) {
    const double a[3] = {s.p / kRuns, s.v / kRuns, s.th / kRuns};
    for (int b = 0; b < 3; ++b) {
      inside[b] += (a[b] > lo && a[b] < hi) ? 1 : 0;
      mean[b] += a[b] / kSeconds;
    }
  }
  std::printf("seeds %llu+: %d runs x %d frames: NEES mean p %.2f v %.2f th %.2f; inside [%.3f, %.3f]: %d %d %d of %d;"
              " worst final |dp| %.2f m\n",
              static_cast<unsigned long long>(kSeedBase), kRuns, kSeconds, mean[0], mean[1], mean[2], lo, hi, inside[0], inside[1], inside[2], kSeconds,
              worst_err_m);
  // Each frame's average falls outside with 5 % chance when consistent, but
  // frames are correlated in time (errors persist between frames), so
  // excursions come in runs of several frames: over seed bases 2000..7000
  // 77 % to 100 % of frames were inside and every time-mean was within the
  // bounds. Require 75 % of frames inside and the time-mean inside.
  for (int b = 0; b < 3; ++b) {
    EXPECT_GE(inside[b], kSeconds * 3 / 4) << "block " << b;
    EXPECT_GT(mean[b], lo) << "block " << b;
    EXPECT_LT(mean[b], hi) << "block " << b;
  }
  EXPECT_LT(worst_err_m, 10.0);
}

TEST(FilterConsistency, GrossOutliersAreGatedCountedAndNotApplied) {
  constexpr std::uint64_t kSeed = 77;
  SCOPED_TRACE(testing::Message() << "seed " << kSeed);
  trn::filter::FilterConfig cfg;
  const bsp::CameraModel cam{};
  ASSERT_EQ(g_ekf.configure(cfg, cam), FilterStatus::kOk);
  TruthSim truth(kSeed, true, cfg.imu);
  bsp::Rng rng(kSeed, bsp::StreamId::kTest, 3);
  ASSERT_EQ(g_ekf.init(filter_test::perturbed_estimate(truth, rng, 50.0, 0.5, 2e-3)), FilterStatus::kOk);
  // Converge first, so outliers of 40 px stand far above the predicted spread.
  std::uint32_t expected_gate = 0;
  for (int sec = 0; sec < 10; ++sec) {
    for (int k = 0; k < 100; ++k) {
      ASSERT_EQ(g_ekf.propagate(truth.next_imu()), FilterStatus::kOk);
    }
    truth.make_matches(rng, cam, 40, kPixelSigma, g_matches.data());
    std::uint32_t outliers = 0;
    for (int i = 0; i < 40; i += 5) {  // every fifth match: a gross mismatch
      trn::Match& m = g_matches[static_cast<std::size_t>(i)];
      const Vec3 w = Vec3(m.w_c[0] / m.w_c[2] + 40.0 / cam.fx_px, m.w_c[1] / m.w_c[2] - 40.0 / cam.fy_px, 1.0)
                         .normalized();
      m.w_c[0] = w.x();
      m.w_c[1] = w.y();
      m.w_c[2] = w.z();
      ++outliers;
    }
    UpdateReport rep;
    ASSERT_EQ(g_ekf.update(g_matches.data(), 40, rep), FilterStatus::kOk);
    if (sec >= 2) {  // after two frames the position is known to metres
      EXPECT_EQ(rep.rejected_gate, outliers) << "second " << sec;
      expected_gate += outliers;
    }
    EXPECT_GE(rep.accepted, 30U) << "second " << sec;
  }
  EXPECT_GE(g_ekf.state().c.rejected_gate, expected_gate);
  EXPECT_LT((truth.p() - g_ekf.state().x.p_m).norm(), 10.0);

  // A batch of outliers only: counted, and the state (nominal and covariance) is untouched bit for bit.
  static trn::filter::StateBlock before;
  static trn::filter::StateBlock after;
  ASSERT_EQ(trn::filter::write_state_block(g_ekf.state(), before), trn::filter::BlockError::kOk);
  const trn::filter::FilterState s0 = g_ekf.state();
  for (int i = 0; i < 10; ++i) {
    g_matches[static_cast<std::size_t>(i)].w_c[0] += 0.2;  // ~100 px off
  }
  UpdateReport rep;
  ASSERT_EQ(g_ekf.update(g_matches.data(), 10, rep), FilterStatus::kOk);
  EXPECT_EQ(rep.rejected_gate, 10U);
  EXPECT_EQ(rep.accepted, 0U);
  ASSERT_EQ(trn::filter::write_state_block(g_ekf.state(), after), trn::filter::BlockError::kOk);
  for (int i = 0; i < 225; ++i) {
    ASSERT_EQ(std::bit_cast<std::uint64_t>(g_ekf.state().p.data()[i]), std::bit_cast<std::uint64_t>(s0.p.data()[i]))
        << "covariance element " << i;
  }
  EXPECT_EQ(g_ekf.state().x.p_m, s0.x.p_m);
  EXPECT_EQ(g_ekf.state().x.q_mb.coeffs(), s0.x.q_mb.coeffs());
  EXPECT_EQ(g_ekf.state().c.rejected_gate, s0.c.rejected_gate + 10U);
  EXPECT_NE(before, after);  // only the counters changed
}

TEST(FilterConsistency, InvalidMatchesAreCountedSeparately) {
  trn::filter::FilterConfig cfg;
  const bsp::CameraModel cam{};
  ASSERT_EQ(g_ekf.configure(cfg, cam), FilterStatus::kOk);
  TruthSim truth(5, false, cfg.imu);
  bsp::Rng rng(5, bsp::StreamId::kTest, 4);
  ASSERT_EQ(g_ekf.init(filter_test::perturbed_estimate(truth, rng, 10.0, 0.1, 1e-3)), FilterStatus::kOk);
  truth.make_matches(rng, cam, 4, kPixelSigma, g_matches.data());
  g_matches[0].w_c[2] = -g_matches[0].w_c[2];      // bearing pointing backwards
  g_matches[1].p_m[2] = truth.p().z() + 1000.0;    // landmark above the camera
  g_matches[2].sigma_px = 0.0;                      // no noise claimed: refused
  UpdateReport rep;
  ASSERT_EQ(g_ekf.update(g_matches.data(), 4, rep), FilterStatus::kOk);
  EXPECT_EQ(rep.rejected_invalid, 3U);
  EXPECT_EQ(rep.accepted, 1U);
  EXPECT_EQ(g_ekf.update(nullptr, 1, rep), FilterStatus::kBadInput);
  EXPECT_EQ(g_ekf.update(g_matches.data(), trn::kMaxMatchesPerFrame + 1U, rep), FilterStatus::kBadInput);
}

}  // namespace
