/**
 * @file udn_stress_ft.cpp
 * @brief udn_stress --ft on: one fault-tolerant driver task per working tile, checked deliveries.
 *
 * Each working tile runs one task that owns its udn::FtNode: every tick it
 * polls the listener, drains and checks its receive channels, and sends its
 * share of the traffic (a credit of rate x tick per tick, deterministic) to
 * destinations drawn like the raw run's, among working tiles only. Receivers
 * check every message against the pattern of (source, channel, sequence) and
 * the per-stream order; a message sent and never delivered counts as lost.
 */
#include "tools/common/udn_stress.hpp"

#include "bsp_tile64/board.hpp"
#include "bsp_tile64/rng.hpp"
#include "kernel/kernel.hpp"
#include "udn/ft_link.hpp"
#include "udn/raw.hpp"
#include "udn/route.hpp"

#include <array>
#include <chrono>

namespace tools {
namespace {

constexpr std::uint32_t kStackBytes = 16U * 1024U;
constexpr std::uint32_t kChannels = udn::kFtChannels;

struct FtShared {
  StressOptions opts;
  bsp::ChipProfile profile = bsp::kTile64;
  udn::FaultMap map{};
  std::array<bool, bsp::kMaxTiles> working{};
  std::array<bsp::TileId, bsp::kMaxTiles> live{};
  std::uint32_t live_count = 0U;
  std::array<std::uint64_t, bsp::kMaxTiles> quota{};
  std::array<std::uint64_t, bsp::kMaxTiles> done{};  ///< messages sent or refused as unreachable
  std::array<bool, bsp::kMaxTiles> idle{};           ///< quota done and nothing unacknowledged
  std::array<std::array<std::array<std::uint32_t, kChannels>, bsp::kMaxTiles>, bsp::kMaxTiles> sent{};
  std::array<std::array<std::array<std::uint32_t, kChannels>, bsp::kMaxTiles>, bsp::kMaxTiles> got{};
  StressResult::Ft ft{};
};
FtShared g_ft;
std::array<udn::FtNode, bsp::kMaxTiles> g_ft_nodes{};

std::uint32_t pattern(std::uint32_t source, std::uint32_t channel, std::uint32_t seq, std::uint32_t i) {
  std::uint32_t h = (source * 0x9E3779B1U) ^ (channel * 0x85EBCA77U) ^ (seq * 0xC2B2AE3DU) ^ (i * 0x27D4EB2FU);
  h ^= h >> 15U;
  h *= 0x2C1B3C6DU;
  return h ^ (h >> 12U);
}

void check_received(bsp::TileId self) {
  udn::FtMessage m{};
  for (std::uint32_t ch = 0; ch < kChannels; ++ch) {
    while (udn::ft_receive(g_ft_nodes[self], ch, m) == udn::FtError::kOk) {
      std::uint32_t& k = g_ft.got[m.source][self][ch];
      const std::uint32_t sent = g_ft.sent[m.source][self][ch];
      bool intact = m.data_words == g_ft.opts.words;
      for (std::uint32_t i = 0; intact && i < m.data_words; ++i) {
        intact = m.data[i] == pattern(m.source, ch, m.seq, i);
      }
      g_ft.ft.corrupted_delivered += intact ? 0U : 1U;
      if (k >= sent) {
        ++g_ft.ft.duplicated;
      } else if (m.seq != (k & 0xFFU)) {
        ++g_ft.ft.misordered;
      }
      ++k;
      ++g_ft.ft.delivered;
    }
  }
}

bsp::TileId pick_live(bsp::Rng& rng, bsp::TileId self) {
  for (int tries = 0; tries < 64; ++tries) {
    const bsp::TileId d = g_ft.live[rng.below(g_ft.live_count)];
    if (d != self || g_ft.live_count == 1U) {
      return d;
    }
  }
  return self;
}

/** Sends while credit and quota last; stops at the first refusal (retried next tick). */
void send_some(bsp::TileId self, bsp::Rng& rng, double& credit, std::array<std::uint32_t, udn::kFtMaxData>& data) {
  udn::FtNode& node = g_ft_nodes[self];
  while (credit >= 1.0 && g_ft.done[self] < g_ft.quota[self]) {
    const bsp::TileId dest = pick_live(rng, self);
    const auto ch = static_cast<std::uint32_t>(g_ft.done[self] % kChannels);
    const std::uint8_t seq = node.tx_stream[dest][ch].next_seq;
    for (std::uint32_t i = 0; i < g_ft.opts.words; ++i) {
      data[i] = pattern(self, ch, seq, i);
    }
    const udn::FtError e = udn::ft_send(node, dest, ch, std::span(data.data(), g_ft.opts.words), static_cast<std::uint32_t>(k::now_ticks()));
    if (e == udn::FtError::kOk) {
      ++g_ft.sent[self][dest][ch];
      ++g_ft.ft.sent;
    } else if (e == udn::FtError::kUnreachable) {
      ++g_ft.ft.unreachable;
    } else {
      return;
    }
    ++g_ft.done[self];
    credit -= 1.0;
  }
}

void ft_driver(void* /*arg*/) {
  const bsp::TileId self = bsp::current_tile();
  if (udn::activate() != udn::RawError::kOk ||
      udn::ft_init(g_ft_nodes[self], self, g_ft.map, udn::ft_task_port(), udn::FtConfig{}) != udn::FtError::kOk) {
    return;
  }
  bsp::Rng rng(g_ft.opts.seed, bsp::StreamId::kTraffic, self);
  const double per_tick = g_ft.opts.rate_per_us * 1e3;  // ticks are 1 ms
  std::array<std::uint32_t, udn::kFtMaxData> data{};
  std::array<std::uint32_t, bsp::kUdnMaxLength> rx{};
  double credit = per_tick;
  k::Ticks credited = k::now_ticks();
  for (;;) {
    // Sleep until an FT packet lands or the tick ends, then handle it and the rest.
    udn::RxInfo info{};
    if (udn::receive(udn::kFtQueue, info, rx, k::Timeout{1U}) == udn::RawError::kOk) {
      const std::size_t n = info.data_words < rx.size() ? info.data_words : rx.size();
      udn::ft_accept(g_ft_nodes[self], std::span(rx.data(), n), static_cast<std::uint32_t>(k::now_ticks()));
    }
    (void)udn::ft_poll(g_ft_nodes[self], static_cast<std::uint32_t>(k::now_ticks()), 256U);
    check_received(self);
    const k::Ticks now = k::now_ticks();
    credit += per_tick * static_cast<double>(now - credited);
    credited = now;
    send_some(self, rng, credit, data);
    g_ft.idle[self] = g_ft.done[self] == g_ft.quota[self] && udn::ft_outstanding(g_ft_nodes[self]) == 0U;
  }
}

constexpr k::TaskSpec kFtTasks[] = {
    {"udn_ft", &ft_driver, nullptr, 2, 0, 0, kStackBytes, k::Policy::kPreemptive},
};
static_assert(k::check_table(kFtTasks) == k::TableError::kOk);

bool ft_all_done(void* /*arg*/) {
  for (std::uint32_t i = 0; i < g_ft.live_count; ++i) {
    if (!g_ft.idle[g_ft.live[i]]) {
      return false;
    }
  }
  std::uint64_t gave_up = 0U;
  for (const udn::FtNode& n : g_ft_nodes) {
    gave_up += n.stats.gave_up;
  }
  return g_ft.ft.delivered + gave_up >= g_ft.ft.sent && bsp::udn_net_in_flight() == 0U;
}

bool build_map(const StressOptions& opts) {
  const bsp::ChipProfile& p = g_ft.profile;
  if (udn::fault_map_init(g_ft.map, p.cols, p.rows) != udn::RouteError::kOk) {
    return false;
  }
  g_ft.working.fill(false);
  for (bsp::TileId t = 0; t < p.tiles(); ++t) {
    g_ft.working[t] = true;
  }
  for (const std::uint32_t t : opts.failed_tiles) {
    g_ft.working[t] = false;
    (void)udn::fault_map_fail_tile(g_ft.map, t);
  }
  for (const std::uint32_t t : opts.failed_switches) {
    g_ft.working[t] = false;  // a tile without its switch cannot talk to anyone
    (void)udn::fault_map_fail_tile(g_ft.map, t);
  }
  for (const std::string& l : opts.failed_links) {
    LinkSpec spec{};
    if (!parse_link(l, p.cols, p.rows, spec).empty() ||
        udn::fault_map_fail_link(g_ft.map, spec.tile, spec.dir, true) != udn::RouteError::kOk) {
      return false;
    }
  }
  for (bsp::TileId t = 0; t < p.tiles(); ++t) {
    if (g_ft.working[t]) {
      g_ft.live[g_ft.live_count++] = t;
    }
  }
  return g_ft.live_count > 0U;
}

bool boot_ft_board(const StressOptions& opts) {
  g_ft = FtShared{};
  g_ft_nodes = {};
  g_ft.opts = opts;
  g_ft.profile = opts.profile == "maestro" ? bsp::kMaestro : bsp::kTile64;
  const bsp::ChipProfile& p = g_ft.profile;
  if (!build_map(opts)) {
    return false;
  }
  bsp::BoardConfig cfg = bsp::default_config(p);
  const auto quantum = static_cast<bsp::Cycles>(opts.quantum_us * static_cast<double>(p.clock_hz) / 1e6);
  cfg.quantum_cycles = quantum < 1U ? 1U : (quantum > cfg.tick_cycles ? cfg.tick_cycles : quantum);
  cfg.seed = opts.seed;
  cfg.monitor_tile = bsp::kNoTile;
  for (std::uint32_t i = 0; i < g_ft.live_count; ++i) {
    const bsp::TileId t = g_ft.live[i];
    cfg.boot[t] = &k::boot_entry;
    k::set_task_table(t, kFtTasks, cfg.tick_cycles);
    g_ft.quota[t] = opts.packets / g_ft.live_count + (i < opts.packets % g_ft.live_count ? 1U : 0U);
  }
  bsp::NetConfig net{};
  net.max_in_flight_per_tile = bsp::kUdnMaxInFlightPerTile;
  net.queue_words = bsp::kUdnMaxQueueWords;
  if (bsp::board_init(cfg) != bsp::BoardError::kOk || bsp::udn_net_init(net) != bsp::NetError::kOk) {
    return false;
  }
  bsp::udn_net_set_ber(opts.ber);
  bool ok = true;
  for (const std::uint32_t t : opts.failed_tiles) {
    ok = ok && bsp::udn_net_fail_switch(t) == bsp::NetError::kOk;
  }
  for (const std::uint32_t t : opts.failed_switches) {
    ok = ok && bsp::udn_net_fail_switch(t) == bsp::NetError::kOk;
  }
  for (const std::string& l : opts.failed_links) {
    LinkSpec spec{};
    ok = ok && parse_link(l, p.cols, p.rows, spec).empty() &&
         bsp::udn_net_fail_link(spec.tile, spec.dir) == bsp::NetError::kOk;
  }
  return ok;
}

void collect(StressResult& r) {
  for (const udn::FtNode& n : g_ft_nodes) {
    g_ft.ft.corrected += n.stats.corrected;
    g_ft.ft.forwarded += n.stats.forwarded;
    g_ft.ft.retransmitted += n.stats.retransmitted;
    g_ft.ft.uncorrectable_detected += n.stats.uncorrectable_detected;
    g_ft.ft.gave_up += n.stats.gave_up;
  }
  std::uint64_t in_order = 0U;
  for (std::size_t s = 0; s < bsp::kMaxTiles; ++s) {
    for (std::size_t d = 0; d < bsp::kMaxTiles; ++d) {
      for (std::uint32_t ch = 0; ch < kChannels; ++ch) {
        in_order += std::min(g_ft.got[s][d][ch], g_ft.sent[s][d][ch]);
      }
    }
  }
  g_ft.ft.lost = g_ft.ft.sent - in_order;
  r.ft = g_ft.ft;
  r.sent_by_tasks = g_ft.ft.sent;
  r.received = g_ft.ft.delivered;
}

}  // namespace

StressResult run_stress_ft(const StressOptions& opts, bsp::heap::SealMode seal) {
  StressResult r;
  if (!boot_ft_board(opts)) {
    return r;
  }
  const bsp::ChipProfile& p = g_ft.profile;
  const auto max_cycles = static_cast<bsp::Cycles>(opts.max_ms * static_cast<double>(p.cycles_per_ms()));
  const auto t0 = std::chrono::steady_clock::now();
  bsp::heap::seal(seal);
  const bsp::RunResult run = bsp::run_until(&ft_all_done, nullptr, max_cycles);
  bsp::heap::unseal();
  const auto t1 = std::chrono::steady_clock::now();
  r.heap_allocs_during_run = bsp::heap::allocs_after_seal();
  r.host_s = std::chrono::duration<double>(t1 - t0).count();
  r.net = bsp::udn_net_stats();
  r.completed = ft_all_done(nullptr);
  r.emulated_s = static_cast<double>(run.end_cycle) / static_cast<double>(p.clock_hz);
  collect(r);
  return r;
}

}  // namespace tools
