/**
 * @file warp_grid_test.cpp
 * @brief Grid homography warp: exact where the exact warp is exact, source coordinates within a
 *        measured bound of the homography per grid spacing, pixels within 1 DN of warp_homography(),
 *        the same fill rule, and a small fraction of its TILE64 cycles.
 */
#include "trn/vision/warp_grid.hpp"

#include "bsp_tile64/emu/cost_model.hpp"
#include "tests/trn/vision/synth.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>

namespace {

namespace tv = trn::vision;
using vision_test::Image;

constexpr double kQ16 = 65536.0;

/** Largest distance between the grid's source coordinates and the exact homography over a w x h destination. */
double max_coordinate_error_px(const tv::Homography& h, std::int32_t grid_px, std::int32_t w, std::int32_t hgt,
                               std::int32_t& unusable) {
  const tv::detail::GridShape shape = tv::detail::grid_shape(grid_px, w, hgt);
  EXPECT_EQ(shape.status, tv::Status::kOk);
  double worst = 0.0;
  unusable = 0;
  std::int64_t visited = 0;
  auto visit = [&](std::int32_t x, std::int32_t y, std::int32_t xq, std::int32_t yq, bool usable) {
    ++visited;
    if (!usable) {
      ++unusable;
      return;
    }
    const double* m = h.h;
    const double ww = m[6] * x + m[7] * y + m[8];
    const double xs = (m[0] * x + m[1] * y + m[2]) / ww;
    const double ys = (m[3] * x + m[4] * y + m[5]) / ww;
    worst = std::fmax(worst, std::fmax(std::fabs(xq / kQ16 - xs), std::fabs(yq / kQ16 - ys)));
  };
  bsp::Work work;
  tv::detail::walk_grid(h, shape, w, hgt, visit, work);
  EXPECT_EQ(visited, static_cast<std::int64_t>(w) * hgt);  // every pixel once
  return worst;
}

/** Largest |grid - exact| pixel difference; also checks that both agree on which pixels are outside. */
int max_pixel_difference(const Image& src, const tv::Homography& h, std::int32_t grid_px, std::int32_t w,
                         std::int32_t hgt, std::int32_t& outside) {
  Image exact(w, hgt);
  Image grid(w, hgt);
  std::int32_t outside_exact = -1;
  bsp::Work work;
  EXPECT_EQ(tv::warp_homography(src.view(), h, exact.mview(), 0, outside_exact, work), tv::Status::kOk);
  EXPECT_EQ(tv::warp_homography_grid(src.view(), h, grid_px, grid.mview(), 0, outside, work), tv::Status::kOk);
  EXPECT_EQ(outside, outside_exact);
  int worst = 0;
  for (std::size_t i = 0; i < exact.px.size(); ++i) worst = std::max(worst, std::abs(exact.px[i] - grid.px[i]));
  return worst;
}

TEST(WarpGrid, IdentityAndIntegerTranslationsReproduceTheInputExactly) {
  const Image src = vision_test::random_image(80, 60, 101);
  for (std::int32_t g = tv::kGridWarpMinPx; g <= tv::kGridWarpMaxPx; g *= 2)
    for (std::int32_t t = -3; t <= 3; t += 3) {
      Image dst(40, 30);
      const tv::Homography shift{{1, 0, 20.0 + t, 0, 1, 15.0 - t, 0, 0, 1}};
      std::int32_t outside = -1;
      bsp::Work work;
      ASSERT_EQ(tv::warp_homography_grid(src.view(), shift, g, dst.mview(), 0, outside, work), tv::Status::kOk);
      EXPECT_EQ(outside, 0);
      for (std::int32_t y = 0; y < 30; ++y)
        for (std::int32_t x = 0; x < 40; ++x) ASSERT_EQ(dst.at(x, y), src.at(x + 20 + t, y + 15 - t)) << g << " " << t;
    }
}

TEST(WarpGrid, HalfPixelTranslationRoundsLikeTheExactWarp) {
  Image src(4, 1);
  src.px = {10, 20, 40, 81};
  Image dst(3, 1);
  std::int32_t outside = -1;
  bsp::Work work;
  ASSERT_EQ(tv::warp_homography_grid(src.view(), tv::Homography{{1, 0, 0.5, 0, 1, 0, 0, 0, 1}}, 8, dst.mview(), 0,
                                     outside, work),
            tv::Status::kOk);
  EXPECT_EQ(outside, 0);
  EXPECT_EQ(dst.at(0, 0), 15);
  EXPECT_EQ(dst.at(1, 0), 30);
  EXPECT_EQ(dst.at(2, 0), 61);  // 60.5 rounds half up, as lround() does
}

TEST(WarpGrid, AnAffineMapIsInterpolatedExactlyUpToFixedPointRounding) {
  // Bilinear interpolation reproduces an affine map: only Q16 rounding is left (< 2^-12 px at G = 32).
  const double c = std::cos(0.3) * 0.8, s = std::sin(0.3) * 0.8;
  const tv::Homography a{{c, -s, 40.5, s, c, 30.25, 0, 0, 1}};
  for (std::int32_t g = tv::kGridWarpMinPx; g <= tv::kGridWarpMaxPx; g *= 2) {
    std::int32_t unusable = -1;
    EXPECT_LT(max_coordinate_error_px(a, g, 100, 90, unusable), 1.0 / 4096.0) << g;
    EXPECT_EQ(unusable, 0);
  }
}

TEST(WarpGrid, StrongPerspectiveNeedsFourPixelSpacingForOneSixtyFourthPixel) {
  // The scale changes by ~60 % across the 256 px destination (w from 1 to 1.58): a camera far
  // off nadir. Interpolation error grows as G^2; measured (printed per G): 0.007 px at G 4,
  // 0.028 at 8 (pixels still within 1 DN of the exact warp), 0.11 at 16 (4 DN), 0.42 at 32.
  const tv::Homography h{{1.2, 0.1, 30.0, -0.05, 1.1, 40.0, 0.0015, 0.0008, 1.0}};
  const Image src = vision_test::smooth_texture(320, 320, 2, 102);
  double err[6] = {};
  for (std::int32_t g = tv::kGridWarpMinPx, i = 0; g <= tv::kGridWarpMaxPx; g *= 2, ++i) {
    std::int32_t unusable = -1;
    err[i] = max_coordinate_error_px(h, g, 256, 256, unusable);
    EXPECT_EQ(unusable, 0);
    std::int32_t outside = -1;
    const int dn = max_pixel_difference(src, h, g, 256, 256, outside);
    std::printf("[ grid warp, strong perspective ] G %2d: source coordinates within %.5f px, pixels within %d DN\n",
                g, err[i], dn);
    if (g <= 4) {
      EXPECT_LT(err[i], 1.0 / 64.0) << g;
    }
    if (g <= 8) {
      EXPECT_LT(err[i], 1.0 / 32.0) << g;
      EXPECT_LE(dn, 1) << g;
    }
  }
  EXPECT_GT(err[2], err[0]);  // the bound is the interpolation, not the rounding
}

TEST(WarpGrid, PixelsMappedOutsideGetTheFillValueByTheExactWarpsRule) {
  const Image src = vision_test::random_image(10, 10, 103);
  Image dst(10, 10);
  std::int32_t outside = -1;
  bsp::Work work;
  ASSERT_EQ(tv::warp_homography_grid(src.view(), tv::Homography{{1, 0, 5, 0, 1, 0, 0, 0, 1}}, 4, dst.mview(), 3,
                                     outside, work),
            tv::Status::kOk);
  EXPECT_EQ(outside, 5 * 10);  // columns 5..9 map to 10..14; column 4 maps to 9, the last inside
  for (std::int32_t y = 0; y < 10; ++y) {
    EXPECT_EQ(dst.at(4, y), src.at(9, y));
    EXPECT_EQ(dst.at(6, y), 3);
  }
  // Left and top edges: -0.5 px is outside, 0 is inside.
  ASSERT_EQ(tv::warp_homography_grid(src.view(), tv::Homography{{1, 0, -0.5, 0, 1, 0, 0, 0, 1}}, 4, dst.mview(), 3,
                                     outside, work),
            tv::Status::kOk);
  EXPECT_EQ(outside, 10);
  EXPECT_EQ(dst.at(0, 5), 3);
}

TEST(WarpGrid, CellsWithANodeBehindTheCameraAreOutside) {
  // w = 1 - 0.1 x: nodes at x >= 10 are behind the camera.
  const Image src = vision_test::random_image(64, 64, 104);
  Image dst(32, 8);
  std::int32_t outside = -1;
  bsp::Work work;
  ASSERT_EQ(tv::warp_homography_grid(src.view(), tv::Homography{{1, 0, 0, 0, 1, 0, -0.1, 0, 1}}, 8, dst.mview(), 7,
                                     outside, work),
            tv::Status::kOk);
  // Cell 0 (x 0..7, nodes at 0 and 8, sources 0..40) is in front and inside; cells 1..3 have a
  // node at 16, 24 or 32 behind.
  EXPECT_EQ(outside, 24 * 8);
  EXPECT_EQ(dst.at(0, 0), src.at(0, 0));
  EXPECT_EQ(dst.at(20, 3), 7);
}

TEST(WarpGrid, RejectsUnsupportedSpacingsAndTooWideDestinations) {
  const Image src = vision_test::random_image(16, 16, 105);
  Image dst(16, 16);
  std::int32_t outside = -1;
  bsp::Work work;
  for (std::int32_t g : {0, 1, 2, 3, 6, 12, 64}) {
    EXPECT_EQ(tv::warp_homography_grid(src.view(), tv::Homography{}, g, dst.mview(), 0, outside, work),
              tv::Status::kBadInput)
        << g;
  }
  EXPECT_EQ(tv::warp_homography_grid(tv::ConstImageU8{}, tv::Homography{}, 8, dst.mview(), 0, outside, work),
            tv::Status::kBadInput);
  Image wide(8 * (tv::kGridWarpMaxNodes - 1) + 1, 1);  // needs kGridWarpMaxNodes + 1 node columns
  EXPECT_EQ(tv::warp_homography_grid(src.view(), tv::Homography{}, 8, wide.mview(), 0, outside, work),
            tv::Status::kTooLarge);
  Image widest(8 * (tv::kGridWarpMaxNodes - 1), 1);
  EXPECT_EQ(tv::warp_homography_grid(src.view(), tv::Homography{}, 8, widest.mview(), 0, outside, work),
            tv::Status::kOk);
}

TEST(WarpGrid, CostsAFewPercentOfTheExactWarpOnTheTile64) {
  const tv::Homography h{{1.2, 0.1, 30.0, -0.05, 1.1, 40.0, 0.0015, 0.0008, 1.0}};
  const Image src = vision_test::smooth_texture(320, 320, 2, 106);
  Image dst(256, 256);
  std::int32_t outside = -1;
  bsp::Work exact;
  ASSERT_EQ(tv::warp_homography(src.view(), h, dst.mview(), 0, outside, exact), tv::Status::kOk);
  const auto c_exact = static_cast<double>(bsp::cost_of(bsp::kTile64, exact));
  for (std::int32_t g : {8, 16}) {
    bsp::Work grid;
    ASSERT_EQ(tv::warp_homography_grid(src.view(), h, g, dst.mview(), 0, outside, grid), tv::Status::kOk);
    const auto c_grid = static_cast<double>(bsp::cost_of(bsp::kTile64, grid));
    std::printf("[ grid warp, 256 x 256 ] TILE64 cycles: exact %.2f M, grid G %d %.2f M (%.1f per px)\n", c_exact / 1e6,
                g, c_grid / 1e6, c_grid / (256.0 * 256.0));
    EXPECT_GT(grid.fdivs, 0U);  // the nodes are counted
    EXPECT_GT(grid.int_ops, 256U * 256U * 20U);
    EXPECT_LT(c_grid, 0.05 * c_exact) << g;
  }
}

}  // namespace
