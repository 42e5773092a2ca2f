/**
 * @file vision_tiles_test.cpp
 * @brief The vision tiles a mission gives its coordinator (--vision-tiles N): N of the map's 40,
 *        spread over the map, the rest left out of the coordinator's list.
 */
#include "tools/common/mission/mission.hpp"
#include "trn/tasks/tile_map.hpp"

#include <gtest/gtest.h>

#include <bit>

namespace {

std::uint64_t vision_mask() {
  std::uint64_t m = 0;
  for (std::uint32_t t = 0; t < trn::tasks::kMapTiles; ++t) {
    m |= trn::tasks::kTileRoles[t] == trn::tasks::Role::kVision ? (1ULL << t) : 0ULL;
  }
  return m;
}

TEST(VisionTiles, AllFortyByDefaultAndAtForty) {
  EXPECT_EQ(tools::vision_exclude_mask(trn::tasks::kTile64Deployment, 0U), 0U);
  EXPECT_EQ(tools::vision_exclude_mask(trn::tasks::kTile64Deployment, 40U), 0U);
}

TEST(VisionTiles, NTilesAreKeptSpreadOverTheMap) {
  const std::uint64_t all = vision_mask();
  ASSERT_EQ(std::popcount(all), 40);
  for (const std::uint32_t n : {1U, 5U, 10U, 20U, 30U, 39U}) {
    const std::uint64_t out = tools::vision_exclude_mask(trn::tasks::kTile64Deployment, n);
    EXPECT_EQ(out & ~all, 0U) << "only vision tiles are left out";
    EXPECT_EQ(std::popcount(all & ~out), static_cast<int>(n));
  }
  // Five tiles come from across the map, not from one corner: every fifth row band has one.
  const std::uint64_t kept = all & ~tools::vision_exclude_mask(trn::tasks::kTile64Deployment, 5U);
  std::uint32_t lowest = 64U;
  std::uint32_t highest = 0U;
  for (std::uint32_t t = 0; t < 64U; ++t) {
    if (((kept >> t) & 1ULL) != 0ULL) {
      lowest = std::min(lowest, t);
      highest = std::max(highest, t);
    }
  }
  EXPECT_GE(highest - lowest, 32U) << "spread over at least half the chip";
}

}  // namespace
