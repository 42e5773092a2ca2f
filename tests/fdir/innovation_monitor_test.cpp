/**
 * @file innovation_monitor_test.cpp
 * @brief The innovation monitor (FDIR-IM-xx): a filter whose measurements agree with its
 *        covariance is never failed; one whose innovations grow, or whose matches the gate keeps
 *        rejecting, is failed within a window.
 */
#include "fdir/innovation_monitor.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

namespace {

constexpr double kGate = 13.815510558;  // 99.9 %, 2 degrees of freedom

/** What one job of @p n measurements gives: d2 drawn as chi-square 2 dof times @p scale. */
struct Job {
  std::uint32_t n = 0U;
  std::uint32_t rejected = 0U;
  double nis = 0.0;
};

Job draw(std::mt19937_64& rng, std::uint32_t n, double scale) {
  std::exponential_distribution<double> chi2_2dof(0.5);  // mean 2
  Job j{};
  j.n = n;
  for (std::uint32_t i = 0; i < n; ++i) {
    const double d2 = scale * chi2_2dof(rng);
    j.rejected += d2 > kGate ? 1U : 0U;
    j.nis += d2 < kGate ? d2 : kGate;
  }
  return j;
}

fdir::InnovationVerdict add(fdir::InnovationMonitor& m, const Job& j, fdir::InnovationWindow& w) {
  bsp::Work work{};
  return fdir::innovation_add(m, fdir::InnovationMonitorConfig{}, kGate, j.n, j.rejected, j.nis, w, work);
}

}  // namespace

// FDIR-IM-01: the clipped chi-square's mean and variance are the law's (checked against a draw).
TEST(InnovationMonitor, TheClippedChiSquareMomentsAreTheLaws) {
  EXPECT_NEAR(fdir::clipped_chi2_mean(kGate), 1.998, 1e-3);
  std::mt19937_64 rng(7U);
  std::exponential_distribution<double> e(0.5);
  double s = 0.0;
  double s2 = 0.0;
  constexpr int kN = 400000;
  for (int i = 0; i < kN; ++i) {
    const double d = std::min(e(rng), kGate);
    s += d;
    s2 += d * d;
  }
  const double mean = s / kN;
  EXPECT_NEAR(mean, fdir::clipped_chi2_mean(kGate), 0.01);
  EXPECT_NEAR(s2 / kN - mean * mean, fdir::clipped_chi2_var(kGate), 0.05);
}

// FDIR-IM-02: a consistent filter (d2 as the law, and 40 % below it) is never failed over 20 000 windows.
TEST(InnovationMonitor, AConsistentFilterIsNeverFailed) {
  for (const double scale : {1.0, 0.6, 1.3}) {
    std::mt19937_64 rng(11U);
    fdir::InnovationMonitor m{};
    fdir::innovation_clear(m);
    std::uint32_t judged = 0U;
    for (int job = 0; job < 100000; ++job) {
      fdir::InnovationWindow w{};
      const fdir::InnovationVerdict v = add(m, draw(rng, 1U + static_cast<std::uint32_t>(job % 9), scale), w);
      ASSERT_TRUE(v == fdir::InnovationVerdict::kNone || v == fdir::InnovationVerdict::kConsistent)
          << "scale " << scale << " job " << job << " n " << w.n << " rejected " << w.rejected << " mean "
          << w.mean_nis_milli;
      judged += v == fdir::InnovationVerdict::kConsistent ? 1U : 0U;
    }
    EXPECT_GT(judged, 20000U);
  }
}

// FDIR-IM-03: innovations 3x the covariance's fail a window on their mean; one of those windows is enough.
TEST(InnovationMonitor, InnovationsLargerThanTheCovarianceFailAWindow) {
  std::mt19937_64 rng(3U);
  fdir::InnovationMonitor m{};
  fdir::innovation_clear(m);
  fdir::InnovationVerdict v = fdir::InnovationVerdict::kNone;
  fdir::InnovationWindow w{};
  std::uint32_t matches = 0U;
  while (v == fdir::InnovationVerdict::kNone && matches < 1000U) {
    v = add(m, draw(rng, 10U, 3.0), w);
    matches += 10U;
  }
  EXPECT_TRUE(v == fdir::InnovationVerdict::kNisHigh || v == fdir::InnovationVerdict::kRejectedHigh);
  EXPECT_LE(matches, 120U);  // the first full window: 6 blocks of 20
  EXPECT_GT(w.mean_nis_milli, 4000U);
}

// FDIR-IM-04: matches the gate rejects (a state off by more than the gate) fail on the rejected fraction.
TEST(InnovationMonitor, MatchesTheGateKeepsRejectingFailAWindow) {
  fdir::InnovationMonitor m{};
  fdir::innovation_clear(m);
  fdir::InnovationWindow w{};
  fdir::InnovationVerdict v = fdir::InnovationVerdict::kNone;
  for (int job = 0; job < 12 && v == fdir::InnovationVerdict::kNone; ++job) {
    v = add(m, Job{10U, 4U, 4.0 * kGate + 6.0 * 1.5}, w);
  }
  EXPECT_EQ(v, fdir::InnovationVerdict::kRejectedHigh);
  EXPECT_EQ(w.n, 120U);
  EXPECT_EQ(w.rejected, 48U);
  // Cleared, it judges afresh: the next window is consistent.
  fdir::innovation_clear(m);
  std::mt19937_64 rng(5U);
  v = fdir::InnovationVerdict::kNone;
  while (v == fdir::InnovationVerdict::kNone) {
    v = add(m, draw(rng, 10U, 1.0), w);
  }
  EXPECT_EQ(v, fdir::InnovationVerdict::kConsistent);
}

// FDIR-IM-05: a count or sum an upset left absurd is bounded; a bad configuration is refused.
TEST(InnovationMonitor, AbsurdInputsAreBoundedAndBadSettingsRefused) {
  fdir::InnovationMonitor m{};
  fdir::innovation_clear(m);
  m.next = 0xFFFFFFF0U;  // an upset of the ring's place
  fdir::InnovationWindow w{};
  for (int i = 0; i < 6; ++i) {
    bsp::Work work{};
    (void)fdir::innovation_add(m, fdir::InnovationMonitorConfig{}, kGate, 20U, 30U, std::nan(""), w, work);
  }
  EXPECT_LE(w.rejected, w.n);
  fdir::InnovationMonitorConfig c{};
  EXPECT_TRUE(fdir::innovation_config_ok(c));
  c.window_blocks = fdir::kMaxInnovationBlocks + 1U;
  EXPECT_FALSE(fdir::innovation_config_ok(c));
  c = fdir::InnovationMonitorConfig{};
  c.block_matches = 0U;
  EXPECT_FALSE(fdir::innovation_config_ok(c));
}
