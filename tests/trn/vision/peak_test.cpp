/**
 * @file peak_test.cpp
 * @brief Peak refinement and quality checks: exact parabola vertex, rejection of
 *        repetitive, edge and weak peaks, acceptance of a good textured match.
 */
#include "trn/vision/fine.hpp"
#include "trn/vision/peak.hpp"

#include "tests/trn/vision/synth.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>

namespace {

namespace tv = trn::vision;
using vision_test::Image;

TEST(Peak, ParabolaOffsetIsExactForAParabolaAtEveryTestedVertex) {
  for (int k = -50; k <= 50; ++k) {
    const double d = k / 100.0;
    auto f = [d](double x) { return 0.9 - 0.3 * (x - d) * (x - d); };
    EXPECT_NEAR(tv::parabola_offset(f(-1), f(0), f(1)), d, 1e-12) << "vertex " << d;
  }
}

TEST(Peak, ParaboloidOffsetIsExactForARotatedQuadraticAtEveryTestedVertex) {
  for (int ky = -9; ky <= 9; ++ky) {
    for (int kx = -9; kx <= 9; ++kx) {
      const double x0 = kx / 10.0;
      const double y0 = ky / 10.0;
      // An elongated peak along the diagonal: the per-axis parabola gets this wrong.
      auto f = [&](double x, double y) {
        const double u = x - x0, v = y - y0;
        return 0.95 - 0.20 * u * u - 0.25 * u * v - 0.15 * v * v;
      };
      double s[9];
      for (int j = 0; j < 3; ++j)
        for (int i = 0; i < 3; ++i) s[j * 3 + i] = f(i - 1, j - 1);
      double dx = 0, dy = 0;
      ASSERT_TRUE(tv::paraboloid_offset(s, dx, dy)) << x0 << "," << y0;
      EXPECT_NEAR(dx, x0, 1e-12);
      EXPECT_NEAR(dy, y0, 1e-12);
    }
  }
}

TEST(Peak, ParaboloidRejectsASaddle) {
  const double s[9] = {0.0, 0.5, 0.0, 0.5, 0.6, 0.5, 0.0, 0.5, 0.0};  // a maximum
  const double saddle[9] = {0.9, 0.5, 0.9, 0.1, 0.5, 0.1, 0.9, 0.5, 0.9};
  double dx = 7, dy = 7;
  EXPECT_TRUE(tv::paraboloid_offset(s, dx, dy));
  EXPECT_NEAR(dx, 0.0, 1e-12);
  double sx = 7, sy = 7;
  EXPECT_FALSE(tv::paraboloid_offset(saddle, sx, sy));
  EXPECT_EQ(sx, 7.0);
}

TEST(Peak, ParabolaOffsetKeepsTheIntegerPositionWhenNotAMaximum) {
  EXPECT_EQ(tv::parabola_offset(0.5, 0.5, 0.5), 0.0);
  EXPECT_EQ(tv::parabola_offset(0.2, 0.5, 0.9), 0.0);
}

/** Window of a stripe or checker pattern, template cut from its middle. */
void expect_ambiguous(const Image& win, const char* what) {
  Image t(21, 21);
  for (std::int32_t y = 0; y < 21; ++y)
    for (std::int32_t x = 0; x < 21; ++x) t.at(x, y) = win.at(x + 14, y + 14);
  static tv::FineWorkspace ws;
  tv::MatchResult r;
  bsp::Work work;
  ASSERT_EQ(tv::fine_match(t.view(), win.view(), tv::kFineQuality, ws, r, work), tv::Status::kOk) << what;
  EXPECT_FALSE(r.accepted()) << what;
  EXPECT_EQ(r.reason(), tv::Reject::kAmbiguous) << what << " second " << r.peak.second << " peak " << r.peak.score;
}

TEST(Peak, RepetitiveStripesAreRejectedAsAmbiguous) {
  Image win(49, 49);
  for (std::int32_t y = 0; y < 49; ++y)
    for (std::int32_t x = 0; x < 49; ++x)
      win.at(x, y) = vision_test::clamp_u8(128.0 + 100.0 * std::sin(6.283185307179586 * x / 6.0));
  expect_ambiguous(win, "vertical stripes, period 6 px");
  Image diag(49, 49);
  for (std::int32_t y = 0; y < 49; ++y)
    for (std::int32_t x = 0; x < 49; ++x) diag.at(x, y) = ((x + y) / 4) % 2 == 0 ? 40 : 210;
  expect_ambiguous(diag, "diagonal bars, period 8 px");
}

TEST(Peak, CheckerPatternIsRejectedAsAmbiguous) {
  Image win(49, 49);
  for (std::int32_t y = 0; y < 49; ++y)
    for (std::int32_t x = 0; x < 49; ++x) win.at(x, y) = ((x / 4) + (y / 4)) % 2 == 0 ? 30 : 220;
  expect_ambiguous(win, "checker, 4 px squares");
}

TEST(Peak, TexturedPatchIsAcceptedAtItsTruePosition) {
  const std::uint64_t seed = 51;
  const Image win = vision_test::smooth_texture(49, 49, 2, seed);
  Image t(21, 21);
  for (std::int32_t y = 0; y < 21; ++y)
    for (std::int32_t x = 0; x < 21; ++x) t.at(x, y) = win.at(x + 11, y + 17);
  static tv::FineWorkspace ws;
  tv::MatchResult r;
  bsp::Work work;
  ASSERT_EQ(tv::fine_match(t.view(), win.view(), tv::kFineQuality, ws, r, work), tv::Status::kOk);
  ASSERT_TRUE(r.accepted()) << "seed " << seed << " reason " << static_cast<int>(r.reason());
  // The autocorrelation of a finite patch is not exactly symmetric: a small sub-pixel offset remains.
  EXPECT_EQ(r.peak.ix, 11);
  EXPECT_EQ(r.peak.iy, 17);
  EXPECT_NEAR(r.x_px, 11.0, 0.15);
  EXPECT_NEAR(r.y_px, 17.0, 0.15);
  EXPECT_LT(r.peak.second, 0.8F * r.peak.score);
}

TEST(Peak, PeakOnTheWindowEdgeIsRejected) {
  const std::uint64_t seed = 52;
  const Image win = vision_test::smooth_texture(49, 49, 2, seed);
  Image t(21, 21);
  for (std::int32_t y = 0; y < 21; ++y)
    for (std::int32_t x = 0; x < 21; ++x) t.at(x, y) = win.at(x, y + 10);  // true position: column 0
  static tv::FineWorkspace ws;
  tv::MatchResult r;
  bsp::Work work;
  ASSERT_EQ(tv::fine_match(t.view(), win.view(), tv::kFineQuality, ws, r, work), tv::Status::kOk);
  EXPECT_EQ(r.peak.ix, 0) << "seed " << seed;
  EXPECT_EQ(r.reason(), tv::Reject::kOnEdge);
}

TEST(Peak, UnrelatedTemplateIsRejectedForALowPeak) {
  const std::uint64_t seed = 53;
  const Image win = vision_test::random_image(49, 49, seed);
  const Image t = vision_test::random_image(21, 21, seed + 1000);
  static tv::FineWorkspace ws;
  tv::MatchResult r;
  bsp::Work work;
  ASSERT_EQ(tv::fine_match(t.view(), win.view(), tv::kFineQuality, ws, r, work), tv::Status::kOk);
  EXPECT_EQ(r.reason(), tv::Reject::kLowPeak) << "seed " << seed << " peak " << r.peak.score;
}

TEST(Peak, FineStageRejectsTemplatesAboveItsCapacity) {
  const Image win = vision_test::random_image(60, 60, 1);
  const Image t = vision_test::random_image(tv::kFineMaxTemplatePx + 1, 21, 2);
  static tv::FineWorkspace ws;
  tv::MatchResult r;
  bsp::Work work;
  EXPECT_EQ(tv::fine_match(t.view(), win.view(), tv::kFineQuality, ws, r, work), tv::Status::kTooLarge);
}

}  // namespace
