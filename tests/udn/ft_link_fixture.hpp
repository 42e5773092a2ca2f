/**
 * @file ft_link_fixture.hpp
 * @brief Host-driven harness of the fault-tolerant messaging tests: a node per tile on the emulated
 *        network, a port that can flip chosen bits of chosen sends, and a deterministic payload check.
 */
#pragma once

#include "bsp_tile64/emu/board.hpp"
#include "bsp_tile64/emu/udn_net.hpp"
#include "udn/ft_link.hpp"

#include <gtest/gtest.h>

#include <array>
#include <cstdint>
#include <span>
#include <vector>

namespace ft_test {

inline constexpr bsp::Cycles kQuantum = 1000U;
inline constexpr bsp::Cycles kTick = 4U * kQuantum;

/** Flips armed for the next data send of one tile (first transmissions and retransmissions alike). */
struct FlipPlan {
  bsp::TileId tile = bsp::kNoTile;
  std::vector<std::pair<std::uint32_t, std::uint32_t>> bits;  ///< (word, bit) of the packet image
  std::uint32_t remaining = 0U;                               ///< sends still to corrupt
};

inline FlipPlan g_flip;
inline std::uint64_t g_refused = 0U;

inline bsp::NetError host_send(void* /*ctx*/, bsp::TileId self, std::span<const std::uint32_t> words) {
  std::array<std::uint32_t, bsp::kUdnMaxPacketWords> w{};
  std::copy(words.begin(), words.end(), w.begin());
  if (g_flip.remaining > 0U && self == g_flip.tile && words.size() > udn::kFtMinPacketWords) {
    for (const auto& [word, bit] : g_flip.bits) {
      w[word] ^= 1U << bit;
    }
    --g_flip.remaining;
  }
  const bsp::NetError e = bsp::udn_net_send_from(self, bsp::board_time(), std::span(w.data(), words.size()));
  g_refused += (e == bsp::NetError::kFull) ? 1U : 0U;
  return e;
}

inline bsp::NetError host_receive(void* /*ctx*/, bsp::TileId self, std::uint32_t queue, bsp::RxPacket& rx,
                                  std::span<std::uint32_t> payload) {
  return bsp::udn_net_receive_on(self, queue, rx, payload);
}

inline std::array<udn::FtNode, 64> g_nodes{};

/** Every event each node reported through its sink, in order (boot() clears them). */
inline std::array<std::vector<udn::FtEvent>, 64> g_events{};

inline void record_event(void* /*ctx*/, bsp::TileId tile, const udn::FtEvent& e) {
  if (tile < g_events.size()) {
    g_events[tile].push_back(e);
  }
}

/** The events of @p tile with cause @p cause. */
inline std::vector<udn::FtEvent> events_of(bsp::TileId tile, udn::FtCause cause) {
  std::vector<udn::FtEvent> out;
  for (const udn::FtEvent& e : g_events[tile]) {
    if (e.cause == cause) {
      out.push_back(e);
    }
  }
  return out;
}

/** The payload word i of message (source, channel, seq): what the receiver checks. */
inline std::uint32_t pattern(std::uint32_t source, std::uint32_t channel, std::uint32_t seq, std::uint32_t i) {
  std::uint32_t h = (source * 0x9E3779B1U) ^ (channel * 0x85EBCA77U) ^ (seq * 0xC2B2AE3DU) ^ (i * 0x27D4EB2FU);
  h ^= h >> 15U;
  h *= 0x2C1B3C6DU;
  return h ^ (h >> 12U);
}

/** Boots a host-driven board (no tile runs code) and a node per tile on @p map. */
inline void boot(const udn::FaultMap& map, std::uint64_t seed = 7U, udn::FtConfig cfg = udn::FtConfig{}) {
  bsp::BoardConfig c = bsp::default_config(bsp::kTile64);
  c.quantum_cycles = kQuantum;
  c.tick_cycles = kTick;
  c.powered_at_start = 0U;
  c.monitor_tile = bsp::kNoTile;
  c.seed = seed;
  ASSERT_EQ(bsp::board_init(c), bsp::BoardError::kOk);
  bsp::NetConfig net{};
  net.max_in_flight_per_tile = 16U;
  net.queue_words = 512U;
  ASSERT_EQ(bsp::udn_net_init(net), bsp::NetError::kOk);
  g_flip = FlipPlan{};
  g_refused = 0U;
  const udn::FtPort port{&host_send, &host_receive, nullptr};
  for (bsp::TileId t = 0; t < map.cols * map.rows; ++t) {
    ASSERT_EQ(udn::ft_init(g_nodes[t], t, map, port, cfg), udn::FtError::kOk);
    udn::ft_set_event_sink(g_nodes[t], udn::FtEventSink{&record_event, nullptr});
    g_events[t].clear();
  }
}

inline std::uint32_t now_tick() { return static_cast<std::uint32_t>(bsp::board_time() / kTick); }

/** One quantum: every node polls, then the board runs (the network moves at the barrier). */
inline void step(std::uint32_t tiles = 64U) {
  for (bsp::TileId t = 0; t < tiles; ++t) {
    (void)udn::ft_poll(g_nodes[t], now_tick(), 64U);
  }
  (void)bsp::run_for(kQuantum);
}

inline std::uint32_t outstanding(std::uint32_t tiles = 64U) {
  std::uint32_t n = 0;
  for (bsp::TileId t = 0; t < tiles; ++t) n += udn::ft_outstanding(g_nodes[t]);
  return n;
}

inline udn::FaultMap grid_map() {
  udn::FaultMap m{};
  EXPECT_EQ(udn::fault_map_init(m, 8U, 8U), udn::RouteError::kOk);
  return m;
}

/** Sum of one statistic over all nodes. */
template <typename F>
std::uint64_t total(F f) {
  std::uint64_t s = 0;
  for (const auto& n : g_nodes) s += f(n.stats);
  return s;
}

}  // namespace ft_test
