/**
 * @file udn_stress.hpp
 * @brief The udn_stress image as a library: command line, traffic run on booted kernels, JSON report.
 *
 * Kept apart from tools/udn_stress/main.cpp so tests can check the parser, the
 * run and the report without the binary, and so the fault-tolerant layer can
 * add its options (add_stress_options() takes the CLI11 app) and its own
 * report fields later.
 */
#pragma once

#include "bsp_tile64/host/heap_guard.hpp"
#include "bsp_tile64/udn_net.hpp"

#include <CLI/CLI.hpp>

#include <cstdint>
#include <ostream>
#include <string>
#include <vector>

namespace tools {

enum class TrafficPattern : std::uint8_t {
  kUniform,    ///< every other tile equally likely
  kTranspose,  ///< (x, y) -> (y, x); diagonal tiles send to themselves (ejection port only)
  kHotspot,    ///< a quarter of the packets to the centre tile (cols/2, rows/2), the rest uniform
};

struct StressOptions {
  TrafficPattern pattern = TrafficPattern::kUniform;
  double rate_per_us = 0.01;      ///< packets per tile per microsecond of emulated time
  std::uint64_t packets = 6400U;  ///< total over all tiles
  std::uint32_t words = 8U;       ///< data words per packet
  std::uint64_t seed = 1U;
  std::vector<std::uint32_t> failed_switches;
  std::string profile = "tile64";
  double max_ms = 1000.0;  ///< emulated-time bound of the run
  double quantum_us = 1.0;  ///< board quantum: software sees a packet at most this long after it arrives
};

/** Registers the udn_stress options on @p app, writing into @p opts (extensible by later layers). */
void add_stress_options(CLI::App& app, StressOptions& opts);

/** Checks what CLI11 cannot: tile indices against the profile's grid. @return "" or the message. */
std::string validate_stress_options(const StressOptions& opts);

/**
 * Parses a command line. @return -1 to go on with the run, 0 after --help
 * (@p message holds the help text), 2 for bad arguments (@p message says why).
 */
int parse_stress_args(int argc, const char* const* argv, StressOptions& opts, std::string& message);

struct StressResult {
  bsp::NetStats net{};
  std::uint64_t sent_by_tasks = 0U;  ///< sends the sender tasks completed
  std::uint64_t received = 0U;       ///< packets the receiver tasks read
  std::uint64_t send_errors = 0U;    ///< sends that returned an error
  bool completed = false;            ///< every packet delivered or lost before the bound
  double emulated_s = 0.0;
  double host_s = 0.0;  ///< host wall time of the run (tool side only, never fed back)
  double link_utilisation_mean = 0.0;
  double link_utilisation_max = 0.0;
  std::uint64_t heap_allocs_during_run = 0U;
};

/** Boots a kernel with a sender and a receiver task on every tile and runs the traffic. */
StressResult run_stress(const StressOptions& opts, bsp::heap::SealMode seal);

/** Writes the result as one JSON object (and a newline). */
void write_stress_json(std::ostream& out, const StressOptions& opts, const StressResult& r);

const char* pattern_name(TrafficPattern p);

}  // namespace tools
