/**
 * @file liveness_test.cpp
 * @brief Worker liveness (FDIR-LV-xx): isolation after N misses, probe rounds, return, events.
 */
#include "fdir/liveness.hpp"

#include "tests/fdir/fdir_fixture.hpp"

#include <gtest/gtest.h>

#include <array>

namespace {

constexpr std::array<bsp::TileId, 3> kTiles = {24U, 25U, 26U};

// FDIR-LV-01
TEST(Liveness, AWorkerMissingTwiceIsIsolatedProbedAndBackWhenItAnswers) {
  fdir::Liveness l{};
  ASSERT_EQ(fdir::liveness_init(l, fdir::LivenessConfig{2U, 5U}, kTiles.data(), 3U), fdir::LivenessError::kOk);
  fdir::liveness_missed(l, 1U);
  EXPECT_TRUE(fdir::liveness_gets_work(l, 1U, 1U)) << "one miss";
  fdir::liveness_missed(l, 1U);
  EXPECT_EQ(fdir::liveness_isolated(l), 1U);
  EXPECT_FALSE(fdir::liveness_gets_work(l, 1U, 1U));
  EXPECT_TRUE(fdir::liveness_gets_work(l, 1U, 5U)) << "probe round";
  EXPECT_TRUE(fdir::liveness_gets_work(l, 0U, 1U));
  fdir::liveness_answered(l, 1U);
  EXPECT_EQ(fdir::liveness_isolated(l), 0U);
  EXPECT_TRUE(fdir::liveness_gets_work(l, 1U, 1U));
}

TEST(Liveness, BadSettingsAreRefused) {
  fdir::Liveness l{};
  EXPECT_EQ(fdir::liveness_init(l, fdir::LivenessConfig{0U, 5U}, kTiles.data(), 3U), fdir::LivenessError::kBadConfig);
  EXPECT_EQ(fdir::liveness_init(l, fdir::LivenessConfig{2U, 0U}, kTiles.data(), 3U), fdir::LivenessError::kBadConfig);
  EXPECT_EQ(fdir::liveness_init(l, fdir::LivenessConfig{2U, 5U}, kTiles.data(), fdir::kMaxWorkers + 1U),
            fdir::LivenessError::kBadConfig);
}

// FDIR-LV-02: isolation and return are flight events naming the worker, once each.
TEST(Liveness, IsolationAndReturnAreEventsOnTheCoordinatorsTile) {
  fdir_test::run_on_tile0([] {
    static fdir::Liveness l{};
    (void)fdir::liveness_init(l, fdir::LivenessConfig{2U, 5U}, kTiles.data(), 3U);
    for (int i = 0; i < 4; ++i) {
      fdir::liveness_missed(l, 2U);
    }
    fdir::liveness_answered(l, 2U);
    fdir::liveness_answered(l, 2U);
  });
  const std::vector<fdir::Event> ev = fdir_test::events_of(0);
  ASSERT_EQ(ev.size(), 2U);
  EXPECT_EQ(ev[0].id, fdir::EventId::kWorkerSilent);
  EXPECT_EQ(ev[0].subject, 26U);
  EXPECT_EQ(ev[1].id, fdir::EventId::kWorkerBack);
  EXPECT_EQ(ev[1].subject, 26U);
}

}  // namespace
