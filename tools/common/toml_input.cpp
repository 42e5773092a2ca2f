/**
 * @file toml_input.cpp
 * @brief The check of TOML text for characters toml++ 3.3.0 cannot classify (see toml_input.hpp).
 */
#include "tools/common/toml_input.hpp"

#include <cstddef>
#include <cstdint>

namespace tools::detail {

namespace {

/**
 * True for the code points toml++ 3.3.0's is_non_ascii_horizontal_whitespace()
 * has no answer for: it splits U+00A0..U+FEFF into blocks of 0x3FA, and blocks
 * 0, 11 and 63 end in an "unreachable" branch for all but U+00A0, U+3000, U+FEFF.
 */
bool unclassified(std::uint32_t cp) {
  return (cp >= 0xA1U && cp <= 0x499U) || (cp >= 0x2C5EU && cp <= 0x3057U && cp != 0x3000U) ||
         (cp >= 0xFB26U && cp <= 0xFEFEU);
}

/** The code point of a well-formed UTF-8 sequence at @p i (its length in @p len), or 0 (len 1). */
std::uint32_t decode(std::string_view text, std::size_t i, std::size_t& len) {
  const auto b0 = static_cast<std::uint8_t>(text[i]);
  len = b0 >= 0xF0U ? 4U : b0 >= 0xE0U ? 3U : b0 >= 0xC0U ? 2U : 1U;
  if (len == 1U || i + len > text.size()) {
    len = 1U;
    return 0U;
  }
  std::uint32_t cp = b0 & (0x7FU >> len);
  for (std::size_t k = 1; k < len; ++k) {
    const auto b = static_cast<std::uint8_t>(text[i + k]);
    if ((b & 0xC0U) != 0x80U) {
      len = 1U;
      return 0U;  // malformed: the parser reports it
    }
    cp = (cp << 6U) | (b & 0x3FU);
  }
  return cp;
}

}  // namespace

std::size_t toml_unsafe_line(std::string_view text) {
  std::size_t line = 1;
  std::size_t i = 0;
  while (i < text.size()) {
    std::size_t len = 1;
    const std::uint32_t cp = (static_cast<std::uint8_t>(text[i]) & 0x80U) != 0U ? decode(text, i, len) : 0U;
    if (unclassified(cp)) {
      return line;
    }
    line += text[i] == '\n' ? 1U : 0U;
    i += len;
  }
  return 0U;
}

}  // namespace tools::detail
