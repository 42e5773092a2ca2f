/**
 * @file main.cpp
 * @brief udn_stress: synthetic traffic on the emulated UDN; one JSON object of statistics on stdout.
 *
 * Exit statuses: tools::kExitCompleted, kExitInternal, kExitBadArguments, kExitBound (see --help).
 */
#include "tools/common/udn_stress/udn_stress.hpp"

#include <cstdio>
#include <exception>
#include <iostream>

int main(int argc, char** argv) {
  try {
    return tools::stress_main(argc, argv, std::cout, std::cerr);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "udn_stress: %s\n", e.what());
    return tools::kExitInternal;
  }
}
