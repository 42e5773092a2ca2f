/**
 * @file flight_rules.hpp
 * @brief Checker for the flight-code rules that a compiler does not enforce.
 *
 * Per file, in flight folders (bsp_tile64 kernel udn fdir trn): heap use,
 * owning standard containers and streams, exceptions, RTTI, host time and host
 * randomness. Files under a `host/` folder of a layer are host infrastructure:
 * only the include rules apply to them; in tools/ and tests/ only the include
 * rules apply too.
 *
 * Include rules, on every file of the tree:
 * - layering: includes point down the layer order
 *   bsp_tile64 < kernel < udn < fdir < trn < tools, tests (tools and tests share
 *   the top rank); flight code never includes tools/ or tests/.
 * - truth: a layer above the board (kernel udn fdir trn) includes from
 *   bsp_tile64/ only the headers of kBoardInterfaceDir. Everything else there is
 *   the model (its controls, its statistics, the world's truth, the devices'
 *   simulation of that truth) and flight code does not see it.
 * - cycle: the include graph of the tree has no cycles.
 *
 * Comments and string/character literals are blanked before the token rules
 * match, so a word in a comment never trips a rule.
 */
#pragma once

#include <array>
#include <string>
#include <string_view>
#include <vector>

namespace tools::flight_rules {

/**
 * The board's interface: the folder whose headers, and only those, kernel,
 * udn, fdir and trn may include from bsp_tile64/. Each header there is
 * interface control, as a datasheet or a driver's register map is: it says
 * what software on a tile can do and receive, and nothing of how the board,
 * the network or the world are simulated (port, work, memory, power, UDN
 * vocabulary and driver, the I/O tile's device FIFOs and the records and
 * conventions flight code shares with the devices). Beside it, out of bounds
 * above the board: emu/ (the emulator: the board's driver, the network
 * model's controls, the trace's host side, the seeded streams, the chip
 * profile and cost model, the devices' simulation), world/ (the truth) and
 * faults/ (the injector).
 */
inline constexpr std::string_view kBoardInterfaceDir = "bsp_tile64/api/";

struct Finding {
  std::string file;
  int line;
  std::string rule;  ///< "heap", "exceptions", "rtti", "host-time", "layering", "truth", "cycle", "io"
  std::string message;
};

/** One file of the tree: its path relative to the repository root, and its text. */
struct Source {
  std::string path;
  std::string text;
};

/** Layer rank: bsp_tile64 0, kernel 1, udn 2, fdir 3, trn 4, tools and tests 5; -1 if none. */
int layer_rank(std::string_view layer);

/** True for the flight layers (bsp_tile64 kernel udn fdir trn). */
bool is_flight_layer(std::string_view layer);

/** The layer of a path relative to the repository root ("" if none). */
std::string layer_of(std::string_view path);

/** True if a layer above the board may include @p path (a header in kBoardInterfaceDir, not below it). */
bool is_board_interface(std::string_view path);

/**
 * Checks one source text as if it lived in @p layer.
 * @param host_side true for host infrastructure inside a layer (only include rules apply);
 *        files of tools/ and tests/ are always treated so.
 */
std::vector<Finding> check_source(std::string_view file, std::string_view text, std::string_view layer,
                                  bool host_side);

/** Reads and checks one file whose layer follows from its repo-relative path. */
std::vector<Finding> check_file(const std::string& path);

/**
 * Include cycles among @p sources. An include names a file of @p sources as
 * the compiler finds it: a quoted name relative to the including file's folder
 * first, then (quoted or angled) relative to the repository root; includes of
 * anything else (system and generated headers) are not edges.
 * @return one "cycle" finding per cycle found by a depth-first walk in path
 *         order, at the include that closes it, naming the files around it.
 */
std::vector<Finding> find_include_cycles(const std::vector<Source>& sources);

/** Per-file rules on each source (its layer from its path) and the include cycles among them. */
std::vector<Finding> check_sources(const std::vector<Source>& sources);

/**
 * The files the checker covers under the repository root @p root: every .cpp,
 * .hpp and .h in bsp_tile64 kernel udn fdir trn tools tests, except
 * tests/fixtures/ (deliberately broken inputs of the checker's own tests),
 * as sorted repo-relative paths.
 */
std::vector<std::string> project_files(const std::string& root);

/**
 * Reads @p paths (relative to @p root) into sources; an unreadable file
 * becomes an "io" finding in @p errors.
 */
std::vector<Source> read_sources(const std::string& root, const std::vector<std::string>& paths,
                                 std::vector<Finding>& errors);

/** Blanks comments and string/char literals, keeping line structure (exposed for tests). */
std::string strip_comments_and_literals(std::string_view text);

}  // namespace tools::flight_rules
