/**
 * @file crc32c_test.cpp
 * @brief CRC-32C: standard check value, word path equals byte path, bitwise reference.
 */
#include "udn/crc32c.hpp"

#include "bsp_tile64/emu/rng.hpp"

#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>
#include <vector>

namespace {

/** Bit-at-a-time reference, straight from the definition. */
std::uint32_t reference_crc32c(const std::vector<std::uint8_t>& bytes) {
  std::uint32_t crc = 0xFFFFFFFFU;
  for (const std::uint8_t b : bytes) {
    crc ^= b;
    for (int k = 0; k < 8; ++k) {
      crc = (crc & 1U) != 0U ? (crc >> 1U) ^ 0x82F63B78U : crc >> 1U;
    }
  }
  return ~crc;
}

std::vector<std::uint8_t> le_bytes(const std::vector<std::uint32_t>& words) {
  std::vector<std::uint8_t> out;
  for (const std::uint32_t w : words) {
    for (unsigned k = 0; k < 4; ++k) {
      out.push_back(static_cast<std::uint8_t>(w >> (8U * k)));
    }
  }
  return out;
}

TEST(Crc32c, StandardCheckValueOf123456789) {
  const char* s = "123456789";
  std::vector<std::uint8_t> bytes(s, s + std::strlen(s));
  EXPECT_EQ(udn::crc32c_bytes(bytes), 0xE3069283U);
  EXPECT_EQ(reference_crc32c(bytes), 0xE3069283U);
}

TEST(Crc32c, WordPathEqualsBytewiseReferenceOnLittleEndianBytes) {
  const std::uint64_t seed = 0xC3C32CULL;
  bsp::Rng rng(seed, bsp::StreamId::kTest, 0);
  for (std::size_t n = 0; n <= 130; ++n) {
    std::vector<std::uint32_t> words(n);
    for (auto& w : words) {
      w = static_cast<std::uint32_t>(rng.next());
    }
    const auto bytes = le_bytes(words);
    ASSERT_EQ(udn::crc32c_words(words), reference_crc32c(bytes)) << "seed " << seed << " n " << n;
    ASSERT_EQ(udn::crc32c_bytes(bytes), reference_crc32c(bytes)) << "seed " << seed << " n " << n;
  }
}

// The byte path takes four bytes at a time and the last one to three singly: every length and every
// start within a word agrees with the definition.
TEST(Crc32c, BytePathEqualsTheReferenceAtEveryLength) {
  const std::uint64_t seed = 0xB17E5ULL;
  bsp::Rng rng(seed, bsp::StreamId::kTest, 1);
  std::vector<std::uint8_t> buf(160);
  for (auto& b : buf) {
    b = static_cast<std::uint8_t>(rng.next());
  }
  for (std::size_t start = 0; start < 4U; ++start) {
    for (std::size_t n = 0; n + start <= buf.size(); ++n) {
      const std::vector<std::uint8_t> bytes(buf.begin() + static_cast<std::ptrdiff_t>(start),
                                            buf.begin() + static_cast<std::ptrdiff_t>(start + n));
      ASSERT_EQ(udn::crc32c_bytes(bytes), reference_crc32c(bytes)) << "seed " << seed << " start " << start << " n " << n;
    }
  }
}

TEST(Crc32c, ContinuingInPiecesEqualsOneCall) {
  const std::vector<std::uint32_t> words = {1U, 2U, 0xDEADBEEFU, 0U, 0xFFFFFFFFU, 7U};
  const std::span<const std::uint32_t> all(words);
  const std::uint32_t part = udn::crc32c_words(all.subspan(0, 2));
  EXPECT_EQ(udn::crc32c_words_continue(part, all.subspan(2)), udn::crc32c_words(all));
}

}  // namespace
