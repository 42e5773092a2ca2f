/**
 * @file toml_input.cpp
 * @brief The check of TOML text for what toml++ 3.3.0 cannot parse safely (see toml_input.hpp).
 */
#include "tools/common/toml_input.hpp"

#include <cstddef>

namespace tools::detail {

namespace {

enum class Lex : unsigned char { kCode, kComment, kBasic, kLiteral, kMultiBasic, kMultiLiteral };

bool starts(std::string_view text, std::size_t i, std::string_view what) { return text.substr(i, what.size()) == what; }

bool non_ascii(char c) { return (static_cast<unsigned char>(c) & 0x80U) != 0U; }

/** Past the end of a multi-line string whose delimiter @p q starts at @p i (three to five quotes: up to two are content). */
std::size_t past_closing(std::string_view text, std::size_t i, char q) {
  std::size_t n = 0;
  while (n < 5U && i + n < text.size() && text[i + n] == q) {
    ++n;
  }
  return i + n;
}

/**
 * In a multi-line basic string at a backslash: past a line-ending backslash's
 * whitespace (@p unsafe if a character that is not ASCII comes next), else past the escape.
 */
std::size_t after_backslash(std::string_view text, std::size_t i, bool& unsafe) {
  std::size_t j = i + 1;
  while (j < text.size() && (text[j] == ' ' || text[j] == '\t')) {
    ++j;
  }
  if (j >= text.size() || (text[j] != '\n' && text[j] != '\r')) {
    return i + 2;  // an escape: the character after the backslash is part of it
  }
  while (j < text.size() && (text[j] == ' ' || text[j] == '\t' || text[j] == '\n' || text[j] == '\r')) {
    ++j;
  }
  unsafe = j < text.size() && non_ascii(text[j]);
  return j;
}

}  // namespace

std::size_t toml_unsafe_line(std::string_view text) {
  Lex lex = Lex::kCode;
  std::size_t line = 1;
  std::size_t i = starts(text, 0, "\xEF\xBB\xBF") ? 3U : 0U;  // a UTF-8 byte order mark is skipped
  while (i < text.size()) {
    const char c = text[i];
    bool unsafe = false;
    std::size_t next = i + 1;
    switch (lex) {
      case Lex::kCode:
        unsafe = non_ascii(c);
        if (c == '#') {
          lex = Lex::kComment;
        } else if (starts(text, i, "\"\"\"") || starts(text, i, "'''")) {
          lex = c == '"' ? Lex::kMultiBasic : Lex::kMultiLiteral;
          next = i + 3;
        } else if (c == '"' || c == '\'') {
          lex = c == '"' ? Lex::kBasic : Lex::kLiteral;
        }
        break;
      case Lex::kComment:
      case Lex::kBasic:
      case Lex::kLiteral:
        if (c == '\n' || (lex == Lex::kBasic && c == '"') || (lex == Lex::kLiteral && c == '\'')) {
          lex = Lex::kCode;  // a string that a line ends is the parser's error to report
        } else if (lex == Lex::kBasic && c == '\\') {
          next = i + 2;
        }
        break;
      case Lex::kMultiBasic:
        if (c == '\\') {
          next = after_backslash(text, i, unsafe);
        } else if (starts(text, i, "\"\"\"")) {
          lex = Lex::kCode;
          next = past_closing(text, i, '"');
        }
        break;
      case Lex::kMultiLiteral:
        if (starts(text, i, "'''")) {
          lex = Lex::kCode;
          next = past_closing(text, i, '\'');
        }
        break;
    }
    for (std::size_t k = i; k < next && k < text.size(); ++k) {
      line += text[k] == '\n' ? 1U : 0U;
    }
    if (unsafe) {
      return line;
    }
    i = next;
  }
  return 0U;
}

}  // namespace tools::detail
