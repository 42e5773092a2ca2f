/**
 * @file flight_rules.hpp
 * @brief Checker for the flight-code rules that a compiler does not enforce.
 *
 * Rejects, in flight folders (bsp_tile64 kernel udn fdir trn): heap use,
 * owning standard containers and streams, exceptions, RTTI, host time and host
 * randomness, and includes that go up the layer order (or into tools/, tests/,
 * or from a flight layer into the world's truth, bsp_tile64/world/).
 * Files under a `host/` folder of a layer are host infrastructure: only the
 * include rules apply to them.
 *
 * Comments and string/character literals are blanked before matching, so a
 * word in a comment never trips a rule.
 */
#pragma once

#include <string>
#include <string_view>
#include <vector>

namespace tools::flight_rules {

struct Finding {
  std::string file;
  int line;
  std::string rule;  ///< "heap", "exceptions", "rtti", "host-time", "layering", "truth"
  std::string message;
};

/** Layer rank: bsp_tile64 0, kernel 1, udn 2, fdir 3, trn 4; -1 if not a flight layer. */
int layer_rank(std::string_view layer);

/** The layer of a path relative to the repository root ("" if none). */
std::string layer_of(std::string_view path);

/**
 * Checks one source text as if it lived in @p layer.
 * @param host_side true for host infrastructure inside a layer (only include rules apply).
 */
std::vector<Finding> check_source(std::string_view file, std::string_view text, std::string_view layer,
                                  bool host_side);

/** Reads and checks a file whose layer follows from its repo-relative path. */
std::vector<Finding> check_file(const std::string& path);

/** Blanks comments and string/char literals, keeping line structure (exposed for tests). */
std::string strip_comments_and_literals(std::string_view text);

}  // namespace tools::flight_rules
