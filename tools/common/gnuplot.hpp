/**
 * @file gnuplot.hpp
 * @brief Running gnuplot from the host tools: finding it, the PNG terminal line, one bounded run of a script.
 *
 * Shared by the run folder's plots (run_folder.*) and the campaign report
 * (campaign_stats.*), so both pick the terminal and run gnuplot the same way.
 */
#pragma once

#include <string>
#include <vector>

namespace tools {

/** The executable @p name on the PATH, or "" if there is none. */
std::string find_on_path(const std::string& name);

/**
 * The gnuplot lines that select pngcairo when this gnuplot has it, else png
 * (Debian's gnuplot-nox has both; a minimal build may have only png), at
 * @p size ("W,H" in pixels), without enhanced text (names hold underscores).
 */
std::string gnuplot_png_terminal(const char* size);

/** Longest a gnuplot run may take before it is killed, seconds. */
inline constexpr int kGnuplotTimeoutS = 60;

/**
 * Runs `gnuplot ARGS... SCRIPT` in @p folder: stdin from /dev/null, output
 * appended to @p folder/plots.log, its own session (no terminal); killed
 * after kGnuplotTimeoutS. @p args come before the script (e.g. "-e",
 * "out='x.png'" to set a variable the script reads).
 * @return "" on success, else what went wrong (one line).
 */
std::string run_gnuplot(const std::string& gnuplot, const std::string& folder, const std::string& script,
                        const std::vector<std::string>& args = {});

}  // namespace tools
