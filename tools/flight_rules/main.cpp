/**
 * @file main.cpp
 * @brief `flight_rules --tree ROOT` or `flight_rules FILE...`: checks files, prints findings, exits 1 on any.
 *
 * --tree ROOT checks every file the checker covers under the repository root
 * (project_files()) and their include graph; this is what `make lint` runs.
 * FILE... checks the named files (paths relative to the repository root, run
 * from there) and the include cycles among them only.
 */
#include "tools/common/rules/flight_rules.hpp"

#include <iostream>
#include <string>
#include <vector>

namespace fr = tools::flight_rules;

int main(int argc, char** argv) {
  const std::vector<std::string> args(argv + 1, argv + argc);
  if (args.empty() || (args[0] == "--tree" && args.size() != 2U)) {
    std::cerr << "usage: flight_rules --tree ROOT | flight_rules FILE... (paths relative to the repository root)\n";
    return 2;
  }
  const bool tree = args[0] == "--tree";
  const std::string root = tree ? args[1] : ".";
  const std::vector<std::string> paths = tree ? fr::project_files(root) : args;
  if (paths.empty()) {
    std::cerr << "flight_rules: no source files under " << root << "\n";
    return 2;
  }
  for (const std::string& p : paths) {
    if (fr::layer_of(p).empty()) {
      std::cerr << "flight_rules: " << p << " is not in a layer (bsp_tile64 kernel udn fdir trn tools tests)\n";
      return 2;
    }
  }
  std::vector<fr::Finding> findings;
  const std::vector<fr::Source> sources = fr::read_sources(root, paths, findings);
  const std::vector<fr::Finding> checked = fr::check_sources(sources);
  findings.insert(findings.end(), checked.begin(), checked.end());
  for (const auto& f : findings) {
    std::cout << f.file << ":" << f.line << ": [" << f.rule << "] " << f.message << "\n";
  }
  std::cout << "flight_rules: " << paths.size() << " files, " << findings.size() << " findings\n";
  return findings.empty() ? 0 : 1;
}
