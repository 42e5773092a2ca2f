/**
 * @file main.cpp
 * @brief udn_stress: synthetic traffic on the emulated UDN; one JSON object of statistics on stdout.
 */
#include "tools/common/udn_stress.hpp"

#include <cstdio>
#include <exception>
#include <iostream>
#include <string>

int main(int argc, char** argv) {
  try {
    tools::StressOptions opts;
    std::string message;
    const int rc = tools::parse_stress_args(argc, argv, opts, message);
    if (rc == 0) {
      std::cout << message;
      return 0;
    }
    if (rc > 0) {
      std::fprintf(stderr, "udn_stress: %s\nRun with --help for the options.\n", message.c_str());
      return rc;
    }
    const tools::StressResult r = tools::run_stress(opts, bsp::heap::SealMode::kFatal);
    tools::write_stress_json(std::cout, opts, r);
    return r.completed ? 0 : 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "udn_stress: %s\n", e.what());
    return 1;
  }
}
