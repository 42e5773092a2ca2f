/**
 * @file ntt_test.cpp
 * @brief The exact integer transform (ntt.hpp): it is the DFT over Z_p in the stated order, it
 *        inverts exactly at every size, and it convolves exactly; its work is the stated count.
 */
#include "trn/vision/ntt.hpp"

#include "bsp_tile64/emu/rng.hpp"

#include <gtest/gtest.h>

#include <cstdint>
#include <vector>

namespace {

namespace tv = trn::vision;
constexpr std::uint64_t kP = tv::kNttModulus;

std::uint32_t mul(std::uint64_t a, std::uint64_t b) { return static_cast<std::uint32_t>(a * b % kP); }

std::uint32_t pow_mod(std::uint64_t b, std::uint64_t e) {
  std::uint64_t r = 1;
  for (; e != 0; e >>= 1U, b = b * b % kP)
    if ((e & 1U) != 0) r = r * b % kP;
  return static_cast<std::uint32_t>(r);
}

/** The primitive 2^k-th root the transform uses: 31^((p-1)/2^k). */
std::uint32_t root(std::int32_t log2_n) { return pow_mod(31, (kP - 1) >> static_cast<std::uint32_t>(log2_n)); }

std::uint32_t bit_reverse(std::uint32_t k, std::int32_t bits) {
  std::uint32_t r = 0;
  for (std::int32_t b = 0; b < bits; ++b) r |= ((k >> static_cast<std::uint32_t>(b)) & 1U) << static_cast<std::uint32_t>(bits - 1 - b);
  return r;
}

struct Plane {
  std::int32_t lw, lh;
  std::vector<std::uint32_t> v;
  Plane(std::int32_t log2_w, std::int32_t log2_h) : lw(log2_w), lh(log2_h), v(std::size_t{1} << static_cast<std::uint32_t>(lw + lh)) {}
  std::int32_t w() const { return 1 << lw; }
  std::int32_t h() const { return 1 << lh; }
  std::uint32_t& at(std::int32_t x, std::int32_t y) { return v[static_cast<std::size_t>(y * w() + x)]; }
  tv::NttPlane plane() { return tv::NttPlane{v.data(), lw, lh}; }
};

/** Residues uniform in [0, p), with a few p - 1 and 0 (the extremes of the arithmetic). */
Plane random_plane(std::int32_t lw, std::int32_t lh, std::uint64_t seed) {
  bsp::Rng rng(seed, bsp::StreamId::kTest, 31);
  Plane p(lw, lh);
  for (auto& x : p.v) {
    const std::uint64_t r = rng.below(1000);
    x = r == 0 ? static_cast<std::uint32_t>(kP - 1) : (r == 1 ? 0U : static_cast<std::uint32_t>(rng.below(kP)));
  }
  return p;
}

// The forward transform is the 2-D DFT over Z_p with the stated root, both axes in bit-reversed order.
TEST(Ntt, ForwardIsTheDftInBitReversedOrder) {
  for (const auto& [lw, lh] : {std::pair{3, 2}, std::pair{0, 4}, std::pair{5, 0}, std::pair{4, 4}, std::pair{6, 3}}) {
    Plane x = random_plane(lw, lh, 11U + static_cast<std::uint64_t>(lw * 10 + lh));
    Plane y = x;
    bsp::Work work;
    ASSERT_EQ(tv::ntt_forward(y.plane(), y.h(), work), tv::Status::kOk);
    const std::uint32_t wx = root(lw);
    const std::uint32_t wy = root(lh);
    for (std::int32_t k2 = 0; k2 < x.h(); ++k2)
      for (std::int32_t k1 = 0; k1 < x.w(); ++k1) {
        std::uint64_t sum = 0;
        for (std::int32_t n2 = 0; n2 < x.h(); ++n2)
          for (std::int32_t n1 = 0; n1 < x.w(); ++n1) {
            const std::uint32_t tw = mul(pow_mod(wx, static_cast<std::uint64_t>(n1 * k1)), pow_mod(wy, static_cast<std::uint64_t>(n2 * k2)));
            sum = (sum + mul(x.at(n1, n2), tw)) % kP;
          }
        const auto bx = static_cast<std::int32_t>(bit_reverse(static_cast<std::uint32_t>(k1), lw));
        const auto by = static_cast<std::int32_t>(bit_reverse(static_cast<std::uint32_t>(k2), lh));
        ASSERT_EQ(y.at(bx, by), sum) << lw << "x" << lh << " bin " << k1 << "," << k2;
      }
  }
}

// Forward then inverse gives 2^(lw + lh) times the input, exactly, at every plane size up to 256 x 256.
TEST(Ntt, RoundTripIsExactAtEverySize) {
  for (std::int32_t lw = 0; lw <= tv::kNttMaxLog2; ++lw)
    for (std::int32_t lh = 0; lh <= tv::kNttMaxLog2; ++lh) {
      const std::uint64_t seed = 100U + static_cast<std::uint64_t>(lw * 16 + lh);
      const Plane x = random_plane(lw, lh, seed);
      Plane y = x;
      bsp::Work work;
      ASSERT_EQ(tv::ntt_forward(y.plane(), y.h(), work), tv::Status::kOk);
      if (x.v.size() >= 4) {
        EXPECT_NE(y.v, x.v) << "the transform must change the plane";
      }
      ASSERT_EQ(tv::ntt_inverse(y.plane(), 0, y.h(), work), tv::Status::kOk);
      const std::uint64_t scale = std::uint64_t{1} << static_cast<std::uint32_t>(lw + lh);
      std::size_t wrong = 0;
      for (std::size_t i = 0; i < x.v.size(); ++i) wrong += y.v[i] != mul(x.v[i], scale) ? 1U : 0U;
      EXPECT_EQ(wrong, 0U) << lw << " x " << lh << " seed " << seed;
    }
}

// Skipping the row transforms of zero rows changes nothing; an inverse of some rows gives those rows.
TEST(Ntt, SkippedRowsGiveTheFullResult) {
  Plane x = random_plane(5, 6, 7);
  for (std::int32_t y = 20; y < x.h(); ++y)
    for (std::int32_t c = 0; c < x.w(); ++c) x.at(c, y) = 0;
  Plane full = x;
  Plane part = x;
  bsp::Work work;
  ASSERT_EQ(tv::ntt_forward(full.plane(), full.h(), work), tv::Status::kOk);
  ASSERT_EQ(tv::ntt_forward(part.plane(), 20, work), tv::Status::kOk);
  EXPECT_EQ(part.v, full.v);
  ASSERT_EQ(tv::ntt_inverse(full.plane(), 0, full.h(), work), tv::Status::kOk);
  ASSERT_EQ(tv::ntt_inverse(part.plane(), 9, 30, work), tv::Status::kOk);
  for (std::int32_t y = 9; y < 39; ++y)
    for (std::int32_t c = 0; c < x.w(); ++c) ASSERT_EQ(part.at(c, y), full.at(c, y)) << c << "," << y;
}

// Scale one operand, transform both, multiply, invert: the exact cyclic convolution (naive reference).
TEST(Ntt, MultiplyAndInverseGiveTheExactCyclicConvolution) {
  for (const auto& [lw, lh] : {std::pair{3, 3}, std::pair{4, 2}, std::pair{0, 5}, std::pair{6, 5}}) {
    const Plane a = random_plane(lw, lh, 40U + static_cast<std::uint64_t>(lw));
    const Plane b = random_plane(lw, lh, 50U + static_cast<std::uint64_t>(lh));
    Plane fa = a;
    Plane fb = b;
    const std::uint32_t c = tv::ntt_convolution_scale(lw, lh);
    for (auto& v : fb.v) v = mul(v, c);
    bsp::Work work;
    ASSERT_EQ(tv::ntt_forward(fa.plane(), fa.h(), work), tv::Status::kOk);
    ASSERT_EQ(tv::ntt_forward(fb.plane(), fb.h(), work), tv::Status::kOk);
    ASSERT_EQ(tv::ntt_multiply(fa.plane(), fb.plane(), work), tv::Status::kOk);
    ASSERT_EQ(tv::ntt_inverse(fa.plane(), 0, fa.h(), work), tv::Status::kOk);
    const std::int32_t w = a.w();
    const std::int32_t h = a.h();
    for (std::int32_t y = 0; y < h; ++y)
      for (std::int32_t x = 0; x < w; ++x) {
        std::uint64_t s = 0;
        for (std::int32_t v = 0; v < h; ++v)
          for (std::int32_t u = 0; u < w; ++u)
            s = (s + mul(a.v[static_cast<std::size_t>(v * w + u)],
                         b.v[static_cast<std::size_t>(((y - v + h) % h) * w + (x - u + w) % w)])) % kP;
        ASSERT_EQ(fa.at(x, y), s) << lw << "x" << lh << " at " << x << "," << y;
      }
  }
}

TEST(Ntt, ConvolutionScaleIsTwoToTheThirtyTwoOverThePlaneSize) {
  for (std::int32_t s = 0; s <= 2 * tv::kNttMaxLog2; ++s) {
    const std::uint32_t c = tv::ntt_convolution_scale(s / 2, s - s / 2);
    EXPECT_EQ(mul(c, std::uint64_t{1} << static_cast<std::uint32_t>(s)), (std::uint64_t{1} << 32U) % kP) << s;
  }
  EXPECT_EQ(tv::ntt_convolution_scale(tv::kNttMaxLog2 + 1, 0), 0U);
  EXPECT_EQ(tv::ntt_convolution_scale(0, -1), 0U);
}

TEST(Ntt, BadPlanesAndRowRangesAreRefused) {
  Plane x(3, 3);
  bsp::Work work;
  EXPECT_EQ(tv::ntt_forward(tv::NttPlane{}, 0, work), tv::Status::kBadInput);
  EXPECT_EQ(tv::ntt_forward(tv::NttPlane{x.v.data(), tv::kNttMaxLog2 + 1, 0}, 0, work), tv::Status::kBadInput);
  EXPECT_EQ(tv::ntt_forward(x.plane(), 9, work), tv::Status::kBadInput);
  EXPECT_EQ(tv::ntt_forward(x.plane(), -1, work), tv::Status::kBadInput);
  EXPECT_EQ(tv::ntt_inverse(x.plane(), 4, 5, work), tv::Status::kBadInput);
  EXPECT_EQ(tv::ntt_inverse(x.plane(), -1, 2, work), tv::Status::kBadInput);
  Plane y(3, 2);
  EXPECT_EQ(tv::ntt_multiply(x.plane(), y.plane(), work), tv::Status::kBadInput);
  EXPECT_EQ(work.int_macs, 0U) << "nothing refused is charged";
}

// The count: a 256 x 256 forward transform is 2 x 256 x 128 x 8 butterflies of 7 MACs and 22 ops,
// 4 data words each, and 2 twiddle words per row butterfly and per row pair of a 16-column block.
TEST(Ntt, WorkIsTheStatedCount) {
  Plane x(8, 8);
  bsp::Work work;
  ASSERT_EQ(tv::ntt_forward(x.plane(), 256, work), tv::Status::kOk);
  const std::uint64_t bfly = 2U * 256U * 128U * 8U;
  EXPECT_EQ(work.int_macs, 7U * bfly);
  EXPECT_EQ(work.int_ops, 22U * bfly);
  EXPECT_EQ(work.mem_words, 4U * bfly + 2U * (bfly / 2U) + 2U * (256U / 16U) * 128U * 8U);
  EXPECT_EQ(work.flops, 0U);
  bsp::Work inv;
  ASSERT_EQ(tv::ntt_inverse(x.plane(), 10, 100, inv), tv::Status::kOk);
  EXPECT_EQ(inv.int_macs, 7U * (256U * 128U * 8U + 100U * 128U * 8U));
  bsp::Work m;
  ASSERT_EQ(tv::ntt_multiply(x.plane(), x.plane(), m), tv::Status::kOk);
  EXPECT_EQ(m.int_macs, 4U * 65536U);
  EXPECT_EQ(m.int_ops, 27U * 65536U);
}

}  // namespace
