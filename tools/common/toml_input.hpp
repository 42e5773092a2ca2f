/**
 * @file toml_input.hpp
 * @brief Parsing a TOML input file's text, and reading its numbers in range, with the messages every input parser gives.
 */
#pragma once

#include "tools/common/text.hpp"

#include <toml++/toml.h>

#include <cmath>
#include <cstdint>

#include <string>
#include <string_view>

namespace tools {

/**
 * Parses @p text (named @p source in messages) into @p root.
 * @return false with "<source>:<line>:<column>: TOML syntax error: ..." in @p error.
 */
inline bool parse_toml(std::string_view text, const std::string& source, toml::table& root, std::string& error) {
  try {
    root = toml::parse(text, source);
  } catch (const toml::parse_error& e) {
    error = source + ":" + std::to_string(e.source().begin.line) + ":" + std::to_string(e.source().begin.column) +
            ": TOML syntax error: " + std::string(e.description());
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
