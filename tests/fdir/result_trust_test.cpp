/**
 * @file result_trust_test.cpp
 * @brief Result trust (FDIR-RT-xx): a worker whose results fail is suspect, not used, reset,
 *        replaced if it stays wrong; a transient comes back; rare failures are not suspect.
 */
#include "fdir/result_trust.hpp"

#include "tests/fdir/fdir_fixture.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <random>
#include <vector>

namespace {

constexpr std::array<bsp::TileId, 3> kTiles = {24U, 25U, 26U};

/** One round: worker @p bad gets (checked, failed), the others 5 clean results. */
fdir::TrustAction round(fdir::ResultTrust& t, std::uint32_t bad, std::uint32_t checked, std::uint32_t failed) {
  fdir::TrustAction a = fdir::TrustAction::kNone;
  for (std::uint32_t i = 0; i < t.count; ++i) {
    const fdir::TrustAction ai = i == bad ? fdir::result_trust_round(t, i, checked, failed)
                                          : fdir::result_trust_round(t, i, 5U, 0U);
    if (i == bad) {
      a = ai;
    }
  }
  fdir::result_trust_close_round(t);
  return a;
}

// FDIR-RT-01: wrong results every round: suspect at once, reset after 2 more rounds, replaced when still wrong.
TEST(ResultTrust, AWorkerThatStaysWrongIsSuspectResetThenReplaced) {
  fdir::ResultTrust t{};
  ASSERT_EQ(fdir::result_trust_init(t, fdir::ResultTrustConfig{}, kTiles.data(), 3U), fdir::TrustError::kOk);
  EXPECT_EQ(round(t, 1U, 5U, 5U), fdir::TrustAction::kNone);
  EXPECT_FALSE(fdir::result_trust_used(t, 1U));
  EXPECT_TRUE(fdir::result_trust_used(t, 0U));
  EXPECT_EQ(fdir::result_trust_untrusted(t), 1U);
  EXPECT_EQ(round(t, 1U, 5U, 5U), fdir::TrustAction::kNone);
  EXPECT_EQ(round(t, 1U, 5U, 5U), fdir::TrustAction::kReset);
  EXPECT_EQ(round(t, 1U, 0U, 0U), fdir::TrustAction::kNone) << "booting: nothing checked";
  EXPECT_EQ(round(t, 1U, 2U, 2U), fdir::TrustAction::kNone) << "2 failed: under min_failed";
  EXPECT_EQ(round(t, 1U, 5U, 5U), fdir::TrustAction::kReplace);
  EXPECT_EQ(round(t, 1U, 5U, 5U), fdir::TrustAction::kNone) << "asked once";
  fdir::result_trust_replace(t, 1U, 40U);
  EXPECT_TRUE(fdir::result_trust_used(t, 1U));
  EXPECT_EQ(t.tile[1], 40U);
  EXPECT_EQ(round(t, 1U, 5U, 0U), fdir::TrustAction::kNone);
  EXPECT_TRUE(fdir::result_trust_used(t, 1U));
}

// FDIR-RT-02: a transient: suspect, then probation clean rounds make it trusted without a reset.
TEST(ResultTrust, ATransientComesBackAfterProbation) {
  fdir::ResultTrust t{};
  ASSERT_EQ(fdir::result_trust_init(t, fdir::ResultTrustConfig{}, kTiles.data(), 3U), fdir::TrustError::kOk);
  EXPECT_EQ(round(t, 2U, 4U, 4U), fdir::TrustAction::kNone);
  EXPECT_FALSE(fdir::result_trust_used(t, 2U));
  for (int r = 0; r < 2; ++r) {
    EXPECT_EQ(round(t, 2U, 5U, 0U), fdir::TrustAction::kNone);
    EXPECT_FALSE(fdir::result_trust_used(t, 2U)) << "on probation";
  }
  EXPECT_EQ(round(t, 2U, 5U, 0U), fdir::TrustAction::kNone);
  EXPECT_TRUE(fdir::result_trust_used(t, 2U));
}

// FDIR-RT-03: the false-alarm side: one failure in 15, or a minority of failures, never makes a worker suspect.
TEST(ResultTrust, RareOrMinorityFailuresAreNotSuspect) {
  fdir::ResultTrust t{};
  ASSERT_EQ(fdir::result_trust_init(t, fdir::ResultTrustConfig{}, kTiles.data(), 3U), fdir::TrustError::kOk);
  for (int r = 0; r < 30; ++r) {
    EXPECT_EQ(round(t, 0U, 5U, r % 3 == 0 ? 1U : 0U), fdir::TrustAction::kNone);
  }
  for (int r = 0; r < 30; ++r) {
    EXPECT_EQ(round(t, 0U, 8U, 3U), fdir::TrustAction::kNone) << "9 of 24 in the window: a minority";
  }
  EXPECT_EQ(fdir::result_trust_untrusted(t), 0U);
  // Independent failures at 10x the measured clean rate (1e-2 per result) over 10^5 rounds: none suspect.
  std::mt19937_64 rng(7U);
  std::bernoulli_distribution fail(1e-2);
  for (int r = 0; r < 100000; ++r) {
    std::uint32_t f = 0U;
    for (int k = 0; k < 5; ++k) {
      f += fail(rng) ? 1U : 0U;
    }
    (void)round(t, 1U, 5U, f);
  }
  EXPECT_EQ(fdir::result_trust_untrusted(t), 0U);
}

/** One round of the bias test: worker @p bad's 4 results shifted by @p shift_px in u, every result with noise. */
fdir::TrustAction bias_round(fdir::ResultTrust& t, std::uint32_t bad, double shift_px, std::mt19937& rng) {
  std::normal_distribution<double> noise(0.0, 0.15);
  fdir::TrustAction a = fdir::TrustAction::kNone;
  for (std::uint32_t i = 0; i < t.count; ++i) {
    fdir::RoundResiduals r{};
    r.scale = 0.15;
    for (int k = 0; k < 4; ++k) {
      fdir::result_trust_add_residual(t, r, noise(rng) + (i == bad ? shift_px : 0.0), noise(rng));
    }
    const fdir::TrustAction ai = fdir::result_trust_round(t, i, 4U, 0U, r);
    a = i == bad ? ai : a;
  }
  fdir::result_trust_close_round(t);
  return a;
}

// FDIR-RT-07: a worker whose results are all shifted alike by half a pixel (each passes the per-result
// test) is suspect once its bias window holds bias_min of them (3 rounds of 4), reset, and replaced when
// still shifted after the reset; the event says the bias (cause 2, 3) and the count.
TEST(ResultTrust, AWorkerShiftedByHalfAPixelIsFoundByTheMeanOfItsResiduals) {
  fdir_test::run_on_tile0([] {
    static fdir::ResultTrust t{};
    (void)fdir::result_trust_init(t, fdir::ResultTrustConfig{}, kTiles.data(), 3U);
    SCOPED_TRACE("noise seed 7");
    std::mt19937 rng(7U);
    EXPECT_EQ(bias_round(t, 1U, 0.5, rng), fdir::TrustAction::kNone);
    EXPECT_EQ(bias_round(t, 1U, 0.5, rng), fdir::TrustAction::kNone);
    EXPECT_TRUE(fdir::result_trust_used(t, 1U)) << "8 results: under bias_min";
    EXPECT_EQ(bias_round(t, 1U, 0.5, rng), fdir::TrustAction::kNone);
    EXPECT_FALSE(fdir::result_trust_used(t, 1U)) << "12 results 0.5 px off on average: suspect";
    EXPECT_TRUE(fdir::result_trust_used(t, 0U));
    EXPECT_NEAR(fdir::result_trust_bias_px(t, 1U), 0.5, 0.1);
    EXPECT_EQ(bias_round(t, 1U, 0.5, rng), fdir::TrustAction::kNone);
    EXPECT_EQ(bias_round(t, 1U, 0.5, rng), fdir::TrustAction::kReset) << "2 rounds still biased";
    EXPECT_EQ(bias_round(t, 1U, 0.5, rng), fdir::TrustAction::kNone);
    EXPECT_EQ(bias_round(t, 1U, 0.5, rng), fdir::TrustAction::kNone);
    EXPECT_EQ(bias_round(t, 1U, 0.5, rng), fdir::TrustAction::kReplace) << "biased again after its reset";
  });
  const std::vector<fdir::Event> ev = fdir_test::events_of(0);
  ASSERT_EQ(ev.size(), 2U);
  EXPECT_EQ(ev[0].id, fdir::EventId::kResultsSuspect);
  EXPECT_EQ(ev[0].subject, 25U);
  EXPECT_EQ(ev[0].cause, 2U) << "by the bias test";
  EXPECT_NEAR(ev[0].a, 500.0, 100.0) << "the mean residual in thousandths of a pixel";
  EXPECT_EQ(ev[0].b, 12U);
  EXPECT_EQ(ev[1].cause, 3U) << "again after the reset, by the bias test";
}

// FDIR-RT-07 (after a reset): a shifted worker with 2 results a round has too few in its bias window
// for a verdict for 5 rounds after its reset; those rounds are not clean, so it is not trusted again
// on them, and once the window judges it, it is replaced (not reset a second time).
TEST(ResultTrust, AShiftedWorkerJustResetIsNotTrustedAgainBeforeItsBiasIsJudged) {
  SCOPED_TRACE("noise seed 5");
  fdir::ResultTrust t{};
  ASSERT_EQ(fdir::result_trust_init(t, fdir::ResultTrustConfig{}, kTiles.data(), 3U), fdir::TrustError::kOk);
  std::mt19937 rng(5U);
  std::normal_distribution<double> noise(0.0, 0.15);
  const auto shifted_round = [&](std::uint32_t n) {
    fdir::TrustAction a = fdir::TrustAction::kNone;
    for (std::uint32_t i = 0; i < t.count; ++i) {
      fdir::RoundResiduals r{};
      r.scale = 0.15;
      for (std::uint32_t k = 0; k < n; ++k) {
        fdir::result_trust_add_residual(t, r, noise(rng) + (i == 1U ? 0.6 : 0.0), noise(rng));
      }
      const fdir::TrustAction ai = fdir::result_trust_round(t, i, n, 0U, r);
      a = i == 1U ? ai : a;
    }
    fdir::result_trust_close_round(t);
    return a;
  };
  std::vector<fdir::TrustAction> actions;
  for (int r = 0; r < 20; ++r) {
    actions.push_back(shifted_round(2U));
    if (actions.back() == fdir::TrustAction::kReplace) {
      break;
    }
    if (actions.back() == fdir::TrustAction::kNone && r > 8) {
      EXPECT_FALSE(fdir::result_trust_used(t, 1U)) << "round " << r << ": not trusted again while shifted";
    }
  }
  EXPECT_EQ(std::count(actions.begin(), actions.end(), fdir::TrustAction::kReset), 1);
  EXPECT_EQ(actions.back(), fdir::TrustAction::kReplace);
}

// FDIR-RT-08: the bias test's false-alarm side: 40 workers of clean results with a tail (one in 50
// off by up to 0.99 px, under the per-result floor) over 5000 rounds: none suspect; one large residual
// weighs no more than the clip.
TEST(ResultTrust, CleanResultsWithATailAreNeverBiased) {
  std::array<bsp::TileId, 40> tiles{};
  for (std::uint32_t i = 0; i < tiles.size(); ++i) {
    tiles[i] = static_cast<bsp::TileId>(i + 20U);
  }
  fdir::ResultTrust t{};
  ASSERT_EQ(fdir::result_trust_init(t, fdir::ResultTrustConfig{}, tiles.data(), 40U), fdir::TrustError::kOk);
  SCOPED_TRACE("noise seed 11");
  std::mt19937 rng(11U);
  std::normal_distribution<double> noise(0.0, 0.15);
  std::uniform_real_distribution<double> tail(-0.99, 0.99);
  std::uniform_int_distribution<int> pick(0, 49);
  std::uniform_int_distribution<std::uint32_t> count(2U, 6U);
  double worst = 0.0;
  for (int round_no = 0; round_no < 5000; ++round_no) {
    for (std::uint32_t i = 0; i < 40U; ++i) {
      fdir::RoundResiduals r{};
      r.scale = 0.15;
      const std::uint32_t n = count(rng);
      for (std::uint32_t k = 0; k < n; ++k) {
        const double du = pick(rng) == 0 ? tail(rng) : noise(rng);
        fdir::result_trust_add_residual(t, r, du, noise(rng));
      }
      EXPECT_EQ(fdir::result_trust_round(t, i, n, 0U, r), fdir::TrustAction::kNone);
      worst = std::max(worst, fdir::result_trust_bias_px(t, i));
    }
    fdir::result_trust_close_round(t);
  }
  EXPECT_EQ(fdir::result_trust_untrusted(t), 0U);
  EXPECT_LT(worst, 0.2) << "the largest clean window mean, against the 0.28 px floor";
  fdir::RoundResiduals one{};
  fdir::result_trust_add_residual(t, one, 5.0, -5.0);
  EXPECT_DOUBLE_EQ(one.sum_u, 0.6);
  EXPECT_DOUBLE_EQ(one.sum_v, -0.6);
}

TEST(ResultTrust, BadSettingsAreRefused) {
  fdir::ResultTrust t{};
  EXPECT_EQ(fdir::result_trust_init(t, fdir::ResultTrustConfig{0U, 3U, 2U, 3U}, kTiles.data(), 3U),
            fdir::TrustError::kBadConfig);
  EXPECT_EQ(fdir::result_trust_init(t, fdir::ResultTrustConfig{fdir::kMaxTrustWindow + 1U, 3U, 2U, 3U}, kTiles.data(),
                                    3U),
            fdir::TrustError::kBadConfig);
  EXPECT_EQ(fdir::result_trust_init(t, fdir::ResultTrustConfig{3U, 0U, 2U, 3U}, kTiles.data(), 3U),
            fdir::TrustError::kBadConfig);
  EXPECT_EQ(fdir::result_trust_init(t, fdir::ResultTrustConfig{}, kTiles.data(), fdir::kMaxTrustWorkers + 1U),
            fdir::TrustError::kBadConfig);
  EXPECT_EQ(fdir::result_trust_init(t, fdir::ResultTrustConfig{}, nullptr, 2U), fdir::TrustError::kBadConfig);
  fdir::ResultTrustConfig c{};
  c.bias_window = fdir::kMaxTrustWindow + 1U;
  EXPECT_EQ(fdir::result_trust_init(t, c, kTiles.data(), 3U), fdir::TrustError::kBadConfig);
  c = fdir::ResultTrustConfig{};
  c.bias_min = 1U;
  EXPECT_EQ(fdir::result_trust_init(t, c, kTiles.data(), 3U), fdir::TrustError::kBadConfig);
  c = fdir::ResultTrustConfig{};
  c.bias_sigmas = 0U;
  EXPECT_EQ(fdir::result_trust_init(t, c, kTiles.data(), 3U), fdir::TrustError::kBadConfig);
}

// FDIR-RT-04: every change is a flight event naming the tile.
TEST(ResultTrust, SuspectAndConsistentAreEventsOnTheCoordinatorsTile) {
  fdir_test::run_on_tile0([] {
    static fdir::ResultTrust t{};
    (void)fdir::result_trust_init(t, fdir::ResultTrustConfig{}, kTiles.data(), 3U);
    (void)round(t, 1U, 5U, 4U);
    for (int r = 0; r < 3; ++r) {
      (void)round(t, 1U, 5U, 0U);
    }
    for (int r = 0; r < 6; ++r) {
      (void)round(t, 1U, 5U, 5U);
    }
  });
  const std::vector<fdir::Event> ev = fdir_test::events_of(0);
  ASSERT_EQ(ev.size(), 4U);
  EXPECT_EQ(ev[0].id, fdir::EventId::kResultsSuspect);
  EXPECT_EQ(ev[0].subject, 25U);
  EXPECT_EQ(ev[0].a, 4U);
  EXPECT_EQ(ev[0].b, 5U);
  EXPECT_EQ(ev[1].id, fdir::EventId::kResultsConsistent);
  EXPECT_EQ(ev[1].cause, 0U);
  EXPECT_EQ(ev[2].id, fdir::EventId::kResultsSuspect);
  EXPECT_EQ(ev[2].cause, 0U);
  EXPECT_EQ(ev[3].id, fdir::EventId::kResultsSuspect) << "again after the reset: replacement asked";
  EXPECT_EQ(ev[3].cause, 1U);
}

}  // namespace
