/**
 * @file crc32c.cpp
 * @brief CRC-32C with compile-time slicing-by-8 tables (8 KiB read-only).
 */
#include "udn/crc32c.hpp"

#include <array>
#include <cstddef>

namespace udn {
namespace {

constexpr std::uint32_t kPoly = 0x82F63B78U;
constexpr std::uint32_t kInitXor = 0xFFFFFFFFU;

using Tables = std::array<std::array<std::uint32_t, 256>, 8>;

constexpr Tables build_tables() noexcept {
  Tables t{};
  for (std::uint32_t i = 0; i < 256U; ++i) {
    std::uint32_t c = i;
    for (int k = 0; k < 8; ++k) {
      c = ((c & 1U) != 0U) ? ((c >> 1U) ^ kPoly) : (c >> 1U);
    }
    t[0][i] = c;
  }
  // t[k][i]: the CRC of byte i followed by k zero bytes, so four (eight) bytes
  // can be looked up independently and combined.
  for (std::size_t k = 1; k < 8; ++k) {
    for (std::size_t i = 0; i < 256U; ++i) {
      const std::uint32_t prev = t[k - 1][i];
      t[k][i] = (prev >> 8U) ^ t[0][prev & 0xFFU];
    }
  }
  return t;
}

constexpr Tables kTables = build_tables();

/** Bytes @p i .. @p i + 3 of @p b as a little-endian word. */
constexpr std::uint32_t le_word(std::span<const std::uint8_t> b, std::size_t i) noexcept {
  return static_cast<std::uint32_t>(b[i]) | (static_cast<std::uint32_t>(b[i + 1U]) << 8U) |
         (static_cast<std::uint32_t>(b[i + 2U]) << 16U) | (static_cast<std::uint32_t>(b[i + 3U]) << 24U);
}

/** One word folded into @p c through the four tables of its distance from the end of the step (@p k: 0 or 4). */
constexpr std::uint32_t fold(std::uint32_t c, std::size_t k) noexcept {
  return kTables[k + 3U][c & 0xFFU] ^ kTables[k + 2U][(c >> 8U) & 0xFFU] ^ kTables[k + 1U][(c >> 16U) & 0xFFU] ^
         kTables[k][c >> 24U];
}

}  // namespace

std::uint32_t crc32c_bytes(std::span<const std::uint8_t> bytes) noexcept {
  std::uint32_t crc = kInitXor;
  const std::size_t eights = bytes.size() & ~std::size_t{7U};
  // Eight bytes at a time (the same CRC as byte by byte: a host's speed, not the emulated cost),
  // then one word, then the last one to three bytes singly.
  std::size_t i = 0;
  for (; i < eights; i += 8U) {
    crc = fold(crc ^ le_word(bytes, i), 4U) ^ fold(le_word(bytes, i + 4U), 0U);
  }
  if (i + 4U <= bytes.size()) {
    crc = fold(crc ^ le_word(bytes, i), 0U);
    i += 4U;
  }
  for (; i < bytes.size(); ++i) {
    crc = (crc >> 8U) ^ kTables[0][(crc ^ bytes[i]) & 0xFFU];
  }
  return crc ^ kInitXor;
}

std::uint32_t crc32c_words_continue(std::uint32_t crc, std::span<const std::uint32_t> words) noexcept {
  std::uint32_t c = crc ^ kInitXor;
  const std::size_t pairs = words.size() & ~std::size_t{1U};
  std::size_t i = 0;
  for (; i < pairs; i += 2U) {
    c = fold(c ^ words[i], 4U) ^ fold(words[i + 1U], 0U);
  }
  if (i < words.size()) {
    c = fold(c ^ words[i], 0U);
  }
  return c ^ kInitXor;
}

std::uint32_t crc32c_words(std::span<const std::uint32_t> words) noexcept {
  return crc32c_words_continue(0U, words);
}

}  // namespace udn
