/**
 * @file toml_input.hpp
 * @brief Parsing a TOML input file's text with the message every input parser gives for a syntax error.
 */
#pragma once

#include <toml++/toml.h>

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

}  // namespace tools
