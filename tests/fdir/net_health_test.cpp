/**
 * @file net_health_test.cpp
 * @brief Network health votes (FDIR-NH-xx): one vote is never enough, a reporter counts once,
 *        spares and failed switches are ignored, a link reported by both its ends only enters
 *        the map as a link, and a switch reported by two neighbours enters it as a switch.
 */
#include "fdir/net_health.hpp"

#include <gtest/gtest.h>

namespace {

using fdir::detail::Verdict;

class NetHealthVotes : public ::testing::Test {
 protected:
  void SetUp() override { ASSERT_EQ(udn::fault_map_init(map_, 8U, 8U), udn::RouteError::kOk); }
  Verdict take(bsp::TileId reporter, bsp::TileId suspect) {
    return fdir::detail::take_report(votes_, map_, reporter, suspect, count_);
  }
  fdir::detail::Votes votes_{};
  udn::FaultMap map_{};
  std::uint32_t count_ = 0;
};

// FDIR-NH-01
TEST_F(NetHealthVotes, OneVoteIsNeverEnough) {
  EXPECT_EQ(take(36U, 44U), Verdict::kCounted);
  EXPECT_EQ(count_, 1U);
  EXPECT_EQ(map_.failed_tiles, 0U);
  EXPECT_EQ(map_.version, 0U);
}

// FDIR-NH-02
TEST_F(NetHealthVotes, AReporterIsCountedOnce) {
  EXPECT_EQ(take(36U, 44U), Verdict::kCounted);
  EXPECT_EQ(take(36U, 44U), Verdict::kIgnored) << "a report sent again (it still holds) is nothing new";
  EXPECT_EQ(count_, 1U);
  EXPECT_EQ(map_.failed_tiles, 0U);
}

// FDIR-NH-03
TEST_F(NetHealthVotes, TwoNeighboursFailTheSwitchAndMoveTheVersion) {
  EXPECT_EQ(take(36U, 44U), Verdict::kCounted);
  EXPECT_EQ(take(43U, 44U), Verdict::kSwitchFailed);
  EXPECT_EQ(count_, 2U);
  EXPECT_EQ(map_.failed_tiles, 1ULL << 44U);
  EXPECT_EQ(map_.version, 1U);
  EXPECT_EQ(take(52U, 44U), Verdict::kIgnored) << "already failed";
  EXPECT_EQ(take(44U, 45U), Verdict::kIgnored) << "a failed switch's reports do not count";
  EXPECT_EQ(map_.version, 1U);
}

// FDIR-NH-04
TEST_F(NetHealthVotes, SparesAndNonsenseAreIgnored) {
  votes_.not_voted = 1ULL << 10U;
  EXPECT_EQ(take(9U, 10U), Verdict::kIgnored);
  EXPECT_EQ(take(18U, 10U), Verdict::kIgnored);
  EXPECT_EQ(take(12U, 12U), Verdict::kIgnored) << "a tile about itself";
  EXPECT_EQ(take(70U, 12U), Verdict::kIgnored) << "off the grid";
  EXPECT_EQ(map_.failed_tiles, 0U);
}

// FDIR-NH-05: a failed link enters the map, both ways, and neither switch is blamed.
TEST_F(NetHealthVotes, ALinkReportedByBothEndsOnlyEntersTheMapAsALink) {
  EXPECT_EQ(take(27U, 28U), Verdict::kCounted);
  EXPECT_EQ(take(28U, 27U), Verdict::kLinkFailed);
  EXPECT_EQ(map_.failed_tiles, 0U);
  EXPECT_NE(map_.failed_links[27] & (1U << static_cast<unsigned>(bsp::UdnDir::kEast)), 0U);
  EXPECT_NE(map_.failed_links[28] & (1U << static_cast<unsigned>(bsp::UdnDir::kWest)), 0U);
  EXPECT_EQ(map_.version, 1U);
  EXPECT_FALSE(udn::path_clear(map_, 27U, 28U));
  // The link's reports were no votes: two other neighbours are needed to fail switch 28.
  EXPECT_EQ(take(36U, 28U), Verdict::kCounted);
  EXPECT_EQ(count_, 1U);
  EXPECT_EQ(take(29U, 28U), Verdict::kSwitchFailed);
}

TEST_F(NetHealthVotes, MutualReportsOfTilesThatAreNotNeighboursAreNoLink) {
  EXPECT_EQ(take(27U, 45U), Verdict::kCounted);
  EXPECT_EQ(take(45U, 27U), Verdict::kCounted);
  EXPECT_EQ(map_.version, 0U);
}

}  // namespace
