/**
 * @file warp_test.cpp
 * @brief Bilinear warps: identity and integer translations reproduce the input; a known
 *        affine and a homography map points where they should; outside pixels are filled.
 */
#include "trn/vision/warp.hpp"

#include "tests/trn/vision/synth.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>

namespace {

namespace tv = trn::vision;
using vision_test::Image;

TEST(Warp, IdentityReproducesTheInputExactly) {
  const Image src = vision_test::random_image(40, 30, 91);
  Image dst(40, 30);
  std::int32_t outside = -1;
  bsp::Work work;
  ASSERT_EQ(tv::warp_affine(src.view(), tv::Affine2{}, dst.mview(), 0, outside, work), tv::Status::kOk);
  EXPECT_EQ(outside, 0);
  EXPECT_EQ(dst.px, src.px);
  Image dst_h(40, 30);
  ASSERT_EQ(tv::warp_homography(src.view(), tv::Homography{}, dst_h.mview(), 0, outside, work), tv::Status::kOk);
  EXPECT_EQ(dst_h.px, src.px);
  EXPECT_GT(work.flops, 0U);
}

TEST(Warp, IntegerTranslationReproducesTheShiftedInput) {
  const Image src = vision_test::random_image(40, 30, 92);
  for (std::int32_t ty = -3; ty <= 3; ++ty)
    for (std::int32_t tx = -3; tx <= 3; ++tx) {
      Image dst(20, 15);
      const tv::Affine2 shift{{1.0, 0.0, 10.0 + tx, 0.0, 1.0, 8.0 + ty}};
      std::int32_t outside = -1;
      bsp::Work work;
      ASSERT_EQ(tv::warp_affine(src.view(), shift, dst.mview(), 0, outside, work), tv::Status::kOk);
      EXPECT_EQ(outside, 0);
      for (std::int32_t y = 0; y < 15; ++y)
        for (std::int32_t x = 0; x < 20; ++x) ASSERT_EQ(dst.at(x, y), src.at(x + 10 + tx, y + 8 + ty)) << tx << "," << ty;
    }
}

TEST(Warp, HalfPixelTranslationAveragesNeighbours) {
  Image src(4, 1);
  src.px = {10, 20, 40, 80};
  Image dst(3, 1);
  std::int32_t outside = -1;
  bsp::Work work;
  ASSERT_EQ(tv::warp_affine(src.view(), tv::Affine2{{1, 0, 0.5, 0, 1, 0}}, dst.mview(), 0, outside, work),
            tv::Status::kOk);
  EXPECT_EQ(dst.at(0, 0), 15);
  EXPECT_EQ(dst.at(1, 0), 30);
  EXPECT_EQ(dst.at(2, 0), 60);
}

TEST(Warp, KnownAffineMapsALinearRampExactly) {
  // Bilinear interpolation reproduces a linear function: sample I = x + y under a rotation and scale.
  Image src(100, 100);
  for (std::int32_t y = 0; y < 100; ++y)
    for (std::int32_t x = 0; x < 100; ++x) src.at(x, y) = static_cast<std::uint8_t>(x + y);
  const double c = std::cos(0.3) * 0.8, s = std::sin(0.3) * 0.8;
  const tv::Affine2 a{{c, -s, 40.0, s, c, 30.0}};
  Image dst(30, 30);
  std::int32_t outside = -1;
  bsp::Work work;
  ASSERT_EQ(tv::warp_affine(src.view(), a, dst.mview(), 0, outside, work), tv::Status::kOk);
  EXPECT_EQ(outside, 0);
  for (std::int32_t y = 0; y < 30; ++y)
    for (std::int32_t x = 0; x < 30; ++x) {
      const double xs = c * x - s * y + 40.0, ys = s * x + c * y + 30.0;
      EXPECT_NEAR(dst.at(x, y), xs + ys, 0.5 + 1e-9) << x << "," << y;
    }
}

TEST(Warp, AffineInverseRoundTripsPoints) {
  const tv::Affine2 a{{0.9, -0.2, 5.0, 0.3, 1.1, -7.0}};
  tv::Affine2 inv;
  ASSERT_TRUE(tv::invert_affine(a, inv));
  for (double y = -10; y <= 10; y += 5)
    for (double x = -10; x <= 10; x += 5) {
      const double u = a.a[0] * x + a.a[1] * y + a.a[2], v = a.a[3] * x + a.a[4] * y + a.a[5];
      EXPECT_NEAR(inv.a[0] * u + inv.a[1] * v + inv.a[2], x, 1e-12);
      EXPECT_NEAR(inv.a[3] * u + inv.a[4] * v + inv.a[5], y, 1e-12);
    }
  tv::Affine2 untouched;
  EXPECT_FALSE(tv::invert_affine(tv::Affine2{{1, 2, 0, 2, 4, 0}}, untouched));
}

TEST(Warp, HomographyMovesAMarkedPixelWhereTheMappingSays) {
  Image src(64, 64, 0);
  src.at(40, 20) = 255;
  // dst -> src: xs = (x + 8) / w, ys = (y + 4) / w with w = 1 + 0.01 x.
  const tv::Homography h{{1, 0, 8, 0, 1, 4, 0.01, 0, 1}};
  // Solve for the destination of (40, 20): x + 8 = 40 (1 + 0.01 x) -> x = 32 / 0.6.
  Image dst(64, 64);
  std::int32_t outside = -1;
  bsp::Work work;
  ASSERT_EQ(tv::warp_homography(src.view(), h, dst.mview(), 7, outside, work), tv::Status::kOk);
  std::int32_t bx = -1, by = -1, best = -1;
  for (std::int32_t y = 0; y < 64; ++y)
    for (std::int32_t x = 0; x < 64; ++x)
      if (dst.at(x, y) != 7 && dst.at(x, y) > best) { best = dst.at(x, y); bx = x; by = y; }
  const double x_true = 32.0 / 0.6;              // 53.3
  const double y_true = 20.0 * (1 + 0.01 * x_true) - 4.0;  // 26.7
  EXPECT_LE(std::fabs(bx - x_true), 1.0);
  EXPECT_LE(std::fabs(by - y_true), 1.0);
  EXPECT_GT(outside, 0);  // the right part of dst maps outside the source
}

TEST(Warp, PixelsMappedOutsideGetTheFillValue) {
  const Image src = vision_test::random_image(10, 10, 93);
  Image dst(10, 10);
  std::int32_t outside = -1;
  bsp::Work work;
  ASSERT_EQ(tv::warp_affine(src.view(), tv::Affine2{{1, 0, 5, 0, 1, 0}}, dst.mview(), 3, outside, work),
            tv::Status::kOk);
  EXPECT_EQ(outside, 5 * 10);  // columns 5..9 map to 10..14; column 4 maps to 9, the last inside
  for (std::int32_t y = 0; y < 10; ++y) {
    EXPECT_EQ(dst.at(4, y), src.at(9, y));
    EXPECT_EQ(dst.at(6, y), 3);
  }
}

}  // namespace
