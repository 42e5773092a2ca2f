/**
 * @file result_trust_test.cpp
 * @brief Result trust (FDIR-RT-xx): a worker whose results fail is suspect, not used, reset,
 *        replaced if it stays wrong; a transient comes back; rare failures are not suspect.
 */
#include "fdir/result_trust.hpp"

#include "tests/fdir/fdir_fixture.hpp"

#include <gtest/gtest.h>

#include <array>
#include <random>

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
