/**
 * @file ncc_test.cpp
 * @brief NCC surface equals a naive double-precision reference at every window position;
 *        integral images give exact window sums; flat windows and templates are handled.
 */
#include "trn/vision/correlator.hpp"
#include "trn/vision/fine.hpp"
#include "trn/vision/integral.hpp"
#include "trn/vision/ncc.hpp"

#include "tests/support/heap_probe.hpp"
#include "tests/trn/vision/synth.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <cstdint>
#include <string>
#include <vector>

namespace {

namespace tv = trn::vision;
using vision_test::Image;

TEST(Integral, RectangleSumsEqualBruteForceForEveryRectangleOfASmallImage) {
  const std::uint64_t seed = 11;
  const Image im = vision_test::random_image(9, 7, seed);
  static tv::FixedIntegral<16, 16> ii;
  bsp::Work work;
  ASSERT_EQ(ii.build(im.view(), work), tv::Status::kOk);
  for (std::int32_t y = 0; y < im.h; ++y)
    for (std::int32_t x = 0; x < im.w; ++x)
      for (std::int32_t h = 1; y + h <= im.h; ++h)
        for (std::int32_t w = 1; x + w <= im.w; ++w) {
          std::uint64_t s = 0, q = 0;
          for (std::int32_t j = y; j < y + h; ++j)
            for (std::int32_t i = x; i < x + w; ++i) { s += im.at(i, j); q += static_cast<std::uint64_t>(im.at(i, j)) * im.at(i, j); }
          ASSERT_EQ(ii.ref().rect_sum(x, y, w, h), s) << "seed " << seed << " rect " << x << "," << y;
          ASSERT_EQ(ii.ref().rect_sum_sq(x, y, w, h), q) << "seed " << seed;
        }
  EXPECT_GT(work.int_ops, 0U);
}

TEST(Integral, AllWhiteImageAtCapacityDoesNotOverflow) {
  static tv::FixedIntegral<256, 256> ii;
  Image im(256, 256, 255);
  bsp::Work work;
  ASSERT_EQ(ii.build(im.view(), work), tv::Status::kOk);
  EXPECT_EQ(ii.ref().rect_sum(0, 0, 256, 256), 255U * 256U * 256U);
  EXPECT_EQ(ii.ref().rect_sum_sq(0, 0, 256, 256), 65025ULL * 256U * 256U);
  EXPECT_EQ(ii.ref().rect_sum(1, 1, 255, 255), 255U * 255U * 255U);
}

TEST(Integral, RejectsImageAboveCapacity) {
  static tv::FixedIntegral<8, 8> ii;
  Image im(9, 8, 1);
  bsp::Work work;
  EXPECT_EQ(ii.build(im.view(), work), tv::Status::kTooLarge);
}

/** Runs correlate() and compares every surface entry with the naive reference. */
void expect_matches_reference(const Image& t, const Image& win, std::uint64_t seed) {
  static tv::CorrelatorWorkspace<96> ws;
  tv::MatchResult r;
  bsp::Work work;
  ASSERT_EQ(tv::correlate(t.view(), win.view(), tv::QualityParams{}, ws.buffers(), r, work), tv::Status::kOk);
  ASSERT_EQ(r.surface.width, win.w - t.w + 1);
  ASSERT_EQ(r.surface.height, win.h - t.h + 1);
  double worst = 0.0;
  for (std::int32_t y = 0; y < r.surface.height; ++y)
    for (std::int32_t x = 0; x < r.surface.width; ++x) {
      const double ref = vision_test::naive_ncc_at(t, win, x, y);
      const double err = std::fabs(r.surface.at(x, y) - ref);
      worst = std::max(worst, err);
      ASSERT_LE(err, 1e-6) << "seed " << seed << " at " << x << "," << y << " ref " << ref;
    }
  ::testing::Test::RecordProperty("worst_abs_error", std::to_string(worst));
}

TEST(Ncc, EqualsNaiveReferenceOnUniformRandomDataAtEveryPosition) {
  for (std::uint64_t seed = 1; seed <= 4; ++seed) {
    bsp::Rng rng(seed, bsp::StreamId::kTest, 9);
    const auto tw = static_cast<std::int32_t>(3 + rng.below(20));
    const auto th = static_cast<std::int32_t>(3 + rng.below(20));
    const Image t = vision_test::random_image(tw, th, seed * 100);
    const Image win = vision_test::random_image(tw + static_cast<std::int32_t>(rng.below(40)),
                                                th + static_cast<std::int32_t>(rng.below(40)), seed * 100 + 1);
    expect_matches_reference(t, win, seed);
  }
}

TEST(Ncc, EqualsNaiveReferenceOnTextureWithTheTemplateCutFromTheWindow) {
  const std::uint64_t seed = 21;
  const Image win = vision_test::smooth_texture(61, 61, 2, seed);
  Image t(21, 21);
  for (std::int32_t y = 0; y < 21; ++y)
    for (std::int32_t x = 0; x < 21; ++x) t.at(x, y) = win.at(x + 17, y + 9);
  expect_matches_reference(t, win, seed);
  static tv::CorrelatorWorkspace<96> ws;
  tv::MatchResult r;
  bsp::Work work;
  ASSERT_EQ(tv::correlate(t.view(), win.view(), tv::QualityParams{}, ws.buffers(), r, work), tv::Status::kOk);
  EXPECT_EQ(r.peak.ix, 17);
  EXPECT_EQ(r.peak.iy, 9);
  EXPECT_FLOAT_EQ(r.peak.score, 1.0F);
}

TEST(Ncc, FlatWindowsScoreZeroAndAreFlaggedWithoutDividingByZero) {
  const std::uint64_t seed = 31;
  Image win = vision_test::random_image(40, 30, seed);
  for (std::int32_t y = 0; y < 20; ++y)
    for (std::int32_t x = 0; x < 25; ++x) win.at(x, y) = 77;  // a constant block holding several windows
  const Image t = vision_test::random_image(9, 9, seed + 1);
  expect_matches_reference(t, win, seed);
  static tv::FixedIntegral<64, 64> ii;
  bsp::Work work;
  ASSERT_EQ(ii.build(win.view(), work), tv::Status::kOk);
  tv::TemplateStats st;
  ASSERT_EQ(tv::template_stats(t.view(), st, work), tv::Status::kOk);
  std::vector<float> surf(std::size_t{32} * 22U);
  std::vector<std::uint8_t> flags(std::size_t{32} * 22U);
  std::int32_t flat = 0;
  ASSERT_EQ(tv::ncc_surface(t.view(), st, win.view(), ii.ref(), {surf.data(), 32, 22, 32},
                            {flags.data(), 32, 22, 32}, flat, work), tv::Status::kOk);
  EXPECT_EQ(flat, (25 - 9 + 1) * (20 - 9 + 1));  // windows wholly inside the block
  for (std::int32_t y = 0; y < 22; ++y)
    for (std::int32_t x = 0; x < 32; ++x) {
      const bool inside = x + 9 <= 25 && y + 9 <= 20;
      const std::size_t i = vision_test::idx(x, y, 32);
      EXPECT_EQ(flags[i], inside ? 1U : 0U) << x << "," << y;
      if (inside) {
        EXPECT_EQ(surf[i], 0.0F);
      }
      EXPECT_TRUE(std::isfinite(surf[i]));
    }
}

TEST(Ncc, FlatTemplateIsRejectedNotDividedBy) {
  const Image win = vision_test::random_image(30, 30, 41);
  const Image t(11, 11, 200);
  static tv::CorrelatorWorkspace<64> ws;
  tv::MatchResult r;
  bsp::Work work;
  ASSERT_EQ(tv::correlate(t.view(), win.view(), tv::QualityParams{}, ws.buffers(), r, work), tv::Status::kOk);
  EXPECT_FALSE(r.accepted());
  EXPECT_EQ(r.reason(), tv::Reject::kFlatTemplate);
}

TEST(Ncc, AllFlatWindowIsRejected) {
  const Image win(30, 30, 90);
  const Image t = vision_test::random_image(11, 11, 42);
  static tv::CorrelatorWorkspace<64> ws;
  tv::MatchResult r;
  bsp::Work work;
  ASSERT_EQ(tv::correlate(t.view(), win.view(), tv::QualityParams{}, ws.buffers(), r, work), tv::Status::kOk);
  EXPECT_EQ(r.reason(), tv::Reject::kFlatWindow);
  EXPECT_EQ(r.flat_windows, 20 * 20);
}

TEST(Ncc, RejectsInconsistentSizesAndOversizedWindows) {
  static tv::CorrelatorWorkspace<32> ws;
  tv::MatchResult r;
  bsp::Work work;
  const Image small = vision_test::random_image(10, 10, 1);
  const Image big = vision_test::random_image(40, 40, 2);
  EXPECT_EQ(tv::correlate(big.view(), small.view(), {}, ws.buffers(), r, work), tv::Status::kBadInput);
  EXPECT_EQ(tv::correlate(small.view(), big.view(), {}, ws.buffers(), r, work), tv::Status::kTooLarge);
  EXPECT_EQ(tv::correlate(tv::ConstImageU8{}, small.view(), {}, ws.buffers(), r, work), tv::Status::kBadInput);
}

TEST(Ncc, WorkIsNonZeroAndScalesWithTemplateSizeTimesPositions) {
  const bsp::Work a = tv::ncc_surface_work(21, 21, 29, 29);
  const bsp::Work b = tv::ncc_surface_work(21, 21, 58, 29);
  const bsp::Work c = tv::ncc_surface_work(42, 21, 29, 29);
  EXPECT_GT(a.int_macs, 0U);
  EXPECT_GT(a.mem_words, 0U);
  EXPECT_GT(a.fdivs, 0U);
  EXPECT_EQ(b.int_macs, 2U * a.int_macs);
  EXPECT_GE(a.int_macs, 21U * 21U * 29U * 29U);
  EXPECT_NEAR(static_cast<double>(c.int_macs) / static_cast<double>(a.int_macs), 2.0, 0.02);
  // And what correlate() charges includes at least the surface's work.
  const Image win = vision_test::random_image(49, 49, 5);
  const Image t = vision_test::random_image(21, 21, 6);
  static tv::CorrelatorWorkspace<64> ws;
  tv::MatchResult r;
  bsp::Work work;
  ASSERT_EQ(tv::correlate(t.view(), win.view(), {}, ws.buffers(), r, work), tv::Status::kOk);
  EXPECT_GE(work.int_macs, a.int_macs);
  EXPECT_GT(work.mem_words, a.mem_words);
}

/** One surface of @p t over @p win: scores, flags, flat count, check sums and work. */
struct SurfaceRun {
  std::vector<float> surface;
  std::vector<std::uint8_t> flags;
  std::int32_t flat = 0;
  tv::NccCheck check;
  bsp::Work work;
};

SurfaceRun surface_run(const Image& t, const Image& win, tv::NccWideBuffer wide) {
  static tv::FixedIntegral<64, 64> ii;
  SurfaceRun r;
  tv::TemplateStats stats;
  bsp::Work setup;
  EXPECT_EQ(ii.build(win.view(), setup), tv::Status::kOk);
  EXPECT_EQ(tv::template_stats(t.view(), stats, setup), tv::Status::kOk);
  const std::int32_t sw = win.w - t.w + 1;
  const std::int32_t sh = win.h - t.h + 1;
  const auto positions = static_cast<std::size_t>(sw) * static_cast<std::size_t>(sh);
  r.surface.assign(positions, -2.0F);
  r.flags.assign(positions, 9U);
  EXPECT_EQ(tv::ncc_surface(t.view(), stats, win.view(), ii.ref(), {r.surface.data(), sw, sh, sw},
                            {r.flags.data(), sw, sh, sw}, r.flat, r.work, &r.check, wide),
            tv::Status::kOk);
  return r;
}

// Host speed only: the dot products taken from 16-bit copies (templates up to 32 wide, padded to
// 8, 16, 24 or 32 columns) give every score, flag, check sum and charge of the byte path, bit for
// bit; the copies are made only when the scratch holds them, and a template wider than 32 or a
// scratch one entry short takes the byte path without writing the scratch.
TEST(Ncc, DotProductsFromSixteenBitCopiesGiveTheByteSurfaceBitForBit) {
  std::vector<std::int16_t> scratch(static_cast<std::size_t>(tv::ncc_wide_entries(64)));
  std::int32_t cases = 0;
  for (const std::int32_t tw : {1, 5, 8, 9, 16, 17, 21, 24, 25, 31, 32, 33}) {
    for (const std::int32_t extra : {0, 1, 15, 16, 30}) {
      const std::uint64_t seed = (static_cast<std::uint64_t>(tw) * 100U) + static_cast<std::uint64_t>(extra);
      const std::int32_t th = 1 + tw % 7 + extra % 5;
      Image win = vision_test::random_image(tw + extra, th + 6, seed);
      for (std::int32_t y = 0; y < th + 2 && y < win.h; ++y)
        for (std::int32_t x = 0; x < tw + 1 && x < win.w; ++x) win.at(x, y) = 77U;  // flat windows at the top left
      Image t = vision_test::random_image(tw, th, seed + 7U);
      t.at(0, 0) = 0U;
      t.at(tw - 1, th - 1) = 255U;  // the extremes, and never flat
      const SurfaceRun bytes = surface_run(t, win, {});
      std::fill(scratch.begin(), scratch.end(), std::int16_t{-7});
      const std::int32_t cols = (tw + 7) / 8 * 8;
      const std::int64_t need = std::int64_t{th} * cols + std::int64_t{win.h} * (win.w - tw + cols);
      const bool fits = tw <= tv::kNccWideMaxTemplatePx;
      const SurfaceRun wide = surface_run(t, win, {scratch.data(), need});
      const bool written = std::any_of(scratch.begin(), scratch.end(), [](std::int16_t v) { return v != -7; });
      EXPECT_EQ(written, fits) << "template width " << tw;
      EXPECT_EQ(std::memcmp(wide.surface.data(), bytes.surface.data(), bytes.surface.size() * sizeof(float)), 0)
          << "template " << tw << "x" << th << ", window " << win.w << "x" << win.h;
      EXPECT_EQ(wide.flags, bytes.flags) << "template width " << tw;
      EXPECT_EQ(wide.flat, bytes.flat);
      EXPECT_GT(wide.flat, 0) << "template width " << tw << ": the flat windows are taken";
      EXPECT_EQ(wide.check.dot_sum, bytes.check.dot_sum) << "template width " << tw;
      EXPECT_EQ(wide.check.surface_sum, bytes.check.surface_sum);
      EXPECT_EQ(wide.work.int_macs, bytes.work.int_macs);
      EXPECT_EQ(wide.work.int_ops, bytes.work.int_ops);
      EXPECT_EQ(wide.work.mem_words, bytes.work.mem_words);
      // One entry short: the byte path, the scratch untouched.
      std::fill(scratch.begin(), scratch.end(), std::int16_t{-7});
      const SurfaceRun short_of = surface_run(t, win, {scratch.data(), need - 1});
      EXPECT_TRUE(std::all_of(scratch.begin(), scratch.end(), [](std::int16_t v) { return v == -7; }));
      EXPECT_EQ(std::memcmp(short_of.surface.data(), bytes.surface.data(), bytes.surface.size() * sizeof(float)), 0);
      ++cases;
    }
  }
  EXPECT_EQ(cases, 60);
}

// The fine stage's workspace gives correlate() the 16-bit copies, with the same match as without.
TEST(Ncc, TheFineWorkspaceCorrelatesFromSixteenBitCopiesWithTheSameMatch) {
  static tv::FineWorkspace fine;
  static tv::CorrelatorWorkspace<tv::kFineMaxWindowPx> plain;
  EXPECT_NE(fine.buffers().wide.data, nullptr);
  EXPECT_GE(fine.buffers().wide.entries, tv::ncc_wide_entries(tv::kFineMaxWindowPx));
  EXPECT_EQ(plain.buffers().wide.data, nullptr);
  const Image win = vision_test::smooth_texture(tv::kFineMaxWindowPx, tv::kFineMaxWindowPx, 2, 61);
  Image t(tv::kFineTemplatePx, tv::kFineTemplatePx);
  for (std::int32_t y = 0; y < t.h; ++y)
    for (std::int32_t x = 0; x < t.w; ++x) t.at(x, y) = win.at(x + 23, y + 31);
  fine.wide.fill(std::int16_t{-7});
  tv::MatchResult a;
  tv::MatchResult b;
  bsp::Work wa;
  bsp::Work wb;
  ASSERT_EQ(tv::correlate(t.view(), win.view(), tv::kFineQuality, fine.buffers(), a, wa), tv::Status::kOk);
  ASSERT_EQ(tv::correlate(t.view(), win.view(), tv::kFineQuality, plain.buffers(), b, wb), tv::Status::kOk);
  EXPECT_NE(fine.wide[0], std::int16_t{-7});
  EXPECT_EQ(a.peak.ix, 23);
  EXPECT_EQ(a.peak.iy, 31);
  EXPECT_EQ(a.peak.ix, b.peak.ix);
  EXPECT_EQ(a.peak.iy, b.peak.iy);
  EXPECT_EQ(std::bit_cast<std::uint64_t>(a.x_px), std::bit_cast<std::uint64_t>(b.x_px));
  EXPECT_EQ(std::bit_cast<std::uint64_t>(a.y_px), std::bit_cast<std::uint64_t>(b.y_px));
  EXPECT_EQ(wa.int_macs, wb.int_macs);
}

TEST(Ncc, CorrelateMakesNoHeapAllocation) {
  const Image win = vision_test::random_image(49, 49, 7);
  const Image t = vision_test::random_image(21, 21, 8);
  static tv::CorrelatorWorkspace<64> ws;
  tv::MatchResult r;
  bsp::Work work;
  tv::Status st = tv::Status::kBadInput;
  const std::uint64_t allocs = test_support::count_allocs(
      [&] { st = tv::correlate(t.view(), win.view(), {}, ws.buffers(), r, work); });
  EXPECT_EQ(st, tv::Status::kOk);
  EXPECT_EQ(allocs, 0U);
}

}  // namespace
