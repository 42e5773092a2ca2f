/**
 * @file ecc_test.cpp
 * @brief SECDED codes: Hsiao columns, agreement with a naive bit-by-bit encoder,
 *        every single error corrected and every double error detected.
 */
#include "udn/ecc.hpp"

#include "bsp_tile64/emu/rng.hpp"

#include <gtest/gtest.h>

#include <bit>
#include <cstdint>
#include <set>
#include <vector>

namespace {

constexpr std::uint64_t kSeed = 0xECC5EC0DEDULL;

/** The p-th column of an R-bit Hsiao code, found by plain enumeration (reference). */
std::vector<std::uint32_t> reference_columns(unsigned r, std::size_t count) {
  std::vector<std::uint32_t> cols;
  for (int weight = 3; weight <= static_cast<int>(r); weight += 2) {
    for (std::uint32_t v = 0; v < (1U << r); ++v) {
      if (std::popcount(v) == weight && cols.size() < count) {
        cols.push_back(v);
      }
    }
  }
  return cols;
}

/** Naive encoder: XOR the column of every set bit, one bit at a time. */
std::uint32_t naive_encode(const std::vector<std::uint32_t>& cols, const std::vector<std::uint32_t>& words) {
  std::uint32_t check = 0;
  for (std::size_t w = 0; w < words.size(); ++w) {
    for (unsigned b = 0; b < 32; ++b) {
      if (((words[w] >> b) & 1U) != 0U) {
        check ^= cols[w * 32 + b];
      }
    }
  }
  return check;
}

std::vector<std::uint32_t> random_words(bsp::Rng& rng, std::size_t n) {
  std::vector<std::uint32_t> v(n);
  for (auto& w : v) {
    w = static_cast<std::uint32_t>(rng.next());
  }
  return v;
}

template <typename Code>
void expect_columns_are_hsiao() {
  std::set<std::uint32_t> seen;
  for (std::size_t w = 0; w < Code::kWords; ++w) {
    for (unsigned b = 0; b < 32; ++b) {
      const std::uint32_t c = Code::column(w, b);
      ASSERT_EQ(std::popcount(c) % 2, 1) << "word " << w << " bit " << b;
      ASSERT_GE(std::popcount(c), 3) << "word " << w << " bit " << b;
      ASSERT_TRUE(seen.insert(c).second) << "duplicate column at word " << w << " bit " << b;
    }
  }
}

TEST(Secded, ColumnsAreDistinctOddWeightAtLeastThree) {
  expect_columns_are_hsiao<udn::DataCode>();
  expect_columns_are_hsiao<udn::RouteCode>();
}

template <typename Code>
void expect_fast_equals_naive(std::uint64_t seed) {
  const auto cols = reference_columns(Code::kR, Code::kWords * 32);
  bsp::Rng rng(seed, bsp::StreamId::kTest, Code::kR);
  for (std::size_t n = 0; n <= Code::kWords; ++n) {
    for (int rep = 0; rep < 4; ++rep) {
      const auto words = random_words(rng, n);
      ASSERT_EQ(Code::encode(words), naive_encode(cols, words)) << "n " << n << " seed " << seed;
    }
  }
}

TEST(Secded, TableDrivenEncoderAgreesWithNaiveBitByBitReference) {
  expect_fast_equals_naive<udn::DataCode>(kSeed);
  expect_fast_equals_naive<udn::RouteCode>(kSeed);
}

/** Flips one bit of the code word (data bits 0..32n-1, then check bits). */
void flip(std::vector<std::uint32_t>& words, std::uint32_t& check, std::size_t pos) {
  const std::size_t data_bits = words.size() * 32;
  if (pos < data_bits) {
    words[pos / 32] ^= 1U << (pos % 32);
  } else {
    check ^= 1U << (pos - data_bits);
  }
}

template <typename Code>
void expect_every_single_error_located(std::size_t n) {
  bsp::Rng rng(kSeed, bsp::StreamId::kTest, n);
  const auto original = random_words(rng, n);
  const std::uint32_t check = Code::encode(original);
  ASSERT_EQ(Code::check(original, check).status, udn::EccStatus::kClean);
  for (std::size_t pos = 0; pos < n * 32 + Code::kR; ++pos) {
    auto words = original;
    std::uint32_t c = check;
    flip(words, c, pos);
    const udn::EccCheck r = Code::check(words, c);
    if (pos < n * 32) {
      ASSERT_EQ(r.status, udn::EccStatus::kCorrectedData) << "n " << n << " pos " << pos;
      ASSERT_EQ(r.word * 32U + r.bit, pos);
    } else {
      ASSERT_EQ(r.status, udn::EccStatus::kCorrectedCheck) << "n " << n << " pos " << pos;
      ASSERT_EQ(r.bit, pos - n * 32);
    }
  }
}

TEST(Secded, EverySingleBitErrorIsLocatedExactly) {
  for (const std::size_t n : {1U, 2U, 62U, 124U, 125U}) {
    expect_every_single_error_located<udn::DataCode>(n);
  }
  for (std::size_t n = 1; n <= udn::RouteCode::kWords; ++n) {
    expect_every_single_error_located<udn::RouteCode>(n);
  }
}

template <typename Code>
void expect_every_double_error_detected(std::size_t n) {
  bsp::Rng rng(kSeed, bsp::StreamId::kTest, 1000 + n);
  const auto original = random_words(rng, n);
  const std::uint32_t check = Code::encode(original);
  const std::size_t bits = n * 32 + Code::kR;
  for (std::size_t a = 0; a < bits; ++a) {
    for (std::size_t b = a + 1; b < bits; ++b) {
      auto words = original;
      std::uint32_t c = check;
      flip(words, c, a);
      flip(words, c, b);
      ASSERT_EQ(Code::check(words, c).status, udn::EccStatus::kUncorrectable) << "n " << n << " bits " << a
                                                                              << "," << b;
    }
  }
}

TEST(Secded, EveryDoubleBitErrorIsDetectedInShortWords) {
  expect_every_double_error_detected<udn::DataCode>(1);
  expect_every_double_error_detected<udn::DataCode>(2);
  expect_every_double_error_detected<udn::DataCode>(3);
  expect_every_double_error_detected<udn::RouteCode>(4);
}

TEST(Secded, RandomDoubleBitErrorsAreDetectedInLongWords) {
  const std::uint64_t seed = kSeed + 7;
  bsp::Rng rng(seed, bsp::StreamId::kTest, 0);
  for (const std::size_t n : {62U, 124U, 125U}) {
    const auto original = random_words(rng, n);
    const std::uint32_t check = udn::DataCode::encode(original);
    const std::size_t bits = n * 32 + udn::DataCode::kR;
    for (int i = 0; i < 20000; ++i) {
      const std::size_t a = rng.below(bits);
      const std::size_t b = (a + 1 + rng.below(bits - 1)) % bits;
      auto words = original;
      std::uint32_t c = check;
      flip(words, c, a);
      flip(words, c, b);
      ASSERT_EQ(udn::DataCode::check(words, c).status, udn::EccStatus::kUncorrectable)
          << "seed " << seed << " n " << n << " bits " << a << "," << b;
    }
  }
}

TEST(Secded, OversizedInputIsRejectedNotRead) {
  const std::vector<std::uint32_t> words(udn::RouteCode::kWords + 1, 0U);
  EXPECT_EQ(udn::RouteCode::check(words, 0U).status, udn::EccStatus::kUncorrectable);
  EXPECT_EQ(udn::RouteCode::column(udn::RouteCode::kWords, 0), 0U);
}

}  // namespace
