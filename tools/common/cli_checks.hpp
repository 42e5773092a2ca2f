/**
 * @file cli_checks.hpp
 * @brief Checks the tools' command lines share.
 *
 * CLI11 reads "-3" into an unsigned option as 2^64 - 3 without a word, so a
 * typed minus flew a run with seed 18446744073709551613. Unsigned options take
 * kWholeNumber: digits only, or a clear message and exit status 2.
 *
 * Host code: allocation and exceptions are fine here.
 */
#pragma once

#include <CLI/CLI.hpp>

#include <algorithm>
#include <cctype>
#include <string>

namespace tools {

/** A whole number, 0 or more, in decimal digits (an unsigned option's value, or each of a list's). */
inline const CLI::Validator kWholeNumber(
    [](const std::string& v) -> std::string {
      const bool digits = !v.empty() && std::all_of(v.begin(), v.end(), [](char c) {
        return std::isdigit(static_cast<unsigned char>(c)) != 0;
      });
      return digits ? std::string{} : "'" + v + "' is not a whole number 0 or more";
    },
    "UINT");

}  // namespace tools
