/**
 * @file udn_stress.hpp
 * @brief The udn_stress image as a library: command line, traffic run on booted kernels, JSON report.
 *
 * Kept apart from tools/udn_stress/main.cpp so tests can check the parser, the
 * runs, the report and the exit statuses without the binary. Two runs share
 * the options, the traffic plan (udn_stress_plan.hpp), the payload check
 * (udn_stress_payload.hpp) and the report's keys: the raw run (this file's
 * run_stress) and the --ft on run (udn_stress_ft.cpp).
 */
#pragma once

#include "bsp_tile64/emu/host/heap_guard.hpp"
#include "bsp_tile64/emu/udn_net.hpp"

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
  double max_ms = 0.0;      ///< emulated-time bound of the run; 0: derived (bound_ms())
  double quantum_us = 1.0;  ///< board quantum: software sees a packet at most this long after it arrives
  // Faults, in both modes; the fault-tolerant layer (udn/ft_link.hpp) is docs/FT_MESSAGING.md.
  bool ft = false;                           ///< --ft on: traffic through the fault-tolerant layer
  double ber = 0.0;                          ///< bit flip probability per word in transit
  std::vector<std::uint32_t> failed_tiles;   ///< tiles that run nothing and whose switch fails at t=0
  std::vector<std::string> failed_links;     ///< "12E" (link leaving 12 eastwards) or "12-13"; both directions
};

/** Exit statuses of the udn_stress image (listed in --help). */
inline constexpr int kExitCompleted = 0;     ///< every packet delivered or lost before the bound
inline constexpr int kExitInternal = 1;      ///< the board or the network could not be set up, or an exception
inline constexpr int kExitBadArguments = 2;  ///< a message on stderr says which option
inline constexpr int kExitBound = 3;         ///< stopped by the --max-ms bound (or the derived one) first

/** One parsed --failed-links entry: the link leaving tile in dir (both directions fail). */
struct LinkSpec {
  std::uint32_t tile = 0U;
  bsp::UdnDir dir = bsp::UdnDir::kEast;
};

/** Parses "12E"/"12W"/"12N"/"12S" or "12-13" on a cols x rows grid. @return "" or the message. */
std::string parse_link(const std::string& text, std::uint32_t cols, std::uint32_t rows, LinkSpec& out);

/** Registers the udn_stress options on @p app, writing into @p opts (extensible by later layers). */
void add_stress_options(CLI::App& app, StressOptions& opts);

/**
 * Checks what CLI11 cannot: tile indices against the profile's grid, options
 * whose values the chosen mode cannot use (--words above udn::kFtMaxData with
 * --ft on), and that some tile is left to send. @return "" or the message,
 * which names the option.
 */
std::string validate_stress_options(const StressOptions& opts);

/**
 * Parses a command line. @return -1 to go on with the run, 0 after --help
 * (@p message holds the help text), 2 for bad arguments (@p message says why).
 */
int parse_stress_args(int argc, const char* const* argv, StressOptions& opts, std::string& message);

/**
 * The whole image: parses, runs, writes the JSON object to @p out and any
 * message to @p err (one line when the bound stops the run).
 * @return kExitCompleted, kExitInternal, kExitBadArguments or kExitBound.
 */
int stress_main(int argc, const char* const* argv, std::ostream& out, std::ostream& err);

/** How a run ended. */
enum class StressEnd : std::uint8_t {
  kCompleted,    ///< every packet delivered or lost before the bound
  kBound,        ///< the emulated-time bound came first
  kSetupFailed,  ///< the board, the network or a fault could not be set up (nothing ran)
};

struct StressResult {
  StressEnd end = StressEnd::kSetupFailed;
  double bound_ms = 0.0;  ///< the emulated-time bound the run had (given or derived)
  bsp::NetStats net{};
  std::uint64_t send_errors = 0U;  ///< raw sends that returned an error
  double emulated_s = 0.0;
  double host_s = 0.0;  ///< host wall time of the run (tool side only, never fed back)
  double link_utilisation_mean = 0.0;
  double link_utilisation_max = 0.0;
  std::uint64_t heap_allocs_during_run = 0U;
  /**
   * What the traffic's own receivers saw, measured the same way in both modes
   * (packets without --ft, messages with it): every payload is checked against
   * what its sender wrote (udn_stress_payload.hpp).
   */
  struct Delivery {
    std::uint64_t sent = 0U;                 ///< sends accepted (raw send, ft_send)
    std::uint64_t delivered = 0U;            ///< handed to a receiver, whatever its state
    std::uint64_t lost = 0U;                 ///< sent, never received where it was sent to
    std::uint64_t duplicated = 0U;           ///< received again
    std::uint64_t misordered = 0U;           ///< received before an earlier one of its stream
    std::uint64_t corrupted_delivered = 0U;  ///< received with a payload or a length not as sent
    std::uint64_t misdelivered = 0U;         ///< received intact at another tile than its destination
  } delivery{};
  /** The fault-tolerant layer's counters (--ft on; zero in a raw run, which has no such layer). */
  struct Ft {
    std::uint64_t corrected = 0U;
    std::uint64_t forwarded = 0U;
    std::uint64_t retransmitted = 0U;
    std::uint64_t uncorrectable_detected = 0U;
    std::uint64_t gave_up = 0U;      ///< given up after retries, each an event
    std::uint64_t unreachable = 0U;  ///< sends refused for lack of a route
    // The messages given up, by what the layer's events said of each last (a give-up of unknown
    // delivery may be settled later), and checked against the receivers:
    std::uint64_t gave_up_not_delivered = 0U;          ///< reported not delivered
    std::uint64_t gave_up_not_delivered_arrived = 0U;  ///< ... that arrived all the same (a wrong claim)
    std::uint64_t gave_up_unknown = 0U;                ///< reported with delivery unknown
    std::uint64_t gave_up_unknown_arrived = 0U;        ///< ... that arrived (a false alarm, said to be uncertain)
    std::uint64_t acks_lost = 0U;                      ///< reported delivered, only the ACKs lost
    std::uint64_t acks_lost_missing = 0U;              ///< ... that never arrived (a wrong claim)
    std::uint64_t unmatched = 0U;  ///< give-up events and deliveries the run could not match to a message
  } ft{};
  [[nodiscard]] bool completed() const noexcept { return end == StressEnd::kCompleted; }
};

/** The emulated-time bound of a run in ms: --max-ms, or 1 s plus twice what the traffic needs at its rate. */
double bound_ms(const StressOptions& opts);

/** The --ft on run: a fault-tolerant driver task per working tile (tools/common/udn_stress/udn_stress_ft.cpp). */
StressResult run_stress_ft(const StressOptions& opts, bsp::heap::SealMode seal);

/**
 * Runs the traffic of @p opts: with opts.ft, run_stress_ft(); otherwise a
 * kernel with a sender and a receiver task on every tile but the failed ones,
 * through the raw API, with the bit errors and failures asked for.
 */
StressResult run_stress(const StressOptions& opts, bsp::heap::SealMode seal);

/** Writes the result as one JSON object (and a newline). */
void write_stress_json(std::ostream& out, const StressOptions& opts, const StressResult& r);

const char* pattern_name(TrafficPattern p);

}  // namespace tools
