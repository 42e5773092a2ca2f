/**
 * @file fdir_params_doc.hpp
 * @brief The FDIR parameter table (trn/tasks/fdir_params.hpp) as the Markdown rows of docs/FDIR.md.
 */
#pragma once

#include <string>

namespace tools {

/**
 * One row per parameter, "| `name` | default | range | unit | meaning |", newline-terminated:
 * a field's default is its value in a wired, default configuration; a constant's range is "constant".
 */
std::string fdir_params_markdown();

}  // namespace tools
