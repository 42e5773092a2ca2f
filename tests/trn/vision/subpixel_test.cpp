/**
 * @file subpixel_test.cpp
 * @brief Sub-pixel accuracy of the fine stage on band-limited textures shifted by known
 *        fractional offsets: RMS error <= 0.1 px.
 */
#include "trn/vision/fine.hpp"

#include "tests/trn/vision/synth.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstdio>

namespace {

namespace tv = trn::vision;
using vision_test::Image;

struct Rms {
  double sum_sq = 0.0;
  int n = 0;
  int rejected = 0;
  double value() const { return std::sqrt(sum_sq / n); }
};

/**
 * Samples a 21x21 template and a 49x49 window of the same continuous field so that
 * the template's true top-left in the window is (14 + dx, 14 + dy), and measures the error.
 */
Rms run_trials(std::uint64_t seed, int trials, double noise_dn, tv::Subpixel method) {
  const vision_test::WaveField field(seed, 40, 0.12);
  bsp::Rng rng(seed, bsp::StreamId::kTest, 3);
  static tv::FineWorkspace ws;
  tv::QualityParams q = tv::kFineQuality;
  q.subpixel = method;
  Rms rms;
  for (int i = 0; i < trials; ++i) {
    const double dx = rng.uniform(-0.5, 0.5);
    const double dy = rng.uniform(-0.5, 0.5);
    const double tx0 = rng.uniform(0.0, 2000.0);
    const double ty0 = rng.uniform(0.0, 2000.0);
    const Image t = field.sample(tx0, ty0, 21, 21, 10.0, noise_dn, rng);
    const Image win = field.sample(tx0 - 14.0 - dx, ty0 - 14.0 - dy, 49, 49, 10.0, noise_dn, rng);
    tv::MatchResult r;
    bsp::Work work;
    if (tv::fine_match(t.view(), win.view(), q, ws, r, work) != tv::Status::kOk || !r.accepted()) {
      ++rms.rejected;
      continue;
    }
    const double ex = r.x_px - (14.0 + dx);
    const double ey = r.y_px - (14.0 + dy);
    rms.sum_sq += ex * ex + ey * ey;
    ++rms.n;
  }
  return rms;
}

TEST(Subpixel, RmsErrorOnShiftedBandLimitedTextureIsAtMostATenthOfAPixel) {
  const std::uint64_t seed = 61;
  const Rms axis = run_trials(seed, 300, 1.0, tv::Subpixel::kParabola);
  std::printf("sub-pixel (per-axis parabola, for comparison): RMS radial error %.4f px\n", axis.value());
  const Rms rms = run_trials(seed, 300, 1.0, tv::Subpixel::kParaboloid);
  std::printf("sub-pixel: %d accepted, %d rejected, RMS radial error %.4f px (seed %llu, noise 1 DN)\n", rms.n,
              rms.rejected, rms.value(), static_cast<unsigned long long>(seed));
  EXPECT_GE(rms.n, 285) << "seed " << seed;
  EXPECT_LE(rms.value(), 0.1) << "seed " << seed;
}

TEST(Subpixel, RmsErrorStaysBelowATenthOfAPixelWithStrongerNoise) {
  const std::uint64_t seed = 62;
  const Rms rms = run_trials(seed, 200, 4.0, tv::Subpixel::kParaboloid);
  std::printf("sub-pixel: %d accepted, %d rejected, RMS radial error %.4f px (seed %llu, noise 4 DN)\n", rms.n,
              rms.rejected, rms.value(), static_cast<unsigned long long>(seed));
  EXPECT_GE(rms.n, 180) << "seed " << seed;
  EXPECT_LE(rms.value(), 0.1) << "seed " << seed;
}

}  // namespace
