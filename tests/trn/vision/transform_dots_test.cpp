/**
 * @file transform_dots_test.cpp
 * @brief Dot products by the transform (transform_dots.hpp) equal the integer dot products at every
 *        offset, for templates of 1..128 px, windows up to 256 px, any sizes, and at the exactness bound;
 *        the NCC surface from them is the spatial one bit for bit.
 */
#include "trn/vision/transform_dots.hpp"

#include "bsp_tile64/emu/cost_model.hpp"
#include "bsp_tile64/emu/profile.hpp"
#include "trn/vision/integral.hpp"
#include "trn/vision/ncc.hpp"

#include "tests/trn/vision/synth.hpp"

#include <gtest/gtest.h>

#include <bit>
#include <cstdint>
#include <cstdio>
#include <vector>

namespace {

namespace tv = trn::vision;
using vision_test::Image;

tv::TransformWorkspace<256>& workspace() {
  static tv::TransformWorkspace<256> ws;
  return ws;
}

/** The integer dot product at offset (x, y), directly. */
std::uint32_t naive_dot(const Image& t, const Image& w, std::int32_t x, std::int32_t y) {
  std::uint32_t s = 0;
  for (std::int32_t j = 0; j < t.h; ++j)
    for (std::int32_t i = 0; i < t.w; ++i) s += std::uint32_t{t.at(i, j)} * w.at(x + i, y + j);
  return s;
}

/** Compares every dot product by the transform with the direct one; returns the number of mismatches. */
std::int64_t mismatches(const Image& t, const Image& w, bsp::Work& work) {
  tv::ImageView<const std::uint32_t> dots;
  EXPECT_EQ(tv::transform_dots(t.view(), w.view(), workspace().buffers(), dots, work), tv::Status::kOk);
  EXPECT_EQ(dots.width, w.w - t.w + 1);
  EXPECT_EQ(dots.height, w.h - t.h + 1);
  std::int64_t bad = 0;
  for (std::int32_t y = 0; y < dots.height; ++y)
    for (std::int32_t x = 0; x < dots.width; ++x) bad += dots.at(x, y) != naive_dot(t, w, x, y) ? 1 : 0;
  return bad;
}

// Templates 1..128 px (square, flat, tall, wide, odd and power-of-two sides) over windows of any size up
// to 256 px, random bytes: every dot product equals the direct one.
TEST(TransformDots, EveryDotProductEqualsTheDirectOneForRandomInputsAndEdgeSizes) {
  struct Size {
    std::int32_t tw, th, ww, wh;
  };
  const Size sizes[] = {
      {1, 1, 1, 1},     {1, 1, 7, 3},     {2, 2, 2, 2},      {3, 5, 17, 9},     {5, 3, 16, 16},
      {7, 7, 33, 31},   {8, 8, 64, 64},   {9, 9, 65, 65},    {15, 16, 100, 47}, {16, 16, 128, 128},
      {17, 17, 129, 18}, {21, 21, 49, 49}, {31, 1, 200, 5},  {1, 40, 3, 256},   {32, 32, 33, 256},
      {33, 33, 256, 40}, {63, 63, 90, 90}, {64, 64, 256, 256}, {65, 65, 255, 97}, {100, 77, 131, 140},
      {127, 127, 150, 129}, {128, 128, 140, 256}, {128, 1, 256, 20}, {1, 128, 10, 256}, {128, 128, 128, 128},
  };
  std::uint64_t seed = 500;
  for (const Size& s : sizes) {
    ++seed;
    const Image t = vision_test::random_image(s.tw, s.th, seed);
    const Image w = vision_test::random_image(s.ww, s.wh, seed + 1000U);
    bsp::Work work;
    EXPECT_EQ(mismatches(t, w, work), 0) << "template " << s.tw << "x" << s.th << " window " << s.ww << "x" << s.wh
                                         << " seed " << seed;
    EXPECT_GT(work.int_macs, 0U);
  }
}

// Every template side 1..128 once, square, over a window a random 0..40 px larger (at most 256).
TEST(TransformDots, EveryTemplateSideUpTo128IsExact) {
  bsp::Rng rng(77, bsp::StreamId::kTest, 5);
  for (std::int32_t side = 1; side <= 128; ++side) {
    const auto ww = static_cast<std::int32_t>(side + static_cast<std::int32_t>(rng.below(41)));
    const auto wh = static_cast<std::int32_t>(side + static_cast<std::int32_t>(rng.below(41)));
    const Image t = vision_test::random_image(side, side, 900U + static_cast<std::uint64_t>(side));
    const Image w = vision_test::random_image(ww, wh, 1900U + static_cast<std::uint64_t>(side));
    bsp::Work work;
    ASSERT_EQ(mismatches(t, w, work), 0) << "side " << side << " window " << ww << "x" << wh << " (seed 77)";
  }
}

// The largest dot product there can be (128 x 128 at 255 over 255) is returned exactly: 255^2 * 16384 < p.
TEST(TransformDots, TheLargestDotProductIsExact) {
  const Image t(128, 128, 255);
  const Image w(200, 256, 255);
  tv::ImageView<const std::uint32_t> dots;
  bsp::Work work;
  ASSERT_EQ(tv::transform_dots(t.view(), w.view(), workspace().buffers(), dots, work), tv::Status::kOk);
  const std::uint32_t top = 65025U * 16384U;
  for (std::int32_t y = 0; y < dots.height; ++y)
    for (std::int32_t x = 0; x < dots.width; ++x) ASSERT_EQ(dots.at(x, y), top) << x << "," << y;
}

// The coarse case: a 64 x 64 template over a 256 x 256 window. The dot products are the spatial
// ones, and the NCC surface made from them (with its check sums) is the spatial surface bit for bit.
TEST(TransformDots, TheCoarseSurfaceFromTransformDotsIsTheSpatialOneBitForBit) {
  Image w = vision_test::smooth_texture(256, 256, 2, 31U);
  for (std::int32_t y = 100; y < 180; ++y)
    for (std::int32_t x = 0; x < 70; ++x) w.at(x, y) = 90U;  // flat windows too
  Image t(64, 64);
  for (std::int32_t y = 0; y < 64; ++y)
    for (std::int32_t x = 0; x < 64; ++x) t.at(x, y) = w.at(120 + x, 60 + y);
  static tv::FixedIntegral<256, 256> ii;
  bsp::Work work;
  ASSERT_EQ(ii.build(w.view(), work), tv::Status::kOk);
  tv::TemplateStats st;
  ASSERT_EQ(tv::template_stats(t.view(), st, work), tv::Status::kOk);
  constexpr std::int32_t kS = 193;
  std::vector<float> spatial(kS * kS);
  std::vector<float> transform(kS * kS, -7.0F);
  std::vector<std::uint8_t> flags_s(kS * kS);
  std::vector<std::uint8_t> flags_t(kS * kS, 9U);
  std::int32_t flat_s = 0;
  std::int32_t flat_t = 0;
  tv::NccCheck cs;
  tv::NccCheck ct;
  ASSERT_EQ(tv::ncc_surface(t.view(), st, w.view(), ii.ref(), {spatial.data(), kS, kS, kS},
                            {flags_s.data(), kS, kS, kS}, flat_s, work, &cs),
            tv::Status::kOk);
  tv::ImageView<const std::uint32_t> dots;
  bsp::Work tw;
  ASSERT_EQ(tv::transform_dots(t.view(), w.view(), workspace().buffers(), dots, tw), tv::Status::kOk);
  ASSERT_EQ(tv::ncc_surface_from_dots(st, ii.ref(), dots, {transform.data(), kS, kS, kS},
                                      {flags_t.data(), kS, kS, kS}, flat_t, tw, &ct),
            tv::Status::kOk);
  EXPECT_GT(flat_s, 0);
  EXPECT_EQ(flat_t, flat_s);
  EXPECT_EQ(ct.dot_sum, cs.dot_sum);
  EXPECT_EQ(ct.surface_sum, cs.surface_sum);
  EXPECT_EQ(flags_t, flags_s);
  std::int64_t differ = 0;
  for (std::size_t i = 0; i < spatial.size(); ++i)
    differ += std::bit_cast<std::uint32_t>(spatial[i]) != std::bit_cast<std::uint32_t>(transform[i]) ? 1 : 0;
  EXPECT_EQ(differ, 0);
  EXPECT_EQ(ct.dot_sum, tv::ncc_dot_checksum(t.view(), ii.ref(), kS, kS, work));
}

// The work counted is transform_dots_work(), and on the TILE64 it is a fraction of the spatial dot products'.
TEST(TransformDots, WorkIsTheStatedCountAndAFractionOfTheSpatialOne) {
  const Image t = vision_test::random_image(64, 64, 3);
  const Image w = vision_test::random_image(256, 256, 4);
  tv::ImageView<const std::uint32_t> dots;
  bsp::Work work;
  ASSERT_EQ(tv::transform_dots(t.view(), w.view(), workspace().buffers(), dots, work), tv::Status::kOk);
  const bsp::Work stated = tv::transform_dots_work(64, 64, 256, 256);
  EXPECT_EQ(work.int_macs, stated.int_macs);
  EXPECT_EQ(work.int_ops, stated.int_ops);
  EXPECT_EQ(work.mem_words, stated.mem_words);
  EXPECT_EQ(work.flops, 0U);
  EXPECT_EQ(work.fdivs, 0U);
  // The spatial dot products alone: ncc_surface_work less the scores.
  bsp::Work spatial = tv::ncc_surface_work(64, 64, 193, 193);
  const bsp::Work scores = tv::ncc_score_work(193, 193);
  spatial.int_macs -= scores.int_macs;
  spatial.int_ops -= scores.int_ops;
  spatial.mem_words -= scores.mem_words;
  spatial.flops = 0U;
  spatial.fdivs = 0U;
  const auto c_transform = static_cast<double>(bsp::cost_of(bsp::kTile64, work));
  const auto c_spatial = static_cast<double>(bsp::cost_of(bsp::kTile64, spatial));
  std::printf("[ dots 64 on 256 ] TILE64 cycles: transform %.1f M, spatial %.1f M (%.1fx)\n", c_transform / 1e6,
              c_spatial / 1e6, c_spatial / c_transform);
  EXPECT_LT(c_transform, c_spatial / 5.0);
}

TEST(TransformDots, BadInputsAndTooLargeSizesAreRefused) {
  const Image t = vision_test::random_image(8, 8, 1);
  const Image w = vision_test::random_image(32, 32, 2);
  const Image big(257, 20, 1);
  const Image tall(20, 300, 1);
  tv::ImageView<const std::uint32_t> dots;
  bsp::Work work;
  tv::TransformBuffers buf = workspace().buffers();
  EXPECT_EQ(tv::transform_dots(w.view(), t.view(), buf, dots, work), tv::Status::kBadInput);
  EXPECT_EQ(tv::transform_dots(tv::ConstImageU8{}, w.view(), buf, dots, work), tv::Status::kBadInput);
  EXPECT_EQ(tv::transform_dots(t.view(), big.view(), buf, dots, work), tv::Status::kTooLarge);
  EXPECT_EQ(tv::transform_dots(t.view(), tall.view(), buf, dots, work), tv::Status::kTooLarge);
  static tv::TransformWorkspace<16> small;
  EXPECT_EQ(tv::transform_dots(t.view(), w.view(), small.buffers(), dots, work), tv::Status::kTooLarge);
  buf.scaled = nullptr;
  EXPECT_EQ(tv::transform_dots(t.view(), w.view(), buf, dots, work), tv::Status::kBadInput);
  EXPECT_FALSE(dots.valid());
  EXPECT_EQ(work.int_macs, 0U);
}

}  // namespace
