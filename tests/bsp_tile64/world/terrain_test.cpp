/**
 * @file terrain_test.cpp
 * @brief The terrain: determinism per seed, bilinear queries, crater size-frequency law, shading.
 */
#include "bsp_tile64/emu/rng.hpp"
#include "bsp_tile64/world/terrain.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>

namespace {

constexpr double kPi = 3.14159265358979323846;

bsp::world::TerrainConfig small(std::uint64_t seed) {
  bsp::world::TerrainConfig c;
  c.seed = seed;
  c.size_px = 512;
  c.m_per_px = 8.0;
  return c;
}

/** FNV-1a over the height and albedo queries at every grid node. */
std::uint64_t terrain_hash() {
  std::uint64_t h = 1469598103934665603ULL;
  const double half = bsp::world::terrain_half_extent_m();
  const double step = bsp::world::terrain_config().m_per_px;
  for (double y = -half; y <= half + 1e-9; y += step) {
    for (double x = -half; x <= half + 1e-9; x += step) {
      const auto hh = static_cast<std::int64_t>(std::llround(bsp::world::terrain_height_m(x, y) * 1000.0));
      const auto aa = static_cast<std::int64_t>(std::llround(bsp::world::terrain_albedo(x, y) * 255.0));
      h = (h ^ static_cast<std::uint64_t>(hh)) * 1099511628211ULL;
      h = (h ^ static_cast<std::uint64_t>(aa)) * 1099511628211ULL;
    }
  }
  return h;
}

TEST(Terrain, SameSeedGivesTheSameTerrainAndAnotherSeedAnother) {
  ASSERT_EQ(bsp::world::terrain_build(small(5)), bsp::world::WorldError::kOk);
  const std::uint64_t a = terrain_hash();
  ASSERT_EQ(bsp::world::terrain_build(small(6)), bsp::world::WorldError::kOk);
  const std::uint64_t b = terrain_hash();
  ASSERT_EQ(bsp::world::terrain_build(small(5)), bsp::world::WorldError::kOk);
  EXPECT_EQ(terrain_hash(), a);
  EXPECT_NE(a, b);
}

TEST(Terrain, OutOfRangeConfigurationsAreRejectedAndLeaveTheTerrain) {
  ASSERT_EQ(bsp::world::terrain_build(small(5)), bsp::world::WorldError::kOk);
  const std::uint64_t before = terrain_hash();
  bsp::world::TerrainConfig c = small(9);
  c.size_px = bsp::world::kMaxTerrainPx + 1U;
  EXPECT_EQ(bsp::world::terrain_build(c), bsp::world::WorldError::kBadConfig);
  c = small(9);
  c.crater_sfd_exponent = 0.5;
  EXPECT_EQ(bsp::world::terrain_build(c), bsp::world::WorldError::kBadConfig);
  c = small(9);
  c.crater_max_d_m = 1.0;
  EXPECT_EQ(bsp::world::terrain_build(c), bsp::world::WorldError::kBadConfig);
  EXPECT_EQ(terrain_hash(), before);
}

TEST(Terrain, QueriesAreBilinearBetweenNodesAndClampedOutside) {
  ASSERT_EQ(bsp::world::terrain_build(small(5)), bsp::world::WorldError::kOk);
  const double s = 8.0;
  const double x0 = (300 - 255.5) * s;  // node (300, 200)
  const double y0 = (200 - 255.5) * s;
  const double h00 = bsp::world::terrain_height_m(x0, y0);
  const double h10 = bsp::world::terrain_height_m(x0 + s, y0);
  const double h01 = bsp::world::terrain_height_m(x0, y0 + s);
  const double h11 = bsp::world::terrain_height_m(x0 + s, y0 + s);
  for (const double fx : {0.0, 0.25, 0.5, 0.9}) {
    for (const double fy : {0.0, 0.3, 0.75}) {
      const double ref = h00 * (1 - fx) * (1 - fy) + h10 * fx * (1 - fy) + h01 * (1 - fx) * fy + h11 * fx * fy;
      EXPECT_NEAR(bsp::world::terrain_height_m(x0 + fx * s, y0 + fy * s), ref, 1e-9);
    }
  }
  const double half = bsp::world::terrain_half_extent_m();
  EXPECT_DOUBLE_EQ(bsp::world::terrain_height_m(half + 500.0, 0.0), bsp::world::terrain_height_m(half, 0.0));
}

TEST(Terrain, ReliefIsPlausibleForAMartianPlain) {
  ASSERT_EQ(bsp::world::terrain_build(small(5)), bsp::world::WorldError::kOk);
  double lo = 1e9;
  double hi = -1e9;
  const double half = bsp::world::terrain_half_extent_m();
  for (double y = -half; y <= half; y += 16.0) {
    for (double x = -half; x <= half; x += 16.0) {
      const double h = bsp::world::terrain_height_m(x, y);
      lo = std::min(lo, h);
      hi = std::max(hi, h);
      ASSERT_TRUE(std::isfinite(h));
    }
  }
  std::printf("relief over 4 km: %.1f .. %.1f m\n", lo, hi);
  EXPECT_GT(hi - lo, 20.0);
  EXPECT_LT(hi - lo, 1000.0);
}

TEST(Terrain, CraterDiametersFollowTheCumulativePowerLaw) {
  // N(>D) ~ D^-b: the fraction above 2 Dmin is 2^-b (truncation at Dmax is negligible here).
  bsp::world::TerrainConfig c = small(1);
  c.crater_min_d_m = 10.0;
  c.crater_max_d_m = 1e5;
  bsp::Rng rng(77, bsp::StreamId::kTest);
  for (const double b : {1.5, 2.0, 3.0}) {
    c.crater_sfd_exponent = b;
    int above2 = 0;
    int above4 = 0;
    constexpr int kN = 100000;
    for (int i = 0; i < kN; ++i) {
      const double d = bsp::world::detail::crater_diameter_m(rng.uniform(), c);
      ASSERT_GE(d, c.crater_min_d_m);
      ASSERT_LE(d, c.crater_max_d_m);
      above2 += d > 20.0 ? 1 : 0;
      above4 += d > 40.0 ? 1 : 0;
    }
    EXPECT_NEAR(above2 / static_cast<double>(kN), std::pow(2.0, -b), 0.01) << "b " << b << " seed 77";
    EXPECT_NEAR(above4 / static_cast<double>(kN), std::pow(4.0, -b), 0.01) << "b " << b << " seed 77";
  }
}

TEST(Terrain, ShadedImageIsLambertUnderTheGivenSun) {
  ASSERT_EQ(bsp::world::terrain_build(small(5)), bsp::world::WorldError::kOk);
  EXPECT_FALSE(bsp::world::terrain_shaded());
  const bsp::world::SunAngle sun{120.0, 30.0};
  ASSERT_EQ(bsp::world::terrain_shade(sun), bsp::world::WorldError::kOk);
  double s[3];
  bsp::world::sun_vector(sun, s);
  EXPECT_NEAR(s[0] * s[0] + s[1] * s[1] + s[2] * s[2], 1.0, 1e-12);
  EXPECT_NEAR(std::asin(s[2]), 30.0 * kPi / 180.0, 1e-12);
  EXPECT_GT(s[0], 0.0);  // azimuth 120: east of south-east
  EXPECT_LT(s[1], 0.0);
  for (int i = 10; i < 500; i += 37) {
    const double x = (i - 255.5) * 8.0;
    const double y = (500 - i - 255.5) * 8.0;
    EXPECT_NEAR(bsp::world::terrain_shaded_radiance(x, y), bsp::world::terrain_radiance(x, y, s), 2e-3) << i;
  }
  EXPECT_EQ(bsp::world::terrain_shaded_radiance(1e6, 0.0), 0.0);
}

}  // namespace
