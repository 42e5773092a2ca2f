/**
 * @file udn_stress_plan_test.cpp
 * @brief udn_stress traffic plan: who sends and is sent to in each mode, quotas, and destinations
 *        by pattern that never name a tile left out of the traffic.
 */
#include "tools/common/udn_stress/udn_stress_plan.hpp"

#include <gtest/gtest.h>

#include <array>
#include <cstdint>

namespace {

using tools::detail::make_plan;
using tools::detail::pick_destination;
using tools::detail::TrafficPlan;

TEST(UdnStressPlan, FailedTilesAreOutInBothModesFailedSwitchesOnlyWithFt) {
  tools::StressOptions o;
  o.packets = 1000U;
  o.failed_tiles = {5U};
  o.failed_switches = {9U};
  const TrafficPlan raw = make_plan(o);
  EXPECT_FALSE(raw.sends[5]);
  EXPECT_FALSE(raw.addressed[5]);
  EXPECT_TRUE(raw.sends[9]);  // a raw tile does not know its switch failed
  EXPECT_TRUE(raw.addressed[9]);
  EXPECT_EQ(raw.sender_count, 63U);
  o.ft = true;
  const TrafficPlan ft = make_plan(o);
  EXPECT_FALSE(ft.sends[5]);
  EXPECT_FALSE(ft.sends[9]);
  EXPECT_FALSE(ft.addressed[9]);
  EXPECT_EQ(ft.sender_count, 62U);
  for (const TrafficPlan* p : {&raw, &ft}) {
    std::uint64_t total = 0U;
    std::uint64_t most = 0U;
    std::uint64_t least = ~0ULL;
    for (bsp::TileId t = 0; t < 64U; ++t) {
      total += p->quota[t];
      if (p->sends[t]) {
        most = std::max(most, p->quota[t]);
        least = std::min(least, p->quota[t]);
      } else {
        EXPECT_EQ(p->quota[t], 0U) << t;
      }
    }
    EXPECT_EQ(total, 1000U);
    EXPECT_LE(most - least, 1U);
    EXPECT_EQ(p->quota[p->targets[0]], most);  // the bound is derived from the first, busiest sender
  }
}

TEST(UdnStressPlan, UniformNeverPicksSelfOrALeftOutTileAndReachesEveryOther) {
  tools::StressOptions o;
  o.failed_tiles = {0U, 27U, 63U};
  const TrafficPlan plan = make_plan(o);
  bsp::Rng rng(1U, bsp::StreamId::kTraffic, 0U);
  for (const bsp::TileId self : {1U, 28U, 62U}) {
    std::array<std::uint32_t, bsp::kMaxTiles> hits{};
    for (int i = 0; i < 20000; ++i) {
      ++hits[pick_destination(plan, rng, self)];
    }
    for (bsp::TileId t = 0; t < 64U; ++t) {
      if (t == self || !plan.addressed[t]) {
        EXPECT_EQ(hits[t], 0U) << self << "->" << t;
      } else {
        // 20000 draws over 60 tiles: 333 expected each; 200 is more than 7 sigma below.
        EXPECT_GT(hits[t], 200U) << self << "->" << t;
      }
    }
  }
}

TEST(UdnStressPlan, TransposeMirrorsAndRedrawsWhenTheMirrorIsOut) {
  tools::StressOptions o;
  o.pattern = tools::TrafficPattern::kTranspose;
  o.failed_tiles = {26U};  // (2, 3): the mirror of (3, 2) = 19
  const TrafficPlan plan = make_plan(o);
  bsp::Rng rng(2U, bsp::StreamId::kTraffic, 0U);
  EXPECT_EQ(pick_destination(plan, rng, 10U), 17U);  // (2, 1) -> (1, 2)
  EXPECT_EQ(pick_destination(plan, rng, 9U), 9U);    // the diagonal sends to itself
  for (int i = 0; i < 200; ++i) {
    const bsp::TileId d = pick_destination(plan, rng, 19U);
    EXPECT_NE(d, 26U);
    EXPECT_NE(d, 19U);
  }
}

TEST(UdnStressPlan, HotspotSendsAQuarterToTheCentreUnlessItIsOut) {
  tools::StressOptions o;
  o.pattern = tools::TrafficPattern::kHotspot;
  TrafficPlan plan = make_plan(o);
  bsp::Rng rng(3U, bsp::StreamId::kTraffic, 0U);
  std::uint32_t hot = 0U;
  for (int i = 0; i < 8000; ++i) {
    hot += pick_destination(plan, rng, 0U) == 36U ? 1U : 0U;
  }
  // A quarter plus a uniform share of the rest: 2000 + 6000 / 63 = 2095 expected.
  EXPECT_GT(hot, 1900U);
  EXPECT_LT(hot, 2300U);
  o.failed_tiles = {36U};
  plan = make_plan(o);
  for (int i = 0; i < 2000; ++i) {
    EXPECT_NE(pick_destination(plan, rng, 0U), 36U);
  }
}

TEST(UdnStressPlan, ALoneTileSendsToItself) {
  tools::StressOptions o;
  o.profile = "maestro";
  for (bsp::TileId t = 1; t < 49U; ++t) {
    o.failed_tiles.push_back(t);
  }
  const TrafficPlan plan = make_plan(o);
  ASSERT_EQ(plan.sender_count, 1U);
  bsp::Rng rng(4U, bsp::StreamId::kTraffic, 0U);
  EXPECT_EQ(pick_destination(plan, rng, 0U), 0U);
}

}  // namespace
