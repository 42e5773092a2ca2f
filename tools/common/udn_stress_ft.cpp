/**
 * @file udn_stress_ft.cpp
 * @brief udn_stress --ft on: one fault-tolerant driver task per working tile, checked deliveries.
 *
 * Each working tile runs one task that owns its udn::FtNode: every tick it
 * polls the listener, drains and checks its receive channels, and sends its
 * share of the traffic (a credit of rate x tick per tick, deterministic) to
 * destinations drawn like the raw run's (udn_stress_plan.hpp: working tiles
 * only). Payloads are stamped and checked like the raw run's
 * (udn_stress_payload.hpp: corrupted, misdelivered); the order is checked per
 * (source, destination, channel) stream, the unit the layer keeps in order;
 * a message sent and never delivered counts as lost.
 */
#include "tools/common/udn_stress.hpp"

#include "bsp_tile64/board.hpp"
#include "bsp_tile64/rng.hpp"
#include "kernel/kernel.hpp"
#include "tools/common/udn_stress_payload.hpp"
#include "tools/common/udn_stress_plan.hpp"
#include "udn/ft_link.hpp"
#include "udn/raw.hpp"
#include "udn/route.hpp"

#include <array>

namespace tools {
namespace {

constexpr std::uint32_t kStackBytes = 16U * 1024U;
constexpr std::uint32_t kChannels = udn::kFtChannels;

struct FtShared {
  StressOptions opts;
  detail::TrafficPlan plan;  ///< the working tiles send and are addressed
  udn::FaultMap map{};
  std::array<std::uint64_t, bsp::kMaxTiles> done{};  ///< messages sent or refused as unreachable
  std::array<bool, bsp::kMaxTiles> idle{};           ///< quota done and nothing unacknowledged
  std::array<std::array<std::array<std::uint32_t, kChannels>, bsp::kMaxTiles>, bsp::kMaxTiles> sent{};
  std::array<std::array<std::array<std::uint32_t, kChannels>, bsp::kMaxTiles>, bsp::kMaxTiles> got{};
  StressResult::Delivery delivery{};
  StressResult::Ft ft{};
};
FtShared g_ft;
std::array<udn::FtNode, bsp::kMaxTiles> g_ft_nodes{};

void check_received(bsp::TileId self) {
  udn::FtMessage m{};
  for (std::uint32_t ch = 0; ch < kChannels; ++ch) {
    while (udn::ft_receive(g_ft_nodes[self], ch, m) == udn::FtError::kOk) {
      std::uint32_t& k = g_ft.got[m.source][self][ch];
      const std::uint32_t sent = g_ft.sent[m.source][self][ch];
      const std::size_t n = m.data_words < m.data.size() ? m.data_words : m.data.size();
      PayloadStamp st{};
      const PayloadVerdict v =
          check_payload(std::span(m.data.data(), n), m.data_words, g_ft.opts.words, m.source, self, st);
      g_ft.delivery.corrupted_delivered += v == PayloadVerdict::kCorrupted ? 1U : 0U;
      g_ft.delivery.misdelivered += v == PayloadVerdict::kMisdelivered ? 1U : 0U;
      if (k >= sent) {
        ++g_ft.delivery.duplicated;
      } else if (m.seq != (k & 0xFFU)) {
        ++g_ft.delivery.misordered;
      }
      ++k;
      ++g_ft.delivery.delivered;
    }
  }
}

/** A driver's sending state: its traffic stream, the credit of messages due and the next message's destination. */
struct Source {
  bsp::Rng rng;
  double credit = 0.0;
  bsp::TileId dest = bsp::kNoTile;  ///< drawn, not yet accepted (kNoTile: draw the next)
};

/** Sends while credit and quota last; stops at the first refusal (the same message is retried next tick). */
void send_some(bsp::TileId self, Source& src, std::array<std::uint32_t, udn::kFtMaxData>& data) {
  udn::FtNode& node = g_ft_nodes[self];
  bsp::TileId& dest = src.dest;
  while (src.credit >= 1.0 && g_ft.done[self] < g_ft.plan.quota[self]) {
    if (dest == bsp::kNoTile) {
      dest = detail::pick_destination(g_ft.plan, src.rng, self);
    }
    const auto ch = static_cast<std::uint32_t>(g_ft.done[self] % kChannels);
    const std::span<std::uint32_t> payload(data.data(), g_ft.opts.words);
    stamp_payload(PayloadStamp{self, dest, static_cast<std::uint16_t>(g_ft.done[self])}, payload);
    const udn::FtError e = udn::ft_send(node, dest, ch, payload, static_cast<std::uint32_t>(k::now_ticks()));
    if (e == udn::FtError::kOk) {
      ++g_ft.sent[self][dest][ch];
      ++g_ft.delivery.sent;
    } else if (e == udn::FtError::kUnreachable) {
      ++g_ft.ft.unreachable;
    } else {
      return;
    }
    ++g_ft.done[self];
    src.credit -= 1.0;
    dest = bsp::kNoTile;
  }
}

void ft_driver(void* /*arg*/) {
  const bsp::TileId self = bsp::current_tile();
  if (udn::activate() != udn::RawError::kOk ||
      udn::ft_init(g_ft_nodes[self], self, g_ft.map, udn::ft_task_port(), udn::FtConfig{}) != udn::FtError::kOk) {
    return;
  }
  const double per_tick = g_ft.opts.rate_per_us * 1e3;  // ticks are 1 ms
  Source src{bsp::Rng(g_ft.opts.seed, bsp::StreamId::kTraffic, self), per_tick, bsp::kNoTile};
  std::array<std::uint32_t, udn::kFtMaxData> data{};
  std::array<std::uint32_t, bsp::kUdnMaxLength> rx{};
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
    src.credit += per_tick * static_cast<double>(now - credited);
    credited = now;
    send_some(self, src, data);
    g_ft.idle[self] = g_ft.done[self] == g_ft.plan.quota[self] && udn::ft_outstanding(g_ft_nodes[self]) == 0U;
  }
}

constexpr k::TaskSpec kFtTasks[] = {
    {"udn_ft", &ft_driver, nullptr, 2, 0, 0, kStackBytes, k::Policy::kPreemptive},
};
static_assert(k::check_table(kFtTasks) == k::TableError::kOk);

bool ft_all_done(void* /*arg*/) {
  for (std::uint32_t i = 0; i < g_ft.plan.sender_count; ++i) {
    if (!g_ft.idle[g_ft.plan.targets[i]]) {
      return false;
    }
  }
  std::uint64_t gave_up = 0U;
  for (const udn::FtNode& n : g_ft_nodes) {
    gave_up += n.stats.gave_up;
  }
  return g_ft.delivery.delivered + gave_up >= g_ft.delivery.sent && bsp::udn_net_in_flight() == 0U;
}

/** The fault map every node starts from: it knows every failure the run was given at t=0. */
bool build_map(const StressOptions& opts) {
  const bsp::ChipProfile& p = g_ft.plan.profile;
  if (udn::fault_map_init(g_ft.map, p.cols, p.rows) != udn::RouteError::kOk) {
    return false;
  }
  bool ok = true;
  for (const std::uint32_t t : opts.failed_tiles) {
    ok = ok && udn::fault_map_fail_tile(g_ft.map, t) == udn::RouteError::kOk;
  }
  for (const std::uint32_t t : opts.failed_switches) {
    ok = ok && udn::fault_map_fail_tile(g_ft.map, t) == udn::RouteError::kOk;  // its switch is not trusted
  }
  for (const std::string& l : opts.failed_links) {
    LinkSpec spec{};
    ok = ok && parse_link(l, p.cols, p.rows, spec).empty() &&
         udn::fault_map_fail_link(g_ft.map, spec.tile, spec.dir, true) == udn::RouteError::kOk;
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
  g_ft.delivery.lost = g_ft.delivery.sent - in_order;
  r.delivery = g_ft.delivery;
  r.ft = g_ft.ft;
}

}  // namespace

StressResult run_stress_ft(const StressOptions& opts, bsp::heap::SealMode seal) {
  StressResult r;
  g_ft = FtShared{};
  g_ft_nodes = {};
  g_ft.opts = opts;
  g_ft.plan = detail::make_plan(opts);
  bsp::NetConfig net{};
  net.max_in_flight_per_tile = bsp::kUdnMaxInFlightPerTile;
  net.queue_words = bsp::kUdnMaxQueueWords;
  if (g_ft.plan.sender_count == 0U || !build_map(opts) || !detail::boot_stress_board(opts, g_ft.plan, kFtTasks, net)) {
    return r;
  }
  detail::run_stress_board(opts, g_ft.plan, &ft_all_done, seal, r);
  collect(r);
  return r;
}

}  // namespace tools
