/**
 * @file ecc.cpp
 * @brief SECDED encode/check over the compile-time mask and syndrome tables.
 */
#include "udn/ecc.hpp"

#include <bit>

namespace udn {

template <unsigned kCheckBits, std::size_t kMaxWords>
std::uint32_t Secded<kCheckBits, kMaxWords>::encode(std::span<const std::uint32_t> words) noexcept {
  // One accumulator per check bit; the fixed 16-lane inner loop vectorises,
  // and unrolled whole it keeps the accumulators in registers across words.
  std::array<std::uint32_t, detail::kEccLanes> acc{};
  const std::size_t n = words.size() < kMaxWords ? words.size() : kMaxWords;
  for (std::size_t w = 0; w < n; ++w) {
    const std::uint32_t x = words[w];
    const std::array<std::uint32_t, detail::kEccLanes>& m = kTables.masks[w];
#pragma GCC unroll 16
    for (std::size_t j = 0; j < detail::kEccLanes; ++j) {
      acc[j] ^= x & m[j];
    }
  }
  std::uint32_t check = 0;
  for (unsigned j = 0; j < kCheckBits; ++j) {
    check |= (static_cast<std::uint32_t>(std::popcount(acc[j])) & 1U) << j;
  }
  return check;
}

template <unsigned kCheckBits, std::size_t kMaxWords>
EccCheck Secded<kCheckBits, kMaxWords>::check(std::span<const std::uint32_t> words,
                                              std::uint32_t check_bits) noexcept {
  EccCheck r{};
  if (words.size() > kMaxWords) {
    r.status = EccStatus::kUncorrectable;
    return r;
  }
  const std::uint32_t syndrome = (encode(words) ^ check_bits) & kCheckMask;
  if (syndrome == 0U) {
    return r;
  }
  const std::uint16_t pos = kTables.position[syndrome];
  // Even weight: two errors. Odd weight without a column, or a column of the
  // full-length code that this shortened word count does not use: three or more.
  const bool odd = (std::popcount(syndrome) & 1) == 1;
  const bool is_check = pos >= detail::kCheckBase && pos != detail::kNoPosition;
  const bool is_data = pos < words.size() * 32U;
  if (!odd || (!is_check && !is_data)) {
    r.status = EccStatus::kUncorrectable;
  } else if (is_check) {
    r.status = EccStatus::kCorrectedCheck;
    r.bit = static_cast<std::uint8_t>(pos - detail::kCheckBase);
  } else {
    r.status = EccStatus::kCorrectedData;
    r.word = static_cast<std::uint16_t>(pos / 32U);
    r.bit = static_cast<std::uint8_t>(pos % 32U);
  }
  return r;
}

template <unsigned kCheckBits, std::size_t kMaxWords>
std::uint32_t Secded<kCheckBits, kMaxWords>::column(std::size_t word, unsigned bit) noexcept {
  if (word >= kMaxWords || bit >= 32U) {
    return 0U;
  }
  std::uint32_t c = 0;
  for (unsigned j = 0; j < kCheckBits; ++j) {
    c |= ((kTables.masks[word][j] >> bit) & 1U) << j;
  }
  return c;
}

template class Secded<kDataCodeCheckBits, kDataCodeMaxWords>;
template class Secded<kRouteCodeCheckBits, kRouteCodeWords>;

}  // namespace udn
