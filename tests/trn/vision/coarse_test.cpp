/**
 * @file coarse_test.cpp
 * @brief Coarse stage: box decimation is exact, and a kilometre-level position error
 *        (>= 3 km at 12 m/px) is recovered on a synthetic textured scene.
 */
#include "trn/vision/coarse.hpp"

#include "tests/trn/vision/synth.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstdio>

namespace {

namespace tv = trn::vision;
using vision_test::Image;

constexpr double kMetresPerPx = 12.0;  // LVS coarse map resolution

TEST(Coarse, BoxDecimationEqualsTheRoundedBlockMean) {
  const Image in = vision_test::random_image(37, 29, 71);
  for (std::int32_t f = 1; f <= 5; ++f) {
    Image out(37 / f, 29 / f);
    bsp::Work work;
    ASSERT_EQ(tv::downsample_box(in.view(), f, out.mview(), work), tv::Status::kOk);
    for (std::int32_t y = 0; y < out.h; ++y)
      for (std::int32_t x = 0; x < out.w; ++x) {
        int s = 0;
        for (std::int32_t j = 0; j < f; ++j)
          for (std::int32_t i = 0; i < f; ++i) s += in.at(x * f + i, y * f + j);
        EXPECT_EQ(out.at(x, y), static_cast<int>(std::lround(static_cast<double>(s) / (f * f)))) << f;
      }
    EXPECT_GT(work.int_ops, 0U);
  }
}

TEST(Coarse, DecimationRejectsMismatchedSizesAndFactors) {
  const Image in = vision_test::random_image(32, 32, 72);
  Image out(8, 8);
  bsp::Work work;
  EXPECT_EQ(tv::downsample_box(in.view(), 3, out.mview(), work), tv::Status::kBadInput);
  EXPECT_EQ(tv::downsample_box(in.view(), 0, out.mview(), work), tv::Status::kBadInput);
  EXPECT_EQ(tv::downsample_box(in.view(), tv::kCoarseMaxFactor + 1, out.mview(), work), tv::Status::kBadInput);
}

/** A terrain-like texture: fine grain plus broad shading, 1024 x 1024 at 12 m/px. */
Image make_scene(std::uint64_t seed) {
  const Image fine = vision_test::smooth_texture(1024, 1024, 2, seed);
  const Image broad = vision_test::smooth_texture(1024, 1024, 12, seed + 1);
  Image m(1024, 1024);
  for (std::size_t i = 0; i < m.px.size(); ++i) {
    m.px[i] = static_cast<std::uint8_t>((fine.px[i] + 2 * broad.px[i]) / 3);
  }
  return m;
}

/** Camera patch (already in map geometry) at map pixel (x0, y0), with gain, bias and noise. */
Image camera_patch(const Image& map, std::int32_t x0, std::int32_t y0, std::int32_t side, bsp::Rng& rng) {
  Image im(side, side);
  for (std::int32_t y = 0; y < side; ++y)
    for (std::int32_t x = 0; x < side; ++x)
      im.at(x, y) = vision_test::clamp_u8(20.0 + 0.8 * map.at(x0 + x, y0 + y) + rng.normal(0.0, 3.0));
  return im;
}

TEST(Coarse, RecoversPositionErrorsOfThreeKilometresAndMore) {
  const std::uint64_t seed = 73;
  const Image map = make_scene(seed);
  constexpr std::int32_t kSide = 384;        // camera patch, map px (4.6 km)
  constexpr std::int32_t kPredicted = 320;   // predicted top-left: the map centre
  static tv::CoarseWorkspace ws;
  bsp::Rng rng(seed, bsp::StreamId::kTest, 4);
  for (int trial = 0; trial < 6; ++trial) {
    const double radius_m = rng.uniform(3000.0, 3500.0);
    const double angle = rng.uniform(0.0, 6.283185307179586);
    const auto ex = static_cast<std::int32_t>(std::lround(radius_m * std::cos(angle) / kMetresPerPx));
    const auto ey = static_cast<std::int32_t>(std::lround(radius_m * std::sin(angle) / kMetresPerPx));
    const Image img = camera_patch(map, kPredicted + ex, kPredicted + ey, kSide, rng);
    tv::CoarseResult r;
    bsp::Work work;
    ASSERT_EQ(tv::coarse_match(map.view(), img.view(), tv::CoarseParams{}, ws, r, work), tv::Status::kOk);
    ASSERT_TRUE(r.accepted()) << "seed " << seed << " trial " << trial << " reason "
                              << static_cast<int>(r.match.reason());
    const double err_x = r.x_px - (kPredicted + ex);
    const double err_y = r.y_px - (kPredicted + ey);
    std::printf("coarse: initial error %.0f m, residual %.1f m (%.2f, %.2f px), peak %.3f, second %.3f, %.0f M MACs\n",
                std::hypot(ex, ey) * kMetresPerPx, std::hypot(err_x, err_y) * kMetresPerPx, err_x, err_y,
                static_cast<double>(r.match.peak.score), static_cast<double>(r.match.peak.second),
                static_cast<double>(work.int_macs) / 1e6);
    EXPECT_GE(std::hypot(ex, ey) * kMetresPerPx, 2990.0);
    // One coarse pixel (4 map px, 48 m) or better; LVS hands ~200 m to the fine stage.
    EXPECT_LE(std::fabs(err_x), 4.0) << "seed " << seed << " trial " << trial;
    EXPECT_LE(std::fabs(err_y), 4.0) << "seed " << seed << " trial " << trial;
  }
}

TEST(Coarse, FlatCameraImageIsRejected) {
  const Image map = vision_test::smooth_texture(512, 512, 2, 74);
  const Image img(256, 256, 100);
  static tv::CoarseWorkspace ws;
  tv::CoarseResult r;
  bsp::Work work;
  ASSERT_EQ(tv::coarse_match(map.view(), img.view(), tv::CoarseParams{}, ws, r, work), tv::Status::kOk);
  EXPECT_EQ(r.match.reason(), tv::Reject::kFlatTemplate);
}

TEST(Coarse, MapRegionAboveCapacityIsRefused) {
  const Image map(1100, 1100, 1);
  const Image img(256, 256, 100);
  static tv::CoarseWorkspace ws;
  tv::CoarseResult r;
  bsp::Work work;
  EXPECT_EQ(tv::coarse_match(map.view(), img.view(), tv::CoarseParams{}, ws, r, work), tv::Status::kTooLarge);
}

}  // namespace
