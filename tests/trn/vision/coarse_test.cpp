/**
 * @file coarse_test.cpp
 * @brief Coarse stage: box decimation is exact, a kilometre-level position error
 *        (>= 3 km at 12 m/px) is recovered on a synthetic textured scene, and the transform
 *        path gives the spatial path's result bit for bit for a fraction of its cycles.
 */
#include "trn/vision/coarse.hpp"

#include "bsp_tile64/emu/cost_model.hpp"
#include "bsp_tile64/emu/profile.hpp"
#include "tests/trn/vision/synth.hpp"

#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <vector>

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

constexpr std::int32_t kSide = 384;       // camera patch, map px (4.6 km)
constexpr std::int32_t kPredicted = 320;  // predicted top-left: the map centre

/** One trial of the kilometre scenes: the true error (ex, ey) map px and the camera patch seen there. */
struct Trial {
  std::int32_t ex = 0;
  std::int32_t ey = 0;
  Image img;
};

/** The next trial from @p rng: an error of 3-3.5 km in a random direction. */
Trial next_trial(const Image& map, bsp::Rng& rng) {
  Trial t;
  const double radius_m = rng.uniform(3000.0, 3500.0);
  const double angle = rng.uniform(0.0, 6.283185307179586);
  t.ex = static_cast<std::int32_t>(std::lround(radius_m * std::cos(angle) / kMetresPerPx));
  t.ey = static_cast<std::int32_t>(std::lround(radius_m * std::sin(angle) / kMetresPerPx));
  t.img = camera_patch(map, kPredicted + t.ex, kPredicted + t.ey, kSide, rng);
  return t;
}

TEST(Coarse, RecoversPositionErrorsOfThreeKilometresAndMore) {
  const std::uint64_t seed = 73;
  const Image map = make_scene(seed);
  static tv::CoarseWorkspace ws;
  bsp::Rng rng(seed, bsp::StreamId::kTest, 4);
  for (int trial = 0; trial < 6; ++trial) {
    const Trial t = next_trial(map, rng);
    const std::int32_t ex = t.ex;
    const std::int32_t ey = t.ey;
    tv::CoarseResult r;
    bsp::Work work;
    ASSERT_EQ(tv::coarse_match(map.view(), t.img.view(), tv::CoarseParams{}, ws, r, work), tv::Status::kOk);
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

/** Both results, field by field and bit for bit, the surfaces included. */
void expect_identical(const tv::CoarseResult& a, const tv::CoarseResult& b, const char* what) {
  EXPECT_EQ(std::bit_cast<std::uint64_t>(b.x_px), std::bit_cast<std::uint64_t>(a.x_px)) << what;
  EXPECT_EQ(std::bit_cast<std::uint64_t>(b.y_px), std::bit_cast<std::uint64_t>(a.y_px)) << what;
  const tv::MatchResult& ma = a.match;
  const tv::MatchResult& mb = b.match;
  EXPECT_EQ(mb.reason(), ma.reason()) << what;
  EXPECT_EQ(mb.peak.ix, ma.peak.ix) << what;
  EXPECT_EQ(mb.peak.iy, ma.peak.iy) << what;
  EXPECT_EQ(std::bit_cast<std::uint64_t>(mb.peak.x_px), std::bit_cast<std::uint64_t>(ma.peak.x_px)) << what;
  EXPECT_EQ(std::bit_cast<std::uint64_t>(mb.peak.y_px), std::bit_cast<std::uint64_t>(ma.peak.y_px)) << what;
  EXPECT_EQ(std::bit_cast<std::uint32_t>(mb.peak.score), std::bit_cast<std::uint32_t>(ma.peak.score)) << what;
  EXPECT_EQ(std::bit_cast<std::uint32_t>(mb.peak.second), std::bit_cast<std::uint32_t>(ma.peak.second)) << what;
  EXPECT_EQ(std::bit_cast<std::uint64_t>(mb.x_px), std::bit_cast<std::uint64_t>(ma.x_px)) << what;
  EXPECT_EQ(std::bit_cast<std::uint64_t>(mb.y_px), std::bit_cast<std::uint64_t>(ma.y_px)) << what;
  EXPECT_EQ(mb.flat_windows, ma.flat_windows) << what;
  EXPECT_EQ(mb.recomputes, ma.recomputes) << what;
  EXPECT_EQ(mb.check_failed, ma.check_failed) << what;
  EXPECT_EQ(mb.first_check, ma.first_check) << what;
}

/** A copy of a result's surface (it lives in the workspace, which the next call reuses). */
std::vector<std::uint32_t> surface_bits(const tv::CoarseResult& r) {
  std::vector<std::uint32_t> v;
  for (std::int32_t y = 0; y < r.match.surface.height; ++y)
    for (std::int32_t x = 0; x < r.match.surface.width; ++x) v.push_back(std::bit_cast<std::uint32_t>(r.match.surface.at(x, y)));
  return v;
}

// The kilometre scenes above, searched by both methods: the same CoarseResult bit for bit, the whole
// 193 x 193 surface included, for under a quarter of the TILE64 cycles.
TEST(Coarse, TheTransformPathGivesTheSpatialResultBitForBit) {
  const std::uint64_t seed = 73;
  const Image map = make_scene(seed);
  static tv::CoarseWorkspace ws;
  bsp::Rng rng(seed, bsp::StreamId::kTest, 4);
  tv::CoarseParams spatial_p;
  tv::CoarseParams transform_p;
  transform_p.method = tv::CorrelationMethod::kTransform;
  for (int trial = 0; trial < 6; ++trial) {
    const Trial t = next_trial(map, rng);
    tv::CoarseResult rs;
    tv::CoarseResult rt;
    bsp::Work ws_work;
    bsp::Work wt_work;
    ASSERT_EQ(tv::coarse_match(map.view(), t.img.view(), spatial_p, ws, rs, ws_work), tv::Status::kOk);
    const std::vector<std::uint32_t> surface_s = surface_bits(rs);
    ASSERT_EQ(tv::coarse_match(map.view(), t.img.view(), transform_p, ws, rt, wt_work), tv::Status::kOk);
    ASSERT_TRUE(rt.accepted()) << "seed " << seed << " trial " << trial;
    expect_identical(rs, rt, "transform vs spatial");
    EXPECT_EQ(surface_bits(rt), surface_s) << "seed " << seed << " trial " << trial;
    const auto cs = static_cast<double>(bsp::cost_of(bsp::kTile64, ws_work));
    const auto ct = static_cast<double>(bsp::cost_of(bsp::kTile64, wt_work));
    if (trial == 0) {
      std::printf("coarse_match 1024 px region, factor 4, 64 on 256: TILE64 cycles spatial %.1f M, transform %.1f M (%.1fx)\n",
                  cs / 1e6, ct / 1e6, cs / ct);
    }
    EXPECT_LT(ct, 0.25 * cs) << "trial " << trial;
  }
}

// A flat patch and a one-offset search (template as large as the window) agree too.
TEST(Coarse, TheTransformPathAgreesOnFlatAndSingleOffsetSearches) {
  static tv::CoarseWorkspace ws;
  tv::CoarseParams p;
  tv::CoarseParams pt;
  pt.method = tv::CorrelationMethod::kTransform;
  const Image map = vision_test::smooth_texture(512, 512, 2, 75);
  Image flat_map = map;
  for (std::int32_t y = 0; y < 512; ++y)
    for (std::int32_t x = 0; x < 300; ++x) flat_map.at(x, y) = 60U;  // a flat band wider than the template
  const Image img = vision_test::smooth_texture(300, 300, 2, 76);
  const Image* const maps[] = {&map, &flat_map};
  for (const Image* m : maps) {
    tv::CoarseResult a;
    tv::CoarseResult b;
    bsp::Work w;
    ASSERT_EQ(tv::coarse_match(m->view(), img.view(), p, ws, a, w), tv::Status::kOk);
    const std::vector<std::uint32_t> sa = surface_bits(a);
    ASSERT_EQ(tv::coarse_match(m->view(), img.view(), pt, ws, b, w), tv::Status::kOk);
    expect_identical(a, b, m == &map ? "textured" : "flat band");
    EXPECT_EQ(surface_bits(b), sa);
  }
  EXPECT_GT(ws.corr.flags[0], 0U) << "the flat band must give flat windows";
  // Template side = decimated image side = decimated map side: one offset.
  const Image small_map = vision_test::smooth_texture(256, 256, 2, 77);
  tv::CoarseParams one = p;
  one.template_px = 64;
  tv::CoarseParams one_t = one;
  one_t.method = tv::CorrelationMethod::kTransform;
  tv::CoarseResult a;
  tv::CoarseResult b;
  bsp::Work w;
  ASSERT_EQ(tv::coarse_match(small_map.view(), small_map.view(), one, ws, a, w), tv::Status::kOk);
  ASSERT_EQ(tv::coarse_match(small_map.view(), small_map.view(), one_t, ws, b, w), tv::Status::kOk);
  EXPECT_EQ(a.match.surface.width, 1);
  expect_identical(a, b, "one offset");
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
