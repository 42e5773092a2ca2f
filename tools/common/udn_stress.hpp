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
  // Fault-tolerant layer (udn/ft_link.hpp), see docs/FT_MESSAGING.md.
  bool ft = false;                           ///< --ft on: traffic through the fault-tolerant layer
  double ber = 0.0;                          ///< bit flip probability per word in transit
  std::vector<std::uint32_t> failed_tiles;   ///< tiles that run nothing and whose switch fails at t=0
  std::vector<std::string> failed_links;     ///< "12E" (link leaving 12 eastwards) or "12-13"; both directions
};

/** One parsed --failed-links entry: the link leaving tile in dir (both directions fail). */
struct LinkSpec {
  std::uint32_t tile = 0U;
  bsp::UdnDir dir = bsp::UdnDir::kEast;
};

/** Parses "12E"/"12W"/"12N"/"12S" or "12-13" on a cols x rows grid. @return "" or the message. */
std::string parse_link(const std::string& text, std::uint32_t cols, std::uint32_t rows, LinkSpec& out);

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
  /** --ft on only: the fault-tolerant layer's view (messages, not packets). */
  struct Ft {
    std::uint64_t sent = 0U;       ///< messages accepted by ft_send
    std::uint64_t delivered = 0U;  ///< messages handed to the receivers
    std::uint64_t corrected = 0U;
    std::uint64_t forwarded = 0U;
    std::uint64_t retransmitted = 0U;
    std::uint64_t uncorrectable_detected = 0U;
    std::uint64_t lost = 0U;        ///< sent, never delivered, whether reported (gave_up) or not
    std::uint64_t gave_up = 0U;     ///< given up after retries, each an event
    std::uint64_t duplicated = 0U;
    std::uint64_t misordered = 0U;
    std::uint64_t corrupted_delivered = 0U;
    std::uint64_t unreachable = 0U;  ///< sends refused for lack of a route
  } ft{};
};

/** The --ft on run: a fault-tolerant driver task per working tile (tools/common/udn_stress_ft.cpp). */
StressResult run_stress_ft(const StressOptions& opts, bsp::heap::SealMode seal);

/** Boots a kernel with a sender and a receiver task on every tile and runs the traffic. */
StressResult run_stress(const StressOptions& opts, bsp::heap::SealMode seal);

/** Writes the result as one JSON object (and a newline). */
void write_stress_json(std::ostream& out, const StressOptions& opts, const StressResult& r);

const char* pattern_name(TrafficPattern p);

}  // namespace tools
