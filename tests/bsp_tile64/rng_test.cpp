/**
 * @file rng_test.cpp
 * @brief Random streams are reproducible, independent, and have the right moments.
 */
#include "bsp_tile64/emu/rng.hpp"

#include <gtest/gtest.h>

#include <array>

#include <cmath>
#include <cstdint>

namespace {

TEST(Rng, SameSeedStreamAndIndexGiveTheSameSequence) {
  bsp::Rng a(42, bsp::StreamId::kWorld, 3);
  bsp::Rng b(42, bsp::StreamId::kWorld, 3);
  for (int i = 0; i < 1000; ++i) {
    ASSERT_EQ(a.next(), b.next()) << "draw " << i;
  }
}

TEST(Rng, SeedFamilyAndIndexEachChangeTheSequence) {
  const std::uint64_t base = bsp::Rng(42, bsp::StreamId::kWorld, 3).next();
  EXPECT_NE(bsp::Rng(43, bsp::StreamId::kWorld, 3).next(), base);
  EXPECT_NE(bsp::Rng(42, bsp::StreamId::kFaults, 3).next(), base);
  EXPECT_NE(bsp::Rng(42, bsp::StreamId::kWorld, 4).next(), base);
}

TEST(Rng, KnownFirstValuesPinTheGeneratorAcrossBuilds) {
  // Pinned: a change here changes every recorded trace hash.
  bsp::Rng r(1, bsp::StreamId::kTest, 0);
  const std::uint64_t first = r.next();
  bsp::Rng again(1, bsp::StreamId::kTest, 0);
  EXPECT_EQ(again.next(), first);
  // The values this generator gave when the traces were recorded (a literal: computed here, they would
  // follow any change of the generator and pin nothing).
  constexpr std::array<std::uint64_t, 3> kPinned = {7127489281347344175ULL, 13974364321708032109ULL,
                                                       18053453593942019107ULL};
  EXPECT_EQ(first, kPinned[0]);
  EXPECT_EQ(r.next(), kPinned[1]);
  EXPECT_EQ(r.next(), kPinned[2]);
}

TEST(Rng, UniformAndBelowStayInRangeWithTheRightMean) {
  bsp::Rng r(7, bsp::StreamId::kTest);
  double sum = 0.0;
  constexpr int kN = 200000;
  std::uint64_t counts[6] = {};
  for (int i = 0; i < kN; ++i) {
    const double u = r.uniform();
    ASSERT_GE(u, 0.0);
    ASSERT_LT(u, 1.0);
    sum += u;
    const std::uint64_t k = r.below(6);
    ASSERT_LT(k, 6U);
    ++counts[k];
  }
  EXPECT_NEAR(sum / kN, 0.5, 0.005);
  for (const std::uint64_t c : counts) {
    EXPECT_NEAR(static_cast<double>(c) / kN, 1.0 / 6.0, 0.005);
  }
}

TEST(Rng, NormalHasZeroMeanUnitVarianceAndGaussianTails) {
  bsp::Rng r(11, bsp::StreamId::kTest);
  constexpr int kN = 400000;
  double s1 = 0.0;
  double s2 = 0.0;
  int beyond2 = 0;
  for (int i = 0; i < kN; ++i) {
    const double x = r.normal();
    s1 += x;
    s2 += x * x;
    beyond2 += (std::fabs(x) > 2.0) ? 1 : 0;
  }
  const double mean = s1 / kN;
  EXPECT_NEAR(mean, 0.0, 0.01);
  EXPECT_NEAR(s2 / kN - mean * mean, 1.0, 0.01);
  EXPECT_NEAR(static_cast<double>(beyond2) / kN, 0.0455, 0.002);  // P(|x|>2) of a normal
}

}  // namespace
