/**
 * @file udn_stress.cpp
 * @brief udn_stress: option parsing, synthetic traffic on every tile through the raw API, JSON report.
 */
#include "tools/common/udn_stress.hpp"

#include "bsp_tile64/board.hpp"
#include "bsp_tile64/fault_injector.hpp"
#include "bsp_tile64/rng.hpp"
#include "kernel/kernel.hpp"
#include "udn/raw.hpp"

#include <array>
#include <chrono>
#include <cmath>
#include <iomanip>
#include <map>
#include <span>

namespace tools {
namespace {

constexpr std::uint32_t kTag = 0x5755U;
constexpr std::uint32_t kStackBytes = 16U * 1024U;

/** What the tasks of every tile read: written before the run, read-only during it. */
struct Shared {
  StressOptions opts;
  bsp::ChipProfile profile = bsp::kTile64;
  std::array<std::uint64_t, bsp::kMaxTiles> quota{};
  std::array<std::uint64_t, bsp::kMaxTiles> sent{};
  std::array<std::uint64_t, bsp::kMaxTiles> received{};
  std::array<std::uint64_t, bsp::kMaxTiles> errors{};
};
Shared g_shared;

const bsp::ChipProfile& profile_named(const std::string& name) {
  return name == "maestro" ? bsp::kMaestro : bsp::kTile64;
}

bsp::TileId uniform_other(bsp::Rng& rng, bsp::TileId self, std::uint32_t tiles) {
  const auto d = static_cast<bsp::TileId>(rng.below(tiles - 1U));
  return d >= self ? d + 1U : d;
}

bsp::TileId pick_destination(bsp::Rng& rng, bsp::TileId self) {
  const bsp::ChipProfile& p = g_shared.profile;
  const std::uint32_t tiles = p.tiles();
  switch (g_shared.opts.pattern) {
    case TrafficPattern::kTranspose:
      return (self % p.cols) * p.cols + self / p.cols;  // grids are square
    case TrafficPattern::kHotspot: {
      const bsp::TileId hot = (p.rows / 2U) * p.cols + p.cols / 2U;
      if (rng.below(4U) == 0U && hot != self) {
        return hot;
      }
      return uniform_other(rng, self, tiles);
    }
    case TrafficPattern::kUniform:
      break;
  }
  return uniform_other(rng, self, tiles);
}

void sender(void* /*arg*/) {
  const bsp::TileId self = bsp::current_tile();
  if (udn::activate() != udn::RawError::kOk) {
    return;
  }
  bsp::Rng rng(g_shared.opts.seed, bsp::StreamId::kTraffic, self);
  const double mean_gap_cycles =
      static_cast<double>(g_shared.profile.clock_hz) / 1e6 / g_shared.opts.rate_per_us;
  std::array<std::uint32_t, udn::kMaxDataWords> data{};
  const std::span<const std::uint32_t> payload(data.data(), g_shared.opts.words);
  for (std::uint64_t i = 0; i < g_shared.quota[self]; ++i) {
    // Exponential gaps (a Poisson source), counted from the end of the previous send.
    const double gap = -std::log(1.0 - rng.uniform()) * mean_gap_cycles;
    bsp::consume(static_cast<bsp::Cycles>(gap) + 1U);
    const bsp::TileId dest = pick_destination(rng, self);
    data[0] = self;
    data[1] = static_cast<std::uint32_t>(i);
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

void receiver(void* /*arg*/) {
  const bsp::TileId self = bsp::current_tile();
  if (udn::activate() != udn::RawError::kOk) {
    return;
  }
  std::array<std::uint32_t, udn::kMaxDataWords> data{};
  for (;;) {
    udn::RxInfo info{};
    if (udn::receive(udn::kCatchAll, info, data, k::kForever) == udn::RawError::kOk) {
      ++g_shared.received[self];
    }
  }
}

// The receiver is more urgent: it preempts the sender's gaps as soon as a packet lands.
constexpr k::TaskSpec kTasks[] = {
    {"udn_rx", &receiver, nullptr, 2, 0, 0, kStackBytes, k::Policy::kPreemptive},
    {"udn_tx", &sender, nullptr, 3, 0, 0, kStackBytes, k::Policy::kPreemptive},
};
static_assert(k::check_table(kTasks) == k::TableError::kOk);

std::uint64_t sum(const std::array<std::uint64_t, bsp::kMaxTiles>& a) {
  std::uint64_t s = 0U;
  for (const std::uint64_t v : a) {
    s += v;
  }
  return s;
}

bool all_done(void* /*arg*/) {
  const std::uint64_t finished = sum(g_shared.sent) + sum(g_shared.errors);
  return finished == g_shared.opts.packets && bsp::udn_net_in_flight() == 0U;
}

bool boot_board(const StressOptions& opts) {
  g_shared = Shared{};
  g_shared.opts = opts;
  g_shared.profile = profile_named(opts.profile);
  const bsp::ChipProfile& p = g_shared.profile;
  bsp::BoardConfig cfg = bsp::default_config(p);
  const auto quantum = static_cast<bsp::Cycles>(opts.quantum_us * static_cast<double>(p.clock_hz) / 1e6);
  cfg.quantum_cycles = quantum < 1U ? 1U : (quantum > cfg.tick_cycles ? cfg.tick_cycles : quantum);
  cfg.seed = opts.seed;
  cfg.monitor_tile = bsp::kNoTile;
  for (bsp::TileId t = 0; t < p.tiles(); ++t) {
    cfg.boot[t] = &k::boot_entry;
    k::set_task_table(t, kTasks, cfg.tick_cycles);
    g_shared.quota[t] = opts.packets / p.tiles() + (t < opts.packets % p.tiles() ? 1U : 0U);
  }
  if (bsp::board_init(cfg) != bsp::BoardError::kOk || bsp::udn_net_init(bsp::NetConfig{}) != bsp::NetError::kOk) {
    return false;
  }
  for (const std::uint32_t t : opts.failed_switches) {
    bsp::FaultSpec f{};
    f.kind = bsp::FaultKind::kSwitchFail;
    f.tile = t;
    if (bsp::fault_plan_add(f) != bsp::FaultError::kOk) {
      return false;
    }
  }
  return true;
}

void link_utilisation(StressResult& r, bsp::Cycles elapsed) {
  const bsp::ChipProfile& p = g_shared.profile;
  double total = 0.0;
  std::uint32_t links = 0U;
  for (bsp::TileId t = 0; t < p.tiles(); ++t) {
    const std::uint32_t x = t % p.cols;
    const std::uint32_t y = t / p.cols;
    const std::array<bool, bsp::kUdnDirs> exists{x + 1U < p.cols, x > 0U, y > 0U, y + 1U < p.rows};
    for (std::uint32_t d = 0; d < bsp::kUdnDirs; ++d) {
      if (!exists[d] || elapsed == 0U) {
        continue;
      }
      const double u = static_cast<double>(bsp::udn_link_busy_cycles(t, static_cast<bsp::UdnDir>(d))) /
                       static_cast<double>(elapsed);
      total += u;
      r.link_utilisation_max = std::max(r.link_utilisation_max, u);
      ++links;
    }
  }
  r.link_utilisation_mean = links == 0U ? 0.0 : total / links;
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
  app.add_option("--words", opts.words, "Data words per packet (1..128)")
      ->check(CLI::Range(1U, udn::kMaxDataWords));
  app.add_option("--seed", opts.seed, "Run seed (traffic, faults)");
  app.add_option("--failed-switches", opts.failed_switches, "Tile indices whose switch fails at t=0, comma-separated")
      ->delimiter(',');
  app.add_option("--profile", opts.profile, "Chip profile: tile64 (8x8) or maestro (7x7)")
      ->check(CLI::IsMember({"tile64", "maestro"}));
  app.add_option("--max-ms", opts.max_ms, "Bound on emulated milliseconds")->check(CLI::Range(0.001, 1e6));
  app.add_option("--quantum-us", opts.quantum_us, "Board quantum in microseconds (1..1000): delivery granularity")
      ->check(CLI::Range(1.0, 1000.0));
  app.add_option_function<std::string>(
         "--ft", [&opts](const std::string& v) { opts.ft = v == "on"; },
         "on: traffic through the fault-tolerant layer (ECC, retransmission, virtual routing); off: raw")
      ->check(CLI::IsMember({"on", "off"}));
  app.add_option("--ber", opts.ber, "Probability of a bit flip per word in transit")->check(CLI::Range(0.0, 0.1));
  app.add_option("--failed-tiles", opts.failed_tiles, "Tiles that run nothing and whose switch fails at t=0")
      ->delimiter(',');
  app.add_option("--failed-links", opts.failed_links,
                 "Failed links at t=0: 12E (leaving tile 12 eastwards; E W N S) or 12-13; both directions")
      ->delimiter(',');
}

std::string validate_stress_options(const StressOptions& opts) {
  const bsp::ChipProfile& p = profile_named(opts.profile);
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
  return "";
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
  if (!boot_board(opts)) {
    return r;
  }
  const bsp::ChipProfile& p = g_shared.profile;
  const auto max_cycles = static_cast<bsp::Cycles>(opts.max_ms * static_cast<double>(p.cycles_per_ms()));
  const auto t0 = std::chrono::steady_clock::now();
  bsp::heap::seal(seal);
  const bsp::RunResult run = bsp::run_until(&all_done, nullptr, max_cycles);
  bsp::heap::unseal();
  const auto t1 = std::chrono::steady_clock::now();
  r.heap_allocs_during_run = bsp::heap::allocs_after_seal();
  r.host_s = std::chrono::duration<double>(t1 - t0).count();
  r.net = bsp::udn_net_stats();
  r.sent_by_tasks = sum(g_shared.sent);
  r.received = sum(g_shared.received);
  r.send_errors = sum(g_shared.errors);
  r.completed = all_done(nullptr);
  r.emulated_s = static_cast<double>(run.end_cycle) / static_cast<double>(p.clock_hz);
  link_utilisation(r, run.end_cycle);
  return r;
}

void write_stress_json(std::ostream& out, const StressOptions& opts, const StressResult& r) {
  const bsp::NetStats& s = r.net;
  const auto lost = [&s](bsp::UdnLoss c) { return s.lost[static_cast<std::size_t>(c)]; };
  out << std::setprecision(9) << "{\"profile\":\"" << opts.profile << "\",\"pattern\":\"" << pattern_name(opts.pattern)
      << "\",\"rate_per_us\":" << opts.rate_per_us << ",\"packets\":" << opts.packets << ",\"words\":" << opts.words
      << ",\"seed\":" << opts.seed << ",\"quantum_us\":" << opts.quantum_us << ",\"failed_switches\":[";
  for (std::size_t i = 0; i < opts.failed_switches.size(); ++i) {
    out << (i == 0U ? "" : ",") << opts.failed_switches[i];
  }
  out << "],\"completed\":" << (r.completed ? "true" : "false") << ",\"sent\":" << (opts.ft ? r.ft.sent : s.sent)
      << ",\"delivered\":" << (opts.ft ? r.ft.delivered : s.delivered) << ",\"received\":" << r.received
      << ",\"lost_offgrid\":" << lost(bsp::UdnLoss::kOffGrid)
      << ",\"lost_failed_switch\":" << lost(bsp::UdnLoss::kFailedSwitch)
      << ",\"lost_failed_link\":" << lost(bsp::UdnLoss::kFailedLink)
      << ",\"lost_bad_length\":" << lost(bsp::UdnLoss::kBadLength) << ",\"send_errors\":" << r.send_errors
      << ",\"refused_full\":" << s.refused_full << ",\"queue_full_retries\":" << s.queue_full_retries
      << ",\"latency_cycles_min\":" << s.latency_min << ",\"latency_cycles_mean\":" << s.latency_mean()
      << ",\"latency_cycles_max\":" << s.latency_max << ",\"link_utilisation_mean\":" << r.link_utilisation_mean
      << ",\"link_utilisation_max\":" << r.link_utilisation_max << ",\"emulated_s\":" << r.emulated_s
      << ",\"host_s\":" << r.host_s << ",\"packets_per_host_s\":"
      << (r.host_s > 0.0 ? static_cast<double>(s.sent) / r.host_s : 0.0)
      << ",\"heap_allocs_during_run\":" << r.heap_allocs_during_run;
  if (opts.ft) {
    const StressResult::Ft& f = r.ft;
    out << ",\"ft\":true,\"ber\":" << opts.ber << ",\"net_sent\":" << s.sent << ",\"net_delivered\":" << s.delivered
        << ",\"corrected\":" << f.corrected << ",\"forwarded\":" << f.forwarded
        << ",\"retransmitted\":" << f.retransmitted << ",\"uncorrectable_detected\":" << f.uncorrectable_detected
        << ",\"lost\":" << f.lost << ",\"gave_up\":" << f.gave_up << ",\"duplicated\":" << f.duplicated
        << ",\"misordered\":" << f.misordered << ",\"corrupted_delivered\":" << f.corrupted_delivered
        << ",\"unreachable\":" << f.unreachable;
  }
  out << "}\n";
}

}  // namespace tools
