/**
 * @file udn_stress.cpp
 * @brief udn_stress: options, the raw run (checked traffic through the raw API), JSON report, exit statuses.
 */
#include "tools/common/udn_stress/udn_stress.hpp"

#include "bsp_tile64/emu/board.hpp"
#include "bsp_tile64/emu/rng.hpp"
#include "kernel/kernel.hpp"
#include "tools/common/cli_checks.hpp"
#include "tools/common/udn_stress/udn_stress_payload.hpp"
#include "tools/common/udn_stress/udn_stress_plan.hpp"
#include "udn/ft_link.hpp"
#include "udn/raw.hpp"

#include <array>
#include <cmath>
#include <iomanip>
#include <map>
#include <memory>
#include <span>
#include <type_traits>

namespace tools {
namespace {

constexpr std::uint32_t kTag = 0x5755U;
constexpr std::uint32_t kStackBytes = 16U * 1024U;

using PerTile = std::array<std::uint64_t, bsp::kMaxTiles>;

/** What the tasks of every tile read and count: the plan is fixed before the run, counters per tile. */
struct Shared {
  StressOptions opts;
  detail::TrafficPlan plan;
  PerTile sent{};
  PerTile errors{};
  PerTile received{};  ///< every packet the receiver read, whatever its state
  PerTile corrupted{};
  PerTile misdelivered{};
  PerTile duplicated{};
  PerTile misordered{};
  /** [source][receiver]: 0 before the first intact packet, else 0x10000 | its packet number. */
  std::array<std::array<std::uint32_t, bsp::kMaxTiles>, bsp::kMaxTiles> last{};
};
Shared g_shared;

void sender(void* /*arg*/) {
  const bsp::TileId self = bsp::current_tile();
  if (udn::activate() != udn::RawError::kOk) {
    return;
  }
  bsp::Rng rng(g_shared.opts.seed, bsp::StreamId::kTraffic, self);
  const double mean_gap_cycles =
      static_cast<double>(g_shared.plan.profile.clock_hz) / 1e6 / g_shared.opts.rate_per_us;
  std::array<std::uint32_t, udn::kMaxDataWords> data{};
  const std::span<std::uint32_t> payload(data.data(), g_shared.opts.words);
  for (std::uint64_t i = 0; i < g_shared.plan.quota[self]; ++i) {
    // Exponential gaps (a Poisson source), counted from the end of the previous send.
    const double gap = -std::log(1.0 - rng.uniform()) * mean_gap_cycles;
    bsp::consume(static_cast<bsp::Cycles>(gap) + 1U);
    const bsp::TileId dest = detail::pick_destination(g_shared.plan, rng, self);
    stamp_payload(PayloadStamp{self, dest, static_cast<std::uint16_t>(i)}, payload);
    if (udn::send(dest, kTag, payload, k::kForever) == udn::RawError::kOk) {
      ++g_shared.sent[self];
    } else {
      ++g_shared.errors[self];
    }
  }
  for (;;) {
    k::sleep(1'000'000U);
  }
}

/** Order of the intact packets of one (source, receiver) pair: the network keeps it. Needs packet numbers. */
void check_order(const PayloadStamp& st, bsp::TileId self) {
  if (g_shared.opts.words < 2U) {
    return;  // a one-word payload has no packet number
  }
  std::uint32_t& last = g_shared.last[st.source][self];
  const auto ahead = static_cast<std::uint16_t>(st.number - static_cast<std::uint16_t>(last));
  if (last != 0U && ahead == 0U) {
    ++g_shared.duplicated[self];
  } else if (last != 0U && ahead >= 0x8000U) {
    ++g_shared.misordered[self];
  } else {
    last = 0x10000U | st.number;
  }
}

void receiver(void* /*arg*/) {
  const bsp::TileId self = bsp::current_tile();
  if (udn::activate() != udn::RawError::kOk) {
    return;
  }
  std::array<std::uint32_t, udn::kMaxDataWords> data{};
  for (;;) {
    udn::RxInfo info{};
    if (udn::receive(udn::kCatchAll, info, data, k::kForever) != udn::RawError::kOk) {
      continue;
    }
    ++g_shared.received[self];
    const std::size_t n = info.data_words < data.size() ? info.data_words : data.size();
    PayloadStamp st{};
    // A flipped tag is corruption too: it would pick another demux queue had any tag been bound.
    const PayloadVerdict v = info.tag != kTag ? PayloadVerdict::kCorrupted
                                              : check_payload(std::span(data.data(), n), info.data_words,
                                                              g_shared.opts.words, info.source, self, st);
    switch (v) {
      case PayloadVerdict::kCorrupted:
        ++g_shared.corrupted[self];
        break;
      case PayloadVerdict::kMisdelivered:
        ++g_shared.misdelivered[self];
        break;
      case PayloadVerdict::kIntact:
        check_order(st, self);
        break;
    }
  }
}

// The receiver is more urgent: it preempts the sender's gaps as soon as a packet lands.
constexpr k::TaskSpec kTasks[] = {
    {"udn_rx", &receiver, nullptr, 2, 0, 0, kStackBytes, k::Policy::kPreemptive},
    {"udn_tx", &sender, nullptr, 3, 0, 0, kStackBytes, k::Policy::kPreemptive},
};
static_assert(k::check_table(kTasks) == k::TableError::kOk);

std::uint64_t sum(const PerTile& a) {
  std::uint64_t s = 0U;
  for (const std::uint64_t v : a) {
    s += v;
  }
  return s;
}

/** Every packet sent or refused, none in flight, and each one that left the network read or counted lost. */
bool all_done(void* /*arg*/) {
  const std::uint64_t sent = sum(g_shared.sent);
  return sent + sum(g_shared.errors) == g_shared.opts.packets && bsp::udn_net_in_flight() == 0U &&
         sum(g_shared.received) + bsp::udn_net_stats().lost_total() == sent;
}

void collect(StressResult& r) {
  StressResult::Delivery& d = r.delivery;
  d.sent = sum(g_shared.sent);
  d.delivered = sum(g_shared.received);
  d.lost = d.sent > d.delivered ? d.sent - d.delivered : 0U;
  d.duplicated = sum(g_shared.duplicated);
  d.misordered = sum(g_shared.misordered);
  d.corrupted_delivered = sum(g_shared.corrupted);
  d.misdelivered = sum(g_shared.misdelivered);
  r.send_errors = sum(g_shared.errors);
}

std::string option_checks(const StressOptions& opts) {
  if (opts.ft && opts.words > udn::kFtMaxData) {
    return "--words " + std::to_string(opts.words) + ": the fault-tolerant layer carries at most " +
           std::to_string(udn::kFtMaxData) + " data words (--ft on)";
  }
  if (detail::make_plan(opts).sender_count == 0U) {
    return std::string("--failed-tiles") + (opts.ft ? "/--failed-switches" : "") + ": no tile is left to run traffic";
  }
  return "";
}

template <typename T>
void write_list(std::ostream& out, const char* key, const std::vector<T>& items) {
  out << ",\"" << key << "\":[";
  for (std::size_t i = 0; i < items.size(); ++i) {
    out << (i == 0U ? "" : ",");
    if constexpr (std::is_same_v<T, std::string>) {
      out << '"' << items[i] << '"';
    } else {
      out << items[i];
    }
  }
  out << ']';
}

}  // namespace

const char* pattern_name(TrafficPattern p) {
  switch (p) {
    case TrafficPattern::kTranspose:
      return "transpose";
    case TrafficPattern::kHotspot:
      return "hotspot";
    case TrafficPattern::kUniform:
      break;
  }
  return "uniform";
}

void add_stress_options(CLI::App& app, StressOptions& opts) {
  static const std::map<std::string, TrafficPattern> kPatterns{
      {"uniform", TrafficPattern::kUniform}, {"transpose", TrafficPattern::kTranspose}, {"hotspot", TrafficPattern::kHotspot}};
  app.add_option_function<std::string>(
         "--pattern", [&opts](const std::string& v) { opts.pattern = kPatterns.at(v); },
         "Traffic pattern: uniform, transpose or hotspot")
      ->check(CLI::IsMember({"uniform", "transpose", "hotspot"}));
  app.add_option("--rate", opts.rate_per_us, "Packets per tile per microsecond of emulated time")
      ->check(CLI::Range(1e-6, 10.0));
  app.add_option("--packets", opts.packets, "Total packets over all tiles")->check(CLI::Range(1, 10'000'000));
  app.add_option("--words", opts.words, "Data words per packet (1..128; 1..124 with --ft on)")
      ->check(CLI::Range(1U, udn::kMaxDataWords));
  app.add_option("--seed", opts.seed, "Run seed (traffic, faults)")->check(kWholeNumber);
  app.add_option("--failed-switches", opts.failed_switches,
                 "Tile indices whose switch fails at t=0, comma-separated (both modes; with --ft on those tiles "
                 "also run nothing)")
      ->delimiter(',')
      ->check(kWholeNumber);
  app.add_option("--profile", opts.profile, "Chip profile: tile64 (8x8) or maestro (7x7)")
      ->check(CLI::IsMember({"tile64", "maestro"}));
  app.add_option("--max-ms", opts.max_ms,
                 "Bound on emulated milliseconds (default: 1000 plus twice what the busiest tile needs at --rate)")
      ->check(CLI::Range(0.001, 1e6));
  app.add_option("--quantum-us", opts.quantum_us, "Board quantum in microseconds (1..1000): delivery granularity")
      ->check(CLI::Range(1.0, 1000.0));
  app.add_option_function<std::string>(
         "--ft", [&opts](const std::string& v) { opts.ft = v == "on"; },
         "on: traffic through the fault-tolerant layer (ECC, retransmission, virtual routing); off: raw")
      ->check(CLI::IsMember({"on", "off"}));
  app.add_option("--ber", opts.ber, "Probability of a bit flip per word in transit (both modes)")
      ->check(CLI::Range(0.0, 0.1));
  app.add_option("--failed-tiles", opts.failed_tiles,
                 "Tiles that run nothing, are sent nothing and whose switch fails at t=0 (both modes)")
      ->delimiter(',')
      ->check(kWholeNumber);
  app.add_option("--failed-links", opts.failed_links,
                 "Failed links at t=0: 12E (leaving tile 12 eastwards; E W N S) or 12-13; both directions")
      ->delimiter(',');
  app.footer(
      "Exit status: 0 every packet delivered or lost within the bound; 1 internal error (the board, the network\n"
      "or a fault could not be set up); 2 bad arguments, or an option the chosen mode cannot use (a message names\n"
      "it); 3 stopped by the --max-ms bound (or the derived one) first: one line on stderr, the JSON object all the\n"
      "same.");
}

std::string validate_stress_options(const StressOptions& opts) {
  const bsp::ChipProfile& p = detail::profile_named(opts.profile);
  for (const std::uint32_t t : opts.failed_switches) {
    if (t >= p.tiles()) {
      return "--failed-switches: tile " + std::to_string(t) + " is outside the " + std::to_string(p.cols) + "x" +
             std::to_string(p.rows) + " grid (0.." + std::to_string(p.tiles() - 1U) + ")";
    }
  }
  for (const std::uint32_t t : opts.failed_tiles) {
    if (t >= p.tiles()) {
      return "--failed-tiles: tile " + std::to_string(t) + " is outside the grid";
    }
  }
  for (const std::string& l : opts.failed_links) {
    LinkSpec spec{};
    const std::string m = parse_link(l, p.cols, p.rows, spec);
    if (!m.empty()) {
      return "--failed-links: " + m;
    }
  }
  return option_checks(opts);
}

std::string parse_link(const std::string& text, std::uint32_t cols, std::uint32_t rows, LinkSpec& out) {
  std::size_t used = 0U;
  unsigned long a = 0U;
  try {
    a = std::stoul(text, &used);
  } catch (const std::exception&) {
    return "'" + text + "' does not start with a tile index";
  }
  const std::string rest = text.substr(used);
  if (a >= static_cast<unsigned long>(cols) * rows) {
    return "'" + text + "': tile outside the grid";
  }
  out.tile = static_cast<std::uint32_t>(a);
  const std::uint32_t x = out.tile % cols;
  const std::uint32_t y = out.tile / cols;
  if (rest.size() > 1U && rest[0] == '-') {
    unsigned long b = 0U;
    try {
      b = std::stoul(rest.substr(1U), &used);
    } catch (const std::exception&) {
      return "'" + text + "': no tile after '-'";
    }
    if (used + 1U != rest.size()) {
      return "'" + text + "': trailing characters";
    }
    const std::map<unsigned long, bsp::UdnDir> next{{a + 1U, bsp::UdnDir::kEast}, {a - 1U, bsp::UdnDir::kWest},
                                                    {a - cols, bsp::UdnDir::kNorth}, {a + cols, bsp::UdnDir::kSouth}};
    const auto it = next.find(b);
    if (it == next.end() || b >= static_cast<unsigned long>(cols) * rows ||
        (it->second == bsp::UdnDir::kEast && x + 1U >= cols) || (it->second == bsp::UdnDir::kWest && x == 0U)) {
      return "'" + text + "': not neighbours";
    }
    out.dir = it->second;
    return "";
  }
  const std::map<std::string, bsp::UdnDir> dirs{
      {"E", bsp::UdnDir::kEast}, {"W", bsp::UdnDir::kWest}, {"N", bsp::UdnDir::kNorth}, {"S", bsp::UdnDir::kSouth}};
  const auto it = dirs.find(rest);
  if (it == dirs.end()) {
    return "'" + text + "': expected E, W, N, S or -<tile> after the tile";
  }
  out.dir = it->second;
  const bool on_grid = (out.dir == bsp::UdnDir::kEast && x + 1U < cols) || (out.dir == bsp::UdnDir::kWest && x > 0U) ||
                       (out.dir == bsp::UdnDir::kNorth && y > 0U) || (out.dir == bsp::UdnDir::kSouth && y + 1U < rows);
  return on_grid ? "" : "'" + text + "': the link leaves the grid";
}

int parse_stress_args(int argc, const char* const* argv, StressOptions& opts, std::string& message) {
  CLI::App app{"udn_stress: synthetic traffic on the emulated UDN mesh; prints one JSON object"};
  add_stress_options(app, opts);
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp&) {
    message = app.help();
    return 0;
  } catch (const CLI::ParseError& e) {
    message = e.what();
    return 2;
  }
  message = validate_stress_options(opts);
  return message.empty() ? -1 : 2;
}

StressResult run_stress(const StressOptions& opts, bsp::heap::SealMode seal) {
  if (opts.ft) {
    return run_stress_ft(opts, seal);
  }
  StressResult r;
  std::destroy_at(&g_shared);  // in place: no temporary of the whole state on the stack
  std::construct_at(&g_shared);
  g_shared.opts = opts;
  g_shared.plan = detail::make_plan(opts);
  if (g_shared.plan.sender_count == 0U || !detail::boot_stress_board(opts, g_shared.plan, kTasks, bsp::NetConfig{})) {
    return r;
  }
  detail::run_stress_board(opts, g_shared.plan, &all_done, seal, r);
  collect(r);
  return r;
}

void write_stress_json(std::ostream& out, const StressOptions& opts, const StressResult& r) {
  const bsp::NetStats& s = r.net;
  const StressResult::Delivery& d = r.delivery;
  const StressResult::Ft& f = r.ft;
  const auto lost = [&s](bsp::UdnLoss c) { return s.lost[static_cast<std::size_t>(c)]; };
  out << std::setprecision(9) << "{\"profile\":\"" << opts.profile << "\",\"pattern\":\"" << pattern_name(opts.pattern)
      << "\",\"rate_per_us\":" << opts.rate_per_us << ",\"packets\":" << opts.packets << ",\"words\":" << opts.words
      << ",\"seed\":" << opts.seed << ",\"quantum_us\":" << opts.quantum_us
      << ",\"ft\":" << (opts.ft ? "true" : "false") << ",\"ber\":" << opts.ber;
  write_list(out, "failed_switches", opts.failed_switches);
  write_list(out, "failed_tiles", opts.failed_tiles);
  write_list(out, "failed_links", opts.failed_links);
  out << ",\"bound_ms\":" << r.bound_ms << ",\"completed\":" << (r.completed() ? "true" : "false")
      << ",\"sent\":" << d.sent << ",\"delivered\":" << d.delivered << ",\"lost\":" << d.lost
      << ",\"duplicated\":" << d.duplicated << ",\"misordered\":" << d.misordered
      << ",\"corrupted_delivered\":" << d.corrupted_delivered << ",\"misdelivered\":" << d.misdelivered
      << ",\"corrected\":" << f.corrected << ",\"forwarded\":" << f.forwarded
      << ",\"retransmitted\":" << f.retransmitted << ",\"uncorrectable_detected\":" << f.uncorrectable_detected
      << ",\"gave_up\":" << f.gave_up << ",\"gave_up_not_delivered\":" << f.gave_up_not_delivered
      << ",\"gave_up_not_delivered_arrived\":" << f.gave_up_not_delivered_arrived
      << ",\"gave_up_unknown\":" << f.gave_up_unknown << ",\"gave_up_unknown_arrived\":" << f.gave_up_unknown_arrived
      << ",\"acks_lost\":" << f.acks_lost << ",\"acks_lost_missing\":" << f.acks_lost_missing
      << ",\"unmatched\":" << f.unmatched
      << ",\"unreachable\":" << f.unreachable << ",\"send_errors\":" << r.send_errors << ",\"net_sent\":" << s.sent
      << ",\"net_delivered\":" << s.delivered << ",\"bit_flips\":" << s.bit_flips
      << ",\"lost_offgrid\":" << lost(bsp::UdnLoss::kOffGrid)
      << ",\"lost_failed_switch\":" << lost(bsp::UdnLoss::kFailedSwitch)
      << ",\"lost_failed_link\":" << lost(bsp::UdnLoss::kFailedLink)
      << ",\"lost_bad_length\":" << lost(bsp::UdnLoss::kBadLength) << ",\"refused_full\":" << s.refused_full
      << ",\"queue_full_retries\":" << s.queue_full_retries << ",\"latency_cycles_min\":" << s.latency_min
      << ",\"latency_cycles_mean\":" << s.latency_mean() << ",\"latency_cycles_max\":" << s.latency_max
      << ",\"link_utilisation_mean\":" << r.link_utilisation_mean
      << ",\"link_utilisation_max\":" << r.link_utilisation_max
      << ",\"emulated_s\":" << r.emulated_s << ",\"host_s\":" << r.host_s << ",\"packets_per_host_s\":"
      << (r.host_s > 0.0 ? static_cast<double>(s.sent) / r.host_s : 0.0)
      << ",\"heap_allocs_during_run\":" << r.heap_allocs_during_run << "}\n";
}

int stress_main(int argc, const char* const* argv, std::ostream& out, std::ostream& err) {
  StressOptions opts;
  std::string message;
  const int rc = parse_stress_args(argc, argv, opts, message);
  if (rc == 0) {
    out << message;
    return kExitCompleted;
  }
  if (rc > 0) {
    err << "udn_stress: " << message << "\nRun with --help for the options.\n";
    return kExitBadArguments;
  }
  const StressResult r = run_stress(opts, bsp::heap::SealMode::kFatal);
  if (r.end == StressEnd::kSetupFailed) {
    err << "udn_stress: the board, the network or a fault could not be set up; nothing ran\n";
    return kExitInternal;
  }
  write_stress_json(out, opts, r);
  if (r.end == StressEnd::kBound) {
    const char* what = opts.ft ? "messages" : "packets";
    err << "udn_stress: stopped by the bound of " << r.bound_ms << " emulated ms ("
        << (opts.max_ms > 0.0 ? "--max-ms" : "derived from --rate and --packets; raise it with --max-ms") << "): "
        << r.delivery.sent << " of " << opts.packets << " " << what << " sent, " << r.delivery.delivered
        << " delivered\n";
    return kExitBound;
  }
  return kExitCompleted;
}

}  // namespace tools
