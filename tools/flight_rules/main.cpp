/**
 * @file main.cpp
 * @brief `flight_rules FILE...`: checks flight files, prints findings, exits 1 on any.
 */
#include "tools/common/flight_rules.hpp"

#include <iostream>
#include <string>

int main(int argc, char** argv) {
  if (argc < 2) {
    std::cerr << "usage: flight_rules FILE... (paths relative to the repository root)\n";
    return 2;
  }
  std::size_t findings = 0;
  int checked = 0;
  for (int i = 1; i < argc; ++i) {
    const std::string path = argv[i];
    if (tools::flight_rules::layer_of(path).empty()) {
      std::cerr << "flight_rules: " << path << " is not in a flight layer\n";
      return 2;
    }
    for (const auto& f : tools::flight_rules::check_file(path)) {
      std::cout << f.file << ":" << f.line << ": [" << f.rule << "] " << f.message << "\n";
      ++findings;
    }
    ++checked;
  }
  std::cout << "flight_rules: " << checked << " files, " << findings << " findings\n";
  return findings == 0 ? 0 : 1;
}
