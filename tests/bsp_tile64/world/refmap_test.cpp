/**
 * @file refmap_test.cpp
 * @brief The reference-map product: layout, footprint means, other sun, determinism, discovery in DDR.
 */
#include "bsp_tile64/world/refmap.hpp"

#include "bsp_tile64/api/memory.hpp"
#include "tests/support/heap_probe.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <vector>

namespace {

bsp::world::TerrainConfig small(std::uint64_t seed) {
  bsp::world::TerrainConfig c;
  c.seed = seed;
  c.size_px = 512;
  c.m_per_px = 8.0;
  return c;
}

class RefMap : public ::testing::Test {
 protected:
  void SetUp() override {
    ASSERT_EQ(bsp::world::terrain_build(small(3)), bsp::world::WorldError::kOk);
    ASSERT_EQ(bsp::region_reset(bsp::Region{bsp::Region::kDdr}), bsp::MemError::kOk);
  }
  void TearDown() override { EXPECT_EQ(bsp::region_reset(bsp::Region{bsp::Region::kDdr}), bsp::MemError::kOk); }

  static std::vector<std::uint8_t> bytes(const bsp::MapProductHeader* p) {
    const auto* b = reinterpret_cast<const std::uint8_t*>(p);  // NOLINT(cppcoreguidelines-pro-type-reinterpret-cast): product bytes
    return {b, b + p->total_bytes};
  }
};

TEST_F(RefMap, ProductIsLaidOutAsDocumentedAndFoundInDdr) {
  EXPECT_EQ(bsp::map_product_find(), nullptr);
  bsp::world::WorldError err = bsp::world::WorldError::kNotBuilt;
  const bsp::MapProductHeader* p = bsp::world::refmap_build(bsp::world::MapConfig{}, &err);
  ASSERT_EQ(err, bsp::world::WorldError::kOk);
  ASSERT_NE(p, nullptr);
  EXPECT_EQ(bsp::map_product_find(), p);
  EXPECT_EQ(p->magic, bsp::kMapProductMagic);
  EXPECT_EQ(p->layer_count, bsp::kMapLayers);
  const double side = 2.0 * bsp::world::terrain_half_extent_m();  // 4088 m
  const bsp::MapLayerHeader& fine = p->layers[bsp::kMapLayerFine];
  const bsp::MapLayerHeader& coarse = p->layers[bsp::kMapLayerCoarse];
  EXPECT_EQ(fine.width_px, static_cast<std::uint32_t>(side / 6.0));
  EXPECT_EQ(coarse.height_px, static_cast<std::uint32_t>(side / 12.0));
  EXPECT_DOUBLE_EQ(fine.m_per_px, 6.0);
  EXPECT_DOUBLE_EQ(coarse.m_per_px, 12.0);
  // Centred on the origin; rows run south.
  EXPECT_NEAR(fine.origin_x_m + 0.5 * (fine.width_px - 1) * 6.0, 0.0, 1e-9);
  EXPECT_NEAR(fine.origin_y_m - 0.5 * (fine.height_px - 1) * 6.0, 0.0, 1e-9);
  EXPECT_EQ(fine.image_offset % 64U, 0U);
  EXPECT_EQ(coarse.elevation_offset % 64U, 0U);
  EXPECT_GE(fine.image_offset, sizeof(bsp::MapProductHeader));
  EXPECT_LE(coarse.elevation_offset + 2ULL * coarse.width_px * coarse.height_px, p->total_bytes);
}

TEST_F(RefMap, PixelsAreFootprintMeansOfTheTerrainUnderTheMapSun) {
  const bsp::world::MapConfig cfg;
  const bsp::MapProductHeader* p = bsp::world::refmap_build(cfg, nullptr);
  ASSERT_NE(p, nullptr);
  double sun[3];
  bsp::world::sun_vector(cfg.sun, sun);
  for (std::uint32_t l = 0; l < bsp::kMapLayers; ++l) {
    const bsp::MapLayerHeader& h = p->layers[l];
    const std::uint32_t s = 2U;  // round(m/px / 8 m) clamped to 2..4: 2 for both layers here
    for (std::uint32_t k = 0; k < 40; ++k) {
      const std::uint32_t col = (k * 97U) % h.width_px;
      const std::uint32_t row = (k * 61U + 5U) % h.height_px;
      double xyz[3];
      bsp::map_pixel_position(p, l, col, row, xyz);
      double rad = 0.0;
      double z = 0.0;
      for (std::uint32_t j = 0; j < s; ++j) {
        for (std::uint32_t i = 0; i < s; ++i) {
          const double x = xyz[0] + (-0.5 + (i + 0.5) / s) * h.m_per_px;
          const double y = xyz[1] + (-0.5 + (j + 0.5) / s) * h.m_per_px;
          rad += bsp::world::terrain_radiance(x, y, sun);
          z += bsp::world::terrain_height_m(x, y);
        }
      }
      EXPECT_NEAR(xyz[2], z / (s * s), 0.051) << "layer " << l << " pixel " << col << "," << row;
      const double dn = bsp::map_image(p, l)[std::size_t{row} * h.width_px + col];
      EXPECT_NEAR(dn, rad / (s * s) * h.dn_per_radiance, 0.51) << "layer " << l << " pixel " << col << "," << row;
    }
  }
}

TEST_F(RefMap, SameSeedGivesTheSameProductAndAnotherSunOrSeedAnother) {
  const bsp::world::MapConfig cfg;
  const std::vector<std::uint8_t> a = bytes(bsp::world::refmap_build(cfg, nullptr));
  ASSERT_EQ(bsp::region_reset(bsp::Region{bsp::Region::kDdr}), bsp::MemError::kOk);
  const std::vector<std::uint8_t> b = bytes(bsp::world::refmap_build(cfg, nullptr));
  EXPECT_EQ(a, b);
  ASSERT_EQ(bsp::region_reset(bsp::Region{bsp::Region::kDdr}), bsp::MemError::kOk);
  bsp::world::MapConfig other_sun = cfg;
  other_sun.sun = bsp::world::SunAngle{135.0, 35.0};
  EXPECT_NE(a, bytes(bsp::world::refmap_build(other_sun, nullptr)));
  ASSERT_EQ(bsp::region_reset(bsp::Region{bsp::Region::kDdr}), bsp::MemError::kOk);
  ASSERT_EQ(bsp::world::terrain_build(small(4)), bsp::world::WorldError::kOk);
  EXPECT_NE(a, bytes(bsp::world::refmap_build(cfg, nullptr)));
}

TEST_F(RefMap, BuildingTheWorldAndItsMapNeverTouchesTheHeap) {
  bsp::world::WorldError terrain = bsp::world::WorldError::kNotBuilt;
  bsp::world::WorldError shade = bsp::world::WorldError::kNotBuilt;
  bsp::world::WorldError map = bsp::world::WorldError::kNotBuilt;
  const std::uint64_t allocs = test_support::count_allocs([&] {
    terrain = bsp::world::terrain_build(small(8));
    shade = bsp::world::terrain_shade(bsp::world::SunAngle{135.0, 35.0});
    (void)bsp::world::refmap_build(bsp::world::MapConfig{}, &map);
  });
  EXPECT_EQ(terrain, bsp::world::WorldError::kOk);
  EXPECT_EQ(shade, bsp::world::WorldError::kOk);
  EXPECT_EQ(map, bsp::world::WorldError::kOk);
  EXPECT_EQ(allocs, 0U);
}

TEST_F(RefMap, BadConfigurationsAreRejectedWithoutCarving) {
  bsp::world::WorldError err = bsp::world::WorldError::kOk;
  bsp::world::MapConfig cfg;
  cfg.extent_m = 1e5;  // larger than the terrain
  EXPECT_EQ(bsp::world::refmap_build(cfg, &err), nullptr);
  EXPECT_EQ(err, bsp::world::WorldError::kBadConfig);
  cfg = bsp::world::MapConfig{};
  cfg.coarse_m_per_px = 3.0;  // coarser than fine is required
  EXPECT_EQ(bsp::world::refmap_build(cfg, &err), nullptr);
  EXPECT_EQ(err, bsp::world::WorldError::kBadConfig);
  EXPECT_EQ(bsp::region_used(bsp::Region{bsp::Region::kDdr}), 0U);
}

}  // namespace
