/**
 * @file ecc.hpp
 * @brief Table-driven SECDED (Hsiao) codes over arrays of 32-bit words.
 *
 * A code with R check bits gives every protected bit position p = 32*word + bit
 * a distinct R-bit column of odd weight >= 3 (Hsiao: weight-3 columns first,
 * then weight 5, ...; check bit j itself has the unit column 1<<j). The check
 * bits are the XOR of the columns of the set bits. Because every column has odd
 * weight, one flipped bit gives an odd-weight syndrome equal to its column, two
 * give a nonzero even-weight syndrome: single errors are corrected, double
 * errors detected, with no separate overall-parity bit.
 *
 * Speed: the columns are turned at compile time into per-word masks, one per
 * check bit (masks[word][j] = the bits of that word whose column has bit j), so
 * encoding is R AND/XOR per word plus one popcount parity per check bit at the
 * end; decoding adds one lookup in a syndrome -> position table. No bit loops.
 *
 * Columns depend only on the bit position, never on the word count, so a code
 * over fewer words is a shortened code with the same tables (a syndrome that
 * points past the given words is reported uncorrectable).
 */
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>

namespace udn {

/** Outcome of checking a code word. */
enum class EccStatus : std::uint8_t {
  kClean,           ///< syndrome zero: no error seen
  kCorrectedData,   ///< one data bit was wrong, at (word, bit); not yet flipped back
  kCorrectedCheck,  ///< one check bit was wrong: bit = check-bit index; data is right
  kUncorrectable,   ///< two bits wrong (always caught) or more (sometimes caught)
};

/** Result of Secded::check. word/bit are meaningful for the corrected kinds only. */
struct EccCheck {
  EccStatus status = EccStatus::kClean;
  std::uint16_t word = 0;  ///< index into the checked word array
  std::uint8_t bit = 0;    ///< bit within that word (0 = LSB), or check-bit index
};

namespace detail {

/** Mask lanes per word: check bits are at most 16 (they live in half words). */
inline constexpr std::size_t kEccLanes = 16;
/** Syndrome-table entry for "no single-bit error has this syndrome". */
inline constexpr std::uint16_t kNoPosition = 0xFFFFU;
/** Syndrome-table entries >= this base name check bit (entry - base). */
inline constexpr std::uint16_t kCheckBase = 0xFF00U;

/** Number of odd-weight >= 3 columns an R-bit code can give. */
constexpr std::size_t hsiao_columns(unsigned check_bits) noexcept {
  std::size_t n = 0;
  for (std::uint32_t v = 0; v < (1U << check_bits); ++v) {
    const int w = __builtin_popcount(v);
    n += (w >= 3 && (w & 1) == 1) ? 1U : 0U;
  }
  return n;
}

template <unsigned kR, std::size_t kWords>
struct SecdedTables {
  /** masks[w][j]: the bits of word w whose column has check bit j set. */
  std::array<std::array<std::uint32_t, kEccLanes>, kWords> masks{};
  /** syndrome -> bit position 32*w+b, kCheckBase+j for check bit j, or kNoPosition. */
  std::array<std::uint16_t, (1U << kR)> position{};
};

/** Builds the tables at compile time; column order: by weight, then by value. */
template <unsigned kR, std::size_t kWords>
constexpr SecdedTables<kR, kWords> build_secded_tables() noexcept {
  SecdedTables<kR, kWords> t{};
  for (std::uint16_t& p : t.position) {
    p = kNoPosition;
  }
  for (unsigned j = 0; j < kR; ++j) {
    t.position[1U << j] = static_cast<std::uint16_t>(kCheckBase + j);
  }
  constexpr std::size_t kBits = kWords * 32U;
  std::size_t p = 0;
  for (int weight = 3; weight <= static_cast<int>(kR) && p < kBits; weight += 2) {
    for (std::uint32_t v = 0; v < (1U << kR) && p < kBits; ++v) {
      if (__builtin_popcount(v) != weight) {
        continue;
      }
      for (unsigned j = 0; j < kR; ++j) {
        if (((v >> j) & 1U) != 0U) {
          t.masks[p / 32U][j] |= 1U << (p % 32U);
        }
      }
      t.position[v] = static_cast<std::uint16_t>(p);
      ++p;
    }
  }
  return t;
}

}  // namespace detail

/**
 * A SECDED code with kCheckBits check bits over up to kMaxWords 32-bit words.
 * Stateless; all tables are compile-time constants in read-only memory.
 */
template <unsigned kCheckBits, std::size_t kMaxWords>
class Secded {
 public:
  static_assert(kCheckBits >= 4 && kCheckBits <= 15, "check bits must fit a half word");
  static_assert(kMaxWords * 32U <= detail::kCheckBase, "positions must fit the table entries");
  static_assert(detail::hsiao_columns(kCheckBits) >= kMaxWords * 32U, "too few odd-weight columns");

  static constexpr unsigned kR = kCheckBits;
  static constexpr std::size_t kWords = kMaxWords;
  static constexpr std::uint32_t kCheckMask = (1U << kCheckBits) - 1U;

  /**
   * Check bits of words (bits 0..kR-1 of the result).
   * Pre: words.size() <= kMaxWords (extra words are ignored). Bounded: size * 16 AND/XOR.
   */
  static std::uint32_t encode(std::span<const std::uint32_t> words) noexcept;

  /**
   * Checks words against received check bits (only the low kR bits are used).
   * Does not modify the words: a kCorrectedData result names the bit to flip.
   * Pre: words.size() <= kMaxWords (else kUncorrectable).
   */
  static EccCheck check(std::span<const std::uint32_t> words, std::uint32_t check_bits) noexcept;

  /** The column of bit position 32*word+bit (for tests and reference checks). */
  static std::uint32_t column(std::size_t word, unsigned bit) noexcept;

 private:
  static constexpr detail::SecdedTables<kCheckBits, kMaxWords> kTables =
      detail::build_secded_tables<kCheckBits, kMaxWords>();
};

/** Payload code: up to 124 data words plus the optional CRC word; 13 check bits. */
inline constexpr std::size_t kDataCodeMaxWords = 125;
inline constexpr unsigned kDataCodeCheckBits = 13;
using DataCode = Secded<kDataCodeCheckBits, kDataCodeMaxWords>;

/** Route code: hardware words 0, 1 and route words 3, 4; 9 check bits. */
inline constexpr std::size_t kRouteCodeWords = 4;
inline constexpr unsigned kRouteCodeCheckBits = 9;
using RouteCode = Secded<kRouteCodeCheckBits, kRouteCodeWords>;

extern template class Secded<kDataCodeCheckBits, kDataCodeMaxWords>;
extern template class Secded<kRouteCodeCheckBits, kRouteCodeWords>;

}  // namespace udn
