/**
 * @file memory_map_test.cpp
 * @brief The linker fragment places the tile RAM and DDR regions with their configured sizes,
 *        and a region over its budget fails the link.
 */
#include "bsp_tile64/api/memory.hpp"
#include "build_info.hpp"

#include <gtest/gtest.h>

#include <cstdint>
#include <cstdlib>
#include <string>

namespace {

std::uintptr_t addr_of(const void* p) { return reinterpret_cast<std::uintptr_t>(p); }

TEST(MemoryMap, TileRamSectionHasConfiguredSizeAndHoldsEveryTileRegion) {
  const bsp::SectionBounds s = bsp::tile_ram_section();
  EXPECT_EQ(s.end - s.start, bsp::kMaxTiles * bsp::kTileRamBytes);
  EXPECT_EQ(s.budget, bsp::kMaxTiles * bsp::kTileRamBytes);
  EXPECT_EQ(s.start % bsp::kRegionAlign, 0U);
  for (std::uint32_t t = 0; t < bsp::kMaxTiles; ++t) {
    const auto r = bsp::region_span(bsp::Region{t});
    ASSERT_EQ(r.size(), bsp::kTileRamBytes) << "tile " << t;
    EXPECT_EQ(addr_of(r.data()), s.start + t * bsp::kTileRamBytes) << "tile " << t;
  }
}

TEST(MemoryMap, DdrSectionHasConfiguredSize) {
  const bsp::SectionBounds s = bsp::ddr_section();
  EXPECT_EQ(s.end - s.start, bsp::kDdrBytes);
  EXPECT_EQ(s.budget, bsp::kDdrBytes);
  const auto r = bsp::region_span(bsp::Region{bsp::Region::kDdr});
  EXPECT_EQ(addr_of(r.data()), s.start);
  EXPECT_EQ(r.size(), bsp::kDdrBytes);
}

int link_fixture(std::size_t bytes) {
  const std::string out = std::string(::testing::TempDir()) + "region_user";
  const std::string cmd = std::string(build_info::kHostCxx) + " -std=c++20 -O0 -DFIXTURE_BYTES=" +
                          std::to_string(bytes) + " " + build_info::kRepoRoot +
                          "/tests/fixtures/linker/region_user.cpp -Wl,-T," + build_info::kLinkerScript + " -o " +
                          out + " 2>" + out + ".log";
  return std::system(cmd.c_str());
}

TEST(MemoryMap, RegionWithinBudgetLinks) {
  EXPECT_EQ(link_fixture(bsp::kMaxTiles * bsp::kTileRamBytes), 0) << "the control link must succeed";
}

TEST(MemoryMap, RegionOverBudgetFailsTheLink) {
  EXPECT_NE(link_fixture(bsp::kMaxTiles * bsp::kTileRamBytes + 1U), 0);
  // Make sure it failed for the budget, not for an unrelated reason.
  const std::string log = std::string(::testing::TempDir()) + "region_user.log";
  const std::string grep = "grep -q 'tile_ram is over budget' " + log;
  EXPECT_EQ(std::system(grep.c_str()), 0) << "the link failed, but not on the budget assertion";
}

}  // namespace
