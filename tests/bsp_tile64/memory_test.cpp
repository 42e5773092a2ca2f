/**
 * @file memory_test.cpp
 * @brief Carving of the tile RAM and DDR regions: alignment, exhaustion, reset, records.
 */
#include "bsp_tile64/api/memory.hpp"

#include <gtest/gtest.h>

#include <cstdint>

namespace {

constexpr bsp::Region kTile{5};

class Carving : public ::testing::Test {
 protected:
  void SetUp() override { ASSERT_EQ(bsp::region_reset(kTile), bsp::MemError::kOk); }
  void TearDown() override { EXPECT_EQ(bsp::region_reset(kTile), bsp::MemError::kOk); }
};

TEST_F(Carving, CarvesAreAlignedZeroedAndRecorded) {
  const bsp::Carve a = bsp::carve(kTile, 3, 1, "a");
  const bsp::Carve b = bsp::carve(kTile, 16, 64, "b");
  ASSERT_EQ(a.error, bsp::MemError::kOk);
  ASSERT_EQ(b.error, bsp::MemError::kOk);
  EXPECT_EQ(reinterpret_cast<std::uintptr_t>(b.ptr) % 64U, 0U);
  EXPECT_EQ(b.ptr - a.ptr, 64);
  EXPECT_EQ(bsp::region_used(kTile), 80U);
  EXPECT_EQ(b.ptr[15], std::byte{0});
  ASSERT_EQ(bsp::region_carves(kTile).size(), 2U);
  EXPECT_STREQ(bsp::region_carves(kTile)[1].what, "b");
}

TEST_F(Carving, ExhaustionIsAnErrorAndLeavesTheRegionUnchanged) {
  ASSERT_EQ(bsp::carve(kTile, bsp::kTileRamBytes - 8, 8, "big").error, bsp::MemError::kOk);
  const bsp::Carve c = bsp::carve(kTile, 16, 8, "too much");
  EXPECT_EQ(c.error, bsp::MemError::kExhausted);
  EXPECT_EQ(c.ptr, nullptr);
  EXPECT_EQ(bsp::region_used(kTile), bsp::kTileRamBytes - 8);
  EXPECT_EQ(bsp::carve(kTile, 8, 8, "fits exactly").error, bsp::MemError::kOk);
}

TEST_F(Carving, BadArgumentsAreRejected) {
  EXPECT_EQ(bsp::carve(bsp::Region{bsp::kMaxTiles}, 8, 8, "x").error, bsp::MemError::kBadRegion);
  EXPECT_EQ(bsp::carve(kTile, 8, 3, "x").error, bsp::MemError::kBadAlign);
  EXPECT_EQ(bsp::carve(kTile, 8, 0, "x").error, bsp::MemError::kBadAlign);
  EXPECT_EQ(bsp::carve(kTile, 8, bsp::kRegionAlign * 2, "x").error, bsp::MemError::kBadAlign);
  EXPECT_EQ(bsp::region_reset(bsp::Region{bsp::kMaxTiles + 3}), bsp::MemError::kBadRegion);
}

TEST_F(Carving, RecordTableIsBounded) {
  for (std::size_t i = 0; i < bsp::kMaxCarvesPerRegion; ++i) {
    ASSERT_EQ(bsp::carve(kTile, 4, 4, "n").error, bsp::MemError::kOk);
  }
  EXPECT_EQ(bsp::carve(kTile, 4, 4, "n").error, bsp::MemError::kTooMany);
}

TEST_F(Carving, ResetZeroesAndRestartsFromTheRegionStart) {
  bsp::Carve a = bsp::carve(kTile, 32, 8, "a");
  ASSERT_EQ(a.error, bsp::MemError::kOk);
  a.ptr[7] = std::byte{0x5A};
  ASSERT_EQ(bsp::region_reset(kTile), bsp::MemError::kOk);
  EXPECT_EQ(bsp::region_used(kTile), 0U);
  const bsp::Carve b = bsp::carve(kTile, 32, 8, "b");
  EXPECT_EQ(b.ptr, a.ptr);
  EXPECT_EQ(b.ptr[7], std::byte{0});
}

}  // namespace
