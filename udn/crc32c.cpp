/**
 * @file crc32c.cpp
 * @brief CRC-32C with compile-time slicing-by-4 tables (4 KiB read-only).
 */
#include "udn/crc32c.hpp"

#include <array>
#include <cstddef>

namespace udn {
namespace {

constexpr std::uint32_t kPoly = 0x82F63B78U;
constexpr std::uint32_t kInitXor = 0xFFFFFFFFU;

using Tables = std::array<std::array<std::uint32_t, 256>, 4>;

constexpr Tables build_tables() noexcept {
  Tables t{};
  for (std::uint32_t i = 0; i < 256U; ++i) {
    std::uint32_t c = i;
    for (int k = 0; k < 8; ++k) {
      c = ((c & 1U) != 0U) ? ((c >> 1U) ^ kPoly) : (c >> 1U);
    }
    t[0][i] = c;
  }
  // t[k][i]: the CRC of byte i followed by k zero bytes, so four bytes can be
  // looked up independently and combined.
  for (std::size_t k = 1; k < 4; ++k) {
    for (std::size_t i = 0; i < 256U; ++i) {
      const std::uint32_t prev = t[k - 1][i];
      t[k][i] = (prev >> 8U) ^ t[0][prev & 0xFFU];
    }
  }
  return t;
}

constexpr Tables kTables = build_tables();

}  // namespace

std::uint32_t crc32c_bytes(std::span<const std::uint8_t> bytes) noexcept {
  std::uint32_t crc = kInitXor;
  const std::size_t whole = bytes.size() & ~std::size_t{3U};
  // Four bytes at a time as a little-endian word through the four tables (the
  // same CRC as byte by byte), then the last one to three bytes singly.
  for (std::size_t i = 0; i < whole; i += 4U) {
    crc ^= static_cast<std::uint32_t>(bytes[i]) | (static_cast<std::uint32_t>(bytes[i + 1U]) << 8U) |
           (static_cast<std::uint32_t>(bytes[i + 2U]) << 16U) | (static_cast<std::uint32_t>(bytes[i + 3U]) << 24U);
    crc = kTables[3][crc & 0xFFU] ^ kTables[2][(crc >> 8U) & 0xFFU] ^ kTables[1][(crc >> 16U) & 0xFFU] ^
          kTables[0][crc >> 24U];
  }
  for (std::size_t i = whole; i < bytes.size(); ++i) {
    crc = (crc >> 8U) ^ kTables[0][(crc ^ bytes[i]) & 0xFFU];
  }
  return crc ^ kInitXor;
}

std::uint32_t crc32c_words_continue(std::uint32_t crc, std::span<const std::uint32_t> words) noexcept {
  std::uint32_t c = crc ^ kInitXor;
  for (const std::uint32_t w : words) {
    c ^= w;
    c = kTables[3][c & 0xFFU] ^ kTables[2][(c >> 8U) & 0xFFU] ^ kTables[1][(c >> 16U) & 0xFFU] ^
        kTables[0][c >> 24U];
  }
  return c ^ kInitXor;
}

std::uint32_t crc32c_words(std::span<const std::uint32_t> words) noexcept {
  return crc32c_words_continue(0U, words);
}

}  // namespace udn
