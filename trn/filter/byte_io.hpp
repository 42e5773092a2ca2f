/**
 * @file byte_io.hpp
 * @brief Little-endian byte writer and reader over fixed buffers, and CRC-32, for the filter's records.
 *
 * Records are written field by field in a fixed order and byte order, never by
 * copying structs, so padding bytes and host layout never reach a vote or a
 * checksum.
 */
#pragma once

#include <array>
#include <bit>
#include <cstddef>
#include <cstdint>
#include <cstring>

namespace trn::filter {

namespace detail {

using CrcTables = std::array<std::array<std::uint32_t, 256>, 8>;

/** [0]: the byte table; [k]: the CRC of byte i followed by k zero bytes (slicing by 8). */
constexpr CrcTables make_crc_tables() noexcept {
  CrcTables t{};
  for (std::uint32_t i = 0; i < 256U; ++i) {
    std::uint32_t c = i;
    for (int k = 0; k < 8; ++k) {
      c = (c & 1U) != 0U ? (0xEDB88320U ^ (c >> 1U)) : (c >> 1U);
    }
    t[0][i] = c;
  }
  for (std::size_t k = 1; k < 8U; ++k) {
    for (std::size_t i = 0; i < 256U; ++i) {
      t[k][i] = (t[k - 1U][i] >> 8U) ^ t[0][t[k - 1U][i] & 0xFFU];
    }
  }
  return t;
}

inline constexpr CrcTables kCrcTables = make_crc_tables();

}  // namespace detail

/** Bytes @p p[0..3] as a little-endian word. */
constexpr std::uint32_t le32(const std::uint8_t* p) noexcept {
  return static_cast<std::uint32_t>(p[0]) | (static_cast<std::uint32_t>(p[1]) << 8U) |
         (static_cast<std::uint32_t>(p[2]) << 16U) | (static_cast<std::uint32_t>(p[3]) << 24U);
}

/**
 * CRC-32 (IEEE 802.3, reflected, init and final xor 0xFFFFFFFF) of @p n
 * bytes: eight bytes at a time through the eight tables (the same CRC as
 * byte by byte, two independent lookup chains), then the last singly.
 */
constexpr std::uint32_t crc32(const std::uint8_t* data, std::uint32_t n) noexcept {
  const auto& t = detail::kCrcTables;
  std::uint32_t c = 0xFFFFFFFFU;
  const std::uint32_t whole = n & ~7U;
  for (std::uint32_t i = 0; i < whole; i += 8U) {
    const std::uint32_t lo = c ^ le32(data + i);
    const std::uint32_t hi = le32(data + i + 4U);
    c = t[7][lo & 0xFFU] ^ t[6][(lo >> 8U) & 0xFFU] ^ t[5][(lo >> 16U) & 0xFFU] ^ t[4][lo >> 24U] ^
        t[3][hi & 0xFFU] ^ t[2][(hi >> 8U) & 0xFFU] ^ t[1][(hi >> 16U) & 0xFFU] ^ t[0][hi >> 24U];
  }
  for (std::uint32_t i = whole; i < n; ++i) {
    c = t[0][(c ^ data[i]) & 0xFFU] ^ (c >> 8U);
  }
  return c ^ 0xFFFFFFFFU;
}

/** Appends little-endian fields; stops (ok() false) instead of writing past the end. */
class ByteWriter {
 public:
  ByteWriter(std::uint8_t* buf, std::uint32_t cap) noexcept : buf_(buf), cap_(cap) {}
  void u32(std::uint32_t v) noexcept { put(v, 4U); }
  void u64(std::uint64_t v) noexcept { put(v, 8U); }
  void f64(double v) noexcept { put(std::bit_cast<std::uint64_t>(v), 8U); }
  [[nodiscard]] bool ok() const noexcept { return ok_; }
  [[nodiscard]] std::uint32_t size() const noexcept { return pos_; }

 private:
  void put(std::uint64_t v, std::uint32_t n) noexcept {
    if (!ok_ || cap_ - pos_ < n) {
      ok_ = false;
      return;
    }
    if constexpr (std::endian::native == std::endian::little) {
      std::memcpy(buf_ + pos_, &v, n);  // the low n bytes in memory order: the same bytes as the loop below
    } else {
      for (std::uint32_t i = 0; i < n; ++i) {
        buf_[pos_ + i] = static_cast<std::uint8_t>(v >> (8U * i));
      }
    }
    pos_ += n;
  }
  std::uint8_t* buf_;
  std::uint32_t cap_;
  std::uint32_t pos_ = 0;
  bool ok_ = true;
};

/** Reads little-endian fields; reads past the end give 0 and clear ok(). */
class ByteReader {
 public:
  ByteReader(const std::uint8_t* buf, std::uint32_t n) noexcept : buf_(buf), n_(n) {}
  std::uint32_t u32() noexcept { return static_cast<std::uint32_t>(get(4U)); }
  std::uint64_t u64() noexcept { return get(8U); }
  double f64() noexcept { return std::bit_cast<double>(get(8U)); }
  [[nodiscard]] bool ok() const noexcept { return ok_; }
  [[nodiscard]] std::uint32_t pos() const noexcept { return pos_; }

 private:
  std::uint64_t get(std::uint32_t n) noexcept {
    if (!ok_ || n_ - pos_ < n) {
      ok_ = false;
      return 0U;
    }
    std::uint64_t v = 0;
    for (std::uint32_t i = 0; i < n; ++i) {
      v |= static_cast<std::uint64_t>(buf_[pos_ + i]) << (8U * i);
    }
    pos_ += n;
    return v;
  }
  const std::uint8_t* buf_;
  std::uint32_t n_;
  std::uint32_t pos_ = 0;
  bool ok_ = true;
};

}  // namespace trn::filter
