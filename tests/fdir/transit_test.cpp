/**
 * @file transit_test.cpp
 * @brief Transit plans on the mission's tile map and the verdict on lost transits.
 */
#include "fdir/transit.hpp"

#include <gtest/gtest.h>

#include <bit>
#include <cstdio>

namespace {

constexpr std::uint64_t bit(std::uint32_t t) { return std::uint64_t{1} << t; }

/** The mission's live tiles: supervisor 0, coordinator 1, I/O 9, filter 18, vision 24..63. */
constexpr std::uint64_t kLive = bit(0) | bit(1) | bit(9) | bit(18) | (~std::uint64_t{0} << 24U);
constexpr std::uint64_t kSpares = ~kLive;

udn::FaultMap grid() {
  udn::FaultMap m{};
  EXPECT_EQ(udn::fault_map_init(m, 8, 8), udn::RouteError::kOk);
  return m;
}

TEST(Transit, UnderObservedTilesAreThoseWithOneLiveNeighbour) {
  const udn::FaultMap m = grid();
  // 9 has only 1 (8, 10, 17 are spares); 18 has only 26; 0 has only 1; 1 has 0 and 9.
  EXPECT_EQ(fdir::under_observed(m, kLive, 2), bit(0) | bit(9) | bit(18));
}

TEST(Transit, MissionPlanTestsEverySpareThatCarriesTrafficAndTellsThemApart) {
  const udn::FaultMap m = grid();
  const std::uint64_t subjects = kSpares | fdir::under_observed(m, kLive, 2);
  fdir::TransitPlan p{};
  ASSERT_EQ(fdir::plan_transits(m, kLive, subjects, p), fdir::TransitError::kOk);
  for (std::uint32_t i = 0; i < p.count; ++i) {
    std::printf("transit %2u: %2u -> %2u  spares on the way %d\n", i, p.t[i].prober, p.t[i].target,
                std::popcount(p.t[i].path & kSpares & ~bit(p.t[i].prober) & ~bit(p.t[i].target)));
  }
  std::printf("transits %u, tested %d, untested %d\n", p.count, std::popcount(p.tested), std::popcount(p.untested));
  EXPECT_EQ(p.untested, 0U) << "every subject on a leg between live tiles is tested";
  EXPECT_NE(p.tested & bit(11), 0U);
  EXPECT_NE(p.tested & bit(19), 0U);
  EXPECT_NE(p.tested & bit(18), 0U);
  // No prober pings more than its share; no transit pairs mesh neighbours.
  for (bsp::TileId t = 0; t < 64; ++t) {
    EXPECT_LE(std::popcount(fdir::transit_targets(p, t)), static_cast<int>(fdir::kTransitsPerProber));
  }
}

/** The transits a failed switch @p x kills: every one whose round trip crosses it. */
std::uint64_t killed_by(const fdir::TransitPlan& p, bsp::TileId x) {
  std::uint64_t lost = 0;
  for (std::uint32_t i = 0; i < p.count; ++i) {
    lost |= (p.t[i].path & bit(x)) != 0U ? bit(i) : 0U;
  }
  return lost;
}

TEST(Transit, EverySingleFailedSwitchIsNamedAndNoOtherIsBlamed) {
  const udn::FaultMap m = grid();
  const std::uint64_t subjects = kSpares | fdir::under_observed(m, kLive, 2);
  fdir::TransitPlan p{};
  ASSERT_EQ(fdir::plan_transits(m, kLive, subjects, p), fdir::TransitError::kOk);
  for (bsp::TileId x = 0; x < 64; ++x) {
    const std::uint64_t lost = killed_by(p, x);
    const bsp::TileId v = fdir::transit_verdict(p, lost, subjects, 0U);
    if ((p.tested & bit(x)) != 0U) {
      EXPECT_EQ(v, x) << "a tested switch that fails is named";
    } else if ((subjects & bit(x)) == 0U) {
      // A live switch the neighbours vote on: once voted (known failed), its transits tell nothing.
      EXPECT_EQ(fdir::transit_verdict(p, lost, subjects, bit(x)), bsp::kNoTile) << "tile " << x;
    }
  }
}

TEST(Transit, AHungCoreIsNoFailedSwitch) {
  // A hung core answers no ping, so the transits it is an end of are lost,
  // but its switch still carries the transits through it: no switch is named.
  const udn::FaultMap m = grid();
  const std::uint64_t subjects = kSpares | fdir::under_observed(m, kLive, 2);
  fdir::TransitPlan p{};
  ASSERT_EQ(fdir::plan_transits(m, kLive, subjects, p), fdir::TransitError::kOk);
  for (const bsp::TileId x : {bsp::TileId{9}, bsp::TileId{18}}) {
    const std::uint64_t ends = killed_by(p, x) & ~fdir::transits_through(p, x);
    ASSERT_NE(fdir::transits_through(p, x), 0U) << "transits cross tile " << x;
    EXPECT_EQ(fdir::transit_verdict(p, ends, subjects, 0U), bsp::kNoTile) << "tile " << x;
    EXPECT_EQ(fdir::transit_verdict(p, killed_by(p, x), subjects, 0U), x) << "its switch failing is named";
  }
}

TEST(Transit, OneLostTransitIsNeverEnough) {
  const udn::FaultMap m = grid();
  fdir::TransitPlan p{};
  ASSERT_EQ(fdir::plan_transits(m, kLive, kSpares, p), fdir::TransitError::kOk);
  for (std::uint32_t i = 0; i < p.count; ++i) {
    EXPECT_EQ(fdir::transit_verdict(p, bit(i), kSpares, 0U), bsp::kNoTile);
  }
  EXPECT_EQ(fdir::transit_verdict(p, 0U, kSpares, 0U), bsp::kNoTile);
}

TEST(Transit, BadGridIsRefused) {
  udn::FaultMap m{};
  fdir::TransitPlan p{};
  EXPECT_EQ(fdir::plan_transits(m, kLive, kSpares, p), fdir::TransitError::kBadArgs);
}

}  // namespace
