/**
 * @file toml_input.hpp
 * @brief Parsing a TOML input file's text, and reading its numbers in range, with the messages every input parser gives.
 */
#pragma once

#include "tools/common/text.hpp"

#include <cstddef>
#include <string_view>

namespace tools::detail {
/** The first toml++ precondition the current parse broke (nullptr: none); see TOML_ASSERT below. */
inline thread_local const char* g_toml_broken = nullptr;
inline void toml_precondition_broken(const char* expr) noexcept {
  if (g_toml_broken == nullptr) {
    g_toml_broken = expr;
  }
}
/**
 * The line of the first character of @p text that toml++ 3.3.0 cannot tell is
 * whitespace or not (0: none): U+00A1..U+0499 (Latin-1 and Latin Extended,
 * Greek, Cyrillic), U+2C5E..U+3057 but U+3000, U+FB26..U+FEFE. Asked about one,
 * its Unicode table reaches an "unreachable" branch (undefined behaviour;
 * upstream tomlplusplus issue 190), and it asks wherever it looks for
 * whitespace or the end of a value, inside strings too. Text with one, even in
 * a string or a comment, is refused before it is parsed.
 */
std::size_t toml_unsafe_line(std::string_view text);
}  // namespace tools::detail

// toml++ 3.3.0 (Debian 12) checks some of its parser's preconditions with
// assert(), and malformed text can break them: a table header that starts with
// a character no key starts with ("[:a]", "[[[1]]]"; upstream tomlplusplus
// pull request 301) aborted every program reading a scenario, plan or
// campaign. The parser goes on to report such text as a syntax error by
// itself; here a broken check is recorded instead of aborting, and
// parse_toml() refuses the text even if the parser did not. Every file of the
// tools includes toml++ through this header only, so they all see one
// definition. Not with NDEBUG: toml++ then assumes its checks hold
// (undefined behaviour on such text).
#ifdef NDEBUG
#error "tools/common/toml_input.hpp: toml++ needs its precondition checks (NDEBUG turns them into assumptions)"
#endif
#ifdef TOML_ASSERT
#error "tools/common/toml_input.hpp must be the first to include toml++"
#endif
#define TOML_ASSERT(expr) ((expr) ? static_cast<void>(0) : ::tools::detail::toml_precondition_broken(#expr))
#include <toml++/toml.h>

#include <cmath>
#include <cstdint>

#include <string>

namespace tools {

/**
 * Parses @p text (named @p source in messages) into @p root.
 * @return false with "<source>:<line>:<column>: TOML syntax error: ..." in @p error
 *         ("<source>: TOML syntax error: ..." where the parser cannot say where).
 */
inline bool parse_toml(std::string_view text, const std::string& source, toml::table& root, std::string& error) {
  if (const std::size_t line = detail::toml_unsafe_line(text); line != 0U) {
    error = source + ":" + std::to_string(line) +
            ": a character the TOML parser cannot read safely (U+00A1..U+0499, U+2C5E..U+3057, U+FB26..U+FEFE; "
            "use ASCII)";
    return false;
  }
  detail::g_toml_broken = nullptr;
  try {
    root = toml::parse(text, source);
  } catch (const toml::parse_error& e) {
    error = source + ":" + std::to_string(e.source().begin.line) + ":" + std::to_string(e.source().begin.column) +
            ": TOML syntax error: " + std::string(e.description());
    return false;
  }
  if (detail::g_toml_broken != nullptr) {
    error = source + ": TOML syntax error: text the TOML parser cannot read (its check " + detail::g_toml_broken +
            " failed)";
    root = toml::table{};
    return false;
  }
  return true;
}

/** Reads an integer within lo..hi; returns an error text (empty when read). */
inline std::string read_int(const toml::node& node, std::int64_t lo, std::int64_t hi, std::int64_t& out) {
  if (!node.is_integer()) {
    return "wrong type: expected an integer";
  }
  const std::int64_t v = node.as_integer()->get();
  if (v < lo || v > hi) {
    return cat({std::to_string(v), " is out of range: allowed ", std::to_string(lo), " .. ", std::to_string(hi)});
  }
  out = v;
  return {};
}

/** Reads a number (an integer is a valid float) within lo..hi. */
inline std::string read_float(const toml::node& node, double lo, double hi, const char* unit, double& out) {
  double v = 0.0;
  if (node.is_integer()) {
    v = static_cast<double>(node.as_integer()->get());
  } else if (node.is_floating_point()) {
    v = node.as_floating_point()->get();
  } else {
    return "wrong type: expected a number";
  }
  if (!(std::isfinite(v) && v >= lo && v <= hi)) {
    return cat({format_number(v), " is out of range: allowed ", format_number(lo), " .. ", format_number(hi), unit});
  }
  out = v;
  return {};
}

}  // namespace tools
