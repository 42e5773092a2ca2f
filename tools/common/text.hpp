/**
 * @file text.hpp
 * @brief Small text helpers shared by the input-file parsers (scenarios, fault plans).
 */
#pragma once

#include <cmath>
#include <initializer_list>
#include <sstream>
#include <string>
#include <string_view>

namespace tools {

/** Concatenation in one buffer. */
inline std::string cat(std::initializer_list<std::string_view> parts) {
  std::string out;
  for (const std::string_view p : parts) {
    out.append(p);
  }
  return out;
}

/** A number as a message shows it: integers without a fraction (up to 2^53 - 1), others to 10 digits. */
inline std::string format_number(double v) {
  if (std::isfinite(v) && v == std::floor(v) && std::fabs(v) <= 9007199254740991.0) {
    return std::to_string(static_cast<long long>(v));
  }
  std::ostringstream o;
  o.precision(10);
  o << v;
  return o.str();
}

}  // namespace tools
