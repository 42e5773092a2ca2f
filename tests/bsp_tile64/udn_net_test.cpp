/**
 * @file udn_net_test.cpp
 * @brief UDN mesh model: X-then-Y paths, exact latency and contention, delivery order, back-pressure,
 *        header bit flips, failed switches and links, deterministic statistics.
 */
#include "bsp_tile64/emu/board.hpp"
#include "bsp_tile64/faults/fault_injector.hpp"
#include "bsp_tile64/emu/rng.hpp"
#include "bsp_tile64/emu/trace.hpp"
#include "bsp_tile64/emu/udn_net.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cstdint>
#include <set>
#include <vector>

namespace {

constexpr bsp::Cycles kQuantum = 1000U;

void init_board(const bsp::ChipProfile& profile = bsp::kTile64, std::uint64_t seed = 42U,
                bsp::NetConfig net = bsp::NetConfig{}) {
  bsp::BoardConfig c = bsp::default_config(profile);
  c.quantum_cycles = kQuantum;
  c.tick_cycles = 10U * kQuantum;
  c.powered_at_start = 0U;  // host-driven: no tile runs code, the network still works at barriers
  c.monitor_tile = bsp::kNoTile;
  c.seed = seed;
  ASSERT_EQ(bsp::board_init(c), bsp::BoardError::kOk);
  ASSERT_EQ(bsp::udn_net_init(net), bsp::NetError::kOk);
}

/** A packet of @p payload_words words numbered from @p first, tag @p tag, for tile (x, y). */
std::vector<std::uint32_t> packet(std::uint32_t x, std::uint32_t y, std::uint32_t tag, std::uint32_t payload_words,
                                  std::uint32_t first = 0U) {
  std::vector<std::uint32_t> w{bsp::udn_make_header(x, y, payload_words + 1U), tag};
  for (std::uint32_t i = 0; i < payload_words; ++i) {
    w.push_back(first + i);
  }
  return w;
}

bsp::TileId tile_of(std::uint32_t x, std::uint32_t y, std::uint32_t cols = 8U) { return y * cols + x; }

/** Reference X-then-Y path: step x toward the target, then y. */
std::vector<bsp::TileId> reference_path(std::uint32_t cols, bsp::TileId s, bsp::TileId d) {
  std::int32_t x = static_cast<std::int32_t>(s % cols);
  std::int32_t y = static_cast<std::int32_t>(s / cols);
  const auto dx = static_cast<std::int32_t>(d % cols);
  const auto dy = static_cast<std::int32_t>(d / cols);
  std::vector<bsp::TileId> p{s};
  while (x != dx) {
    x += (dx > x) ? 1 : -1;
    p.push_back(static_cast<bsp::TileId>(y) * cols + static_cast<bsp::TileId>(x));
  }
  while (y != dy) {
    y += (dy > y) ? 1 : -1;
    p.push_back(static_cast<bsp::TileId>(y) * cols + static_cast<bsp::TileId>(x));
  }
  return p;
}

struct Received {
  bsp::RxPacket rx;
  std::vector<std::uint32_t> payload;
};

std::vector<Received> drain(bsp::TileId tile, std::uint32_t queue = bsp::kUdnCatchAll) {
  std::vector<Received> out;
  for (;;) {
    Received r{};
    r.payload.assign(bsp::kUdnMaxLength, 0U);
    if (bsp::udn_net_receive_on(tile, queue, r.rx, r.payload) != bsp::NetError::kOk) {
      return out;
    }
    r.payload.resize(r.rx.payload_words);
    out.push_back(r);
  }
}

void check_all_paths(const bsp::ChipProfile& p) {
  std::array<bsp::TileId, std::size_t{2U} * bsp::kMaxTiles> path{};
  for (bsp::TileId s = 0; s < p.tiles(); ++s) {
    for (bsp::TileId d = 0; d < p.tiles(); ++d) {
      const std::size_t n = bsp::udn_route(p.cols, p.rows, s, d, path);
      const std::vector<bsp::TileId> ref = reference_path(p.cols, s, d);
      ASSERT_EQ(n, ref.size()) << p.name << " " << s << "->" << d;
      for (std::size_t k = 0; k < n; ++k) {
        ASSERT_EQ(path[k], ref[k]) << p.name << " " << s << "->" << d << " step " << k;
      }
    }
  }
}

TEST(UdnRoute, EveryPairFollowsTheXThenYPathOn8x8And7x7) {
  check_all_paths(bsp::kTile64);
  check_all_paths(bsp::kMaestro);
  std::array<bsp::TileId, 4> small{};
  EXPECT_EQ(bsp::udn_route(8U, 8U, 0U, 63U, small), 0U) << "a path that does not fit is refused";
  EXPECT_EQ(bsp::udn_route(8U, 8U, 0U, 64U, small), 0U) << "off-grid destination";
}

TEST(UdnRoute, DirectionsOfNeighbours) {
  EXPECT_EQ(bsp::udn_dir(8U, 9U, 10U), bsp::UdnDir::kEast);
  EXPECT_EQ(bsp::udn_dir(8U, 9U, 8U), bsp::UdnDir::kWest);
  EXPECT_EQ(bsp::udn_dir(8U, 9U, 1U), bsp::UdnDir::kNorth);
  EXPECT_EQ(bsp::udn_dir(8U, 9U, 17U), bsp::UdnDir::kSouth);
}

TEST(UdnNet, UncontendedLatencyIsHopsPlusOneTimesHopCyclesPlusWords) {
  init_board();
  ASSERT_EQ(bsp::udn_hop_cycles(), 1U);
  // (1,1) -> (6,4): 5 + 3 = 8 hops; W = header + tag + 10 payload = 12 words.
  const auto w = packet(6U, 4U, 77U, 10U);
  ASSERT_EQ(bsp::udn_net_send_from(tile_of(1U, 1U), 0U, w), bsp::NetError::kOk);
  (void)bsp::run_for(kQuantum);  // barrier at 0 routes it; arrival 21 > 0: not yet visible
  EXPECT_TRUE(drain(tile_of(6U, 4U)).empty());
  (void)bsp::run_for(kQuantum);
  const auto got = drain(tile_of(6U, 4U));
  ASSERT_EQ(got.size(), 1U);
  EXPECT_EQ(got[0].rx.arrival_cycle, (8U + 1U) * 1U + 12U);
  EXPECT_EQ(got[0].rx.delivered_cycle, kQuantum);
  EXPECT_EQ(got[0].rx.source, tile_of(1U, 1U));
  EXPECT_EQ(got[0].rx.tag, 77U);
  EXPECT_EQ(got[0].payload, std::vector<std::uint32_t>(w.begin() + 2, w.end()));
  const bsp::NetStats s = bsp::udn_net_stats();
  EXPECT_EQ(s.sent, 1U);
  EXPECT_EQ(s.delivered, 1U);
  EXPECT_EQ(s.latency_min, 21U);
  EXPECT_EQ(s.latency_max, 21U);
  // Every link of the path carried the 12 words once; links off the path none.
  EXPECT_EQ(bsp::udn_link_busy_cycles(tile_of(1U, 1U), bsp::UdnDir::kEast), 12U);
  EXPECT_EQ(bsp::udn_link_busy_cycles(tile_of(6U, 1U), bsp::UdnDir::kSouth), 12U);
  EXPECT_EQ(bsp::udn_link_busy_cycles(tile_of(6U, 1U), bsp::UdnDir::kEast), 0U);
}

TEST(UdnNet, PacketsSharingALinkQueueBehindEachOther) {
  init_board();
  // A: (0,0) -> (3,0) and B: (1,0) -> (3,0), both sent at cycle 0, W = 10 words.
  // A goes first (same cycle, lower source): links 0E,1E,2E at 1,2,3, ejection at 4, arrival 14.
  // B: 1E is busy until 12 -> t=12; 2E free at 13 -> t = max(13, 13) = 13; ejection free at 14 ->
  // t = max(14, 14) = 14; arrival 14 + 10 = 24 (uncontended it would be 13).
  ASSERT_EQ(bsp::udn_net_send_from(tile_of(1U, 0U), 0U, packet(3U, 0U, 2U, 8U, 100U)), bsp::NetError::kOk);
  ASSERT_EQ(bsp::udn_net_send_from(tile_of(0U, 0U), 0U, packet(3U, 0U, 1U, 8U, 0U)), bsp::NetError::kOk);
  (void)bsp::run_for(2U * kQuantum);
  const auto got = drain(tile_of(3U, 0U));
  ASSERT_EQ(got.size(), 2U);
  EXPECT_EQ(got[0].rx.source, tile_of(0U, 0U));
  EXPECT_EQ(got[0].rx.arrival_cycle, 14U);
  EXPECT_EQ(got[1].rx.source, tile_of(1U, 0U));
  EXPECT_EQ(got[1].rx.arrival_cycle, 24U);
  EXPECT_EQ(bsp::udn_link_busy_cycles(tile_of(1U, 0U), bsp::UdnDir::kEast), 20U);
}

TEST(UdnNet, LaterSendWaitsForTheLinkAcrossBarriers) {
  init_board();
  // A long packet (W = 130) from 0 to 1 sent at 0 keeps link 0E busy until 131; a packet sent at 50
  // on the same path starts at 131, ejects at max(132, 132) and arrives at 132 + 3 = 135.
  ASSERT_EQ(bsp::udn_net_send_from(0U, 0U, packet(1U, 0U, 1U, 128U)), bsp::NetError::kOk);
  ASSERT_EQ(bsp::udn_net_send_from(0U, 50U, packet(1U, 0U, 1U, 1U)), bsp::NetError::kOk);
  (void)bsp::run_for(2U * kQuantum);
  const auto got = drain(1U);
  ASSERT_EQ(got.size(), 2U);
  EXPECT_EQ(got[0].rx.arrival_cycle, 132U);
  EXPECT_EQ(got[1].rx.arrival_cycle, 135U);
}

TEST(UdnNet, TagsSelectDemuxQueuesAndUnboundTagsGoToTheCatchAll) {
  init_board();
  ASSERT_EQ(bsp::udn_net_bind(5U, 0xAAU, 2U), bsp::NetError::kOk);
  ASSERT_EQ(bsp::udn_net_bind(5U, 0xBBU, 0U), bsp::NetError::kOk);
  EXPECT_EQ(bsp::udn_net_bind(5U, 0xCCU, bsp::kUdnCatchAll), bsp::NetError::kBadQueue);
  ASSERT_EQ(bsp::udn_net_send_from(0U, 0U, packet(5U, 0U, 0xAAU, 1U)), bsp::NetError::kOk);
  ASSERT_EQ(bsp::udn_net_send_from(0U, 0U, packet(5U, 0U, 0xBBU, 1U)), bsp::NetError::kOk);
  ASSERT_EQ(bsp::udn_net_send_from(0U, 0U, packet(5U, 0U, 0xCCU, 1U)), bsp::NetError::kOk);
  (void)bsp::run_for(2U * kQuantum);
  EXPECT_EQ(bsp::udn_net_queue_packets(5U, 2U), 1U);
  EXPECT_EQ(bsp::udn_net_queue_packets(5U, 0U), 1U);
  EXPECT_EQ(bsp::udn_net_queue_packets(5U, bsp::kUdnCatchAll), 1U);
  EXPECT_EQ(drain(5U, 2U).at(0).rx.tag, 0xAAU);
  EXPECT_EQ(drain(5U, bsp::kUdnCatchAll).at(0).rx.tag, 0xCCU);
}

TEST(UdnNet, SendsAreCheckedAndBoundedPerSource) {
  init_board(bsp::kTile64, 42U, bsp::NetConfig{3U, 256U});
  auto w = packet(1U, 0U, 1U, 2U);
  w[0] = bsp::udn_make_header(1U, 0U, 5U);  // says 5 words follow, 3 given
  EXPECT_EQ(bsp::udn_net_send_from(0U, 0U, w), bsp::NetError::kBadLength);
  EXPECT_EQ(bsp::udn_net_send_from(64U, 0U, packet(1U, 0U, 1U, 2U)), bsp::NetError::kBadTile);
  for (int i = 0; i < 3; ++i) {
    EXPECT_EQ(bsp::udn_net_send_from(0U, 0U, packet(1U, 0U, 1U, 2U)), bsp::NetError::kOk);
  }
  EXPECT_FALSE(bsp::udn_net_can_send(0U));
  EXPECT_EQ(bsp::udn_net_send_from(0U, 0U, packet(1U, 0U, 1U, 2U)), bsp::NetError::kFull);
  EXPECT_EQ(bsp::udn_net_stats().refused_full, 1U);
  EXPECT_EQ(bsp::udn_net_init(bsp::NetConfig{0U, 256U}), bsp::NetError::kBadConfig);
  EXPECT_EQ(bsp::udn_net_init(bsp::NetConfig{4U, 100U}), bsp::NetError::kBadConfig);
}

TEST(UdnNet, FullQueueHoldsPacketsInFlightLosesNothingAndKeepsOrder) {
  init_board(bsp::kTile64, 42U, bsp::NetConfig{8U, 129U});
  // Queue of 129 words: 10 packets of 1 + 30 words fill it after 4. Nobody reads at first.
  std::uint32_t next = 0U;
  std::uint32_t sent = 0U;
  std::vector<std::uint32_t> firsts;
  for (int round = 0; round < 40; ++round) {
    while (sent < 10U && bsp::udn_net_can_send(9U)) {
      ASSERT_EQ(bsp::udn_net_send_from(9U, bsp::board_time(), packet(2U, 6U, 3U, 30U, next)), bsp::NetError::kOk);
      firsts.push_back(next);
      next += 30U;
      ++sent;
    }
    (void)bsp::run_for(kQuantum);
    if (round < 5) {
      EXPECT_LE(bsp::udn_net_queue_packets(tile_of(2U, 6U), bsp::kUdnCatchAll), 4U);
      continue;  // the receiver is stopped
    }
    for (const auto& r : drain(tile_of(2U, 6U))) {
      ASSERT_FALSE(firsts.empty());
      EXPECT_EQ(r.payload.at(0), firsts.front()) << "per-source order";
      firsts.erase(firsts.begin());
    }
  }
  const bsp::NetStats s = bsp::udn_net_stats();
  EXPECT_EQ(sent, 10U);
  EXPECT_TRUE(firsts.empty()) << "every packet delivered once";
  EXPECT_EQ(s.delivered, 10U);
  EXPECT_EQ(s.lost_total(), 0U);
  EXPECT_GT(s.queue_full_retries, 0U);
  EXPECT_EQ(bsp::udn_net_in_flight(), 0U);
}

TEST(UdnNet, RetriesCountOncePerBarrierEvenAfterARepeatedInit) {
  init_board(bsp::kTile64, 42U, bsp::NetConfig{8U, 129U});
  ASSERT_EQ(bsp::udn_net_init(bsp::NetConfig{8U, 129U}), bsp::NetError::kOk);  // a second hook is registered
  for (std::uint32_t i = 0; i < 5U; ++i) {  // 4 x 31 words fit in 129, the fifth waits
    ASSERT_EQ(bsp::udn_net_send_from(0U, 0U, packet(1U, 0U, 1U, 30U, i)), bsp::NetError::kOk);
  }
  (void)bsp::run_for(3U * kQuantum);  // barriers 0 (route), 1000 and 2000 (deliver 4, retry 1 twice)
  const bsp::NetStats s = bsp::udn_net_stats();
  EXPECT_EQ(s.delivered, 4U);
  EXPECT_EQ(s.queue_full_retries, 2U);
  EXPECT_EQ(bsp::udn_net_in_flight(), 1U);
}

/** Loss events of @p cause in the trace ring. */
std::size_t lost_traces(bsp::UdnLoss cause) {
  std::array<bsp::TraceEvent, bsp::kTraceRingSize> ring{};
  const std::size_t n = bsp::trace_recent(ring);
  std::size_t count = 0U;
  for (std::size_t i = 0; i < n; ++i) {
    count += (ring[i].kind == static_cast<std::uint16_t>(bsp::UdnTrace::kLost) &&
              ring[i].a == static_cast<std::uint64_t>(cause))
                 ? 1U
                 : 0U;
  }
  return count;
}

/** Sends one packet from (1,2) to (3,5) after arming a header flip of word @p word, bit @p bit. */
void send_with_flip(std::uint32_t word, std::uint32_t bit) {
  init_board();
  bsp::FaultSpec f{};
  f.cycle = 0U;
  f.kind = bsp::FaultKind::kPacketBitFlip;
  f.tile = tile_of(1U, 2U);
  f.offset = word;
  f.bit = bit;
  ASSERT_EQ(bsp::fault_plan_add(f), bsp::FaultError::kOk);
  (void)bsp::run_for(kQuantum);  // the fault arms itself on the tile at cycle 0
  ASSERT_EQ(bsp::fault_log().size(), 1U);
  ASSERT_EQ(bsp::fault_log()[0].status, bsp::FaultStatus::kArmed);
  ASSERT_EQ(bsp::udn_net_send_from(tile_of(1U, 2U), kQuantum, packet(3U, 5U, 9U, 6U)), bsp::NetError::kOk);
  (void)bsp::run_for(2U * kQuantum);
  EXPECT_EQ(bsp::fault_log()[0].status, bsp::FaultStatus::kApplied);
  EXPECT_EQ(bsp::fault_log()[0].offset, word);
  EXPECT_EQ(bsp::fault_log()[0].bit, bit);
}

TEST(UdnNetFaults, EveryDestinationBitFlipMisdeliversToTheNamedTileOrIsLostOffGrid) {
  for (std::uint32_t bit = 8U; bit < 24U; ++bit) {
    send_with_flip(0U, bit);
    const std::uint32_t h = bsp::udn_make_header(3U, 5U, 7U) ^ (1U << bit);
    const std::uint32_t x = bsp::udn_header_x(h);
    const std::uint32_t y = bsp::udn_header_y(h);
    const bsp::NetStats s = bsp::udn_net_stats();
    if (x < 8U && y < 8U) {
      EXPECT_EQ(s.delivered, 1U) << "bit " << bit;
      EXPECT_EQ(drain(tile_of(x, y)).size(), 1U) << "bit " << bit << " names (" << x << "," << y << ")";
    } else {
      EXPECT_EQ(s.lost[static_cast<std::size_t>(bsp::UdnLoss::kOffGrid)], 1U) << "bit " << bit;
      EXPECT_EQ(s.delivered, 0U) << "bit " << bit;
      EXPECT_EQ(lost_traces(bsp::UdnLoss::kOffGrid), 1U) << "bit " << bit << ": every loss is traced";
    }
  }
}

TEST(UdnNetFaults, LengthFlipsTruncateOrPadOrLoseThePacket) {
  // Sent length 7 (tag + 6 payload words numbered 0..5).
  for (std::uint32_t bit = 0U; bit < 8U; ++bit) {
    send_with_flip(0U, bit);
    const std::uint32_t len = 7U ^ (1U << bit);
    const bsp::NetStats s = bsp::udn_net_stats();
    if (len > bsp::kUdnMaxLength) {
      EXPECT_EQ(s.lost[static_cast<std::size_t>(bsp::UdnLoss::kBadLength)], 1U) << "bit " << bit;
      continue;
    }
    const auto got = drain(tile_of(3U, 5U));
    ASSERT_EQ(got.size(), 1U) << "bit " << bit;
    ASSERT_EQ(got[0].rx.payload_words, len - 1U) << "bit " << bit;
    for (std::uint32_t i = 0; i < len - 1U; ++i) {
      EXPECT_EQ(got[0].payload[i], i < 6U ? i : 0U) << "bit " << bit << " word " << i;
    }
    EXPECT_EQ(s.words_truncated, len < 7U ? 7U - len : 0U);
    EXPECT_EQ(s.words_padded, len > 7U ? len - 7U : 0U);
  }
}

TEST(UdnNetFaults, TagAndPayloadFlipsAreDeliveredCorrupted) {
  send_with_flip(1U, 3U);
  EXPECT_EQ(drain(tile_of(3U, 5U)).at(0).rx.tag, 9U ^ 8U);
  send_with_flip(4U, 31U);
  EXPECT_EQ(drain(tile_of(3U, 5U)).at(0).payload.at(2), 2U ^ 0x8000'0000U);
}

/** Every tile sends one packet to every other tile (63 rounds); returns (src, dst) pairs delivered. */
std::set<std::pair<bsp::TileId, bsp::TileId>> all_pairs_round() {
  std::set<std::pair<bsp::TileId, bsp::TileId>> got;
  for (bsp::TileId r = 1; r <= 64U; ++r) {  // the last round only delivers what round 63 sent
    for (bsp::TileId s = 0; s < 64U && r < 64U; ++s) {
      const bsp::TileId d = (s + r) % 64U;
      EXPECT_EQ(bsp::udn_net_send_from(s, bsp::board_time(), packet(d % 8U, d / 8U, 1U, 1U, s)), bsp::NetError::kOk);
    }
    (void)bsp::run_for(kQuantum);
    for (bsp::TileId d = 0; d < 64U; ++d) {
      for (const auto& p : drain(d)) {
        got.insert({p.rx.source, d});
      }
    }
  }
  return got;
}

TEST(UdnNetFaults, FailedSwitchLosesExactlyThePacketsWhosePathCrossesIt) {
  init_board();
  const bsp::TileId failed = tile_of(3U, 4U);
  bsp::FaultSpec f{};
  f.kind = bsp::FaultKind::kSwitchFail;
  f.tile = failed;
  ASSERT_EQ(bsp::fault_plan_add(f), bsp::FaultError::kOk);
  (void)bsp::run_for(kQuantum);
  ASSERT_EQ(bsp::fault_log()[0].status, bsp::FaultStatus::kApplied);
  const auto got = all_pairs_round();
  std::uint64_t expected_lost = 0U;
  for (bsp::TileId s = 0; s < 64U; ++s) {
    for (bsp::TileId d = 0; d < 64U; ++d) {
      if (s == d) {
        continue;
      }
      const auto p = reference_path(8U, s, d);
      const bool crosses = std::find(p.begin(), p.end(), failed) != p.end();
      expected_lost += crosses ? 1U : 0U;
      EXPECT_EQ(got.count({s, d}), crosses ? 0U : 1U) << s << "->" << d;
    }
  }
  const bsp::NetStats st = bsp::udn_net_stats();
  EXPECT_EQ(st.lost[static_cast<std::size_t>(bsp::UdnLoss::kFailedSwitch)], expected_lost);
  EXPECT_EQ(st.delivered + expected_lost, 64U * 63U);
}

TEST(UdnNetFaults, FailedLinkLosesExactlyThePacketsCrossingItEitherWay) {
  init_board();
  const bsp::TileId a = tile_of(2U, 2U);
  const bsp::TileId b = tile_of(3U, 2U);
  bsp::FaultSpec f{};
  f.kind = bsp::FaultKind::kLinkFail;
  f.tile = a;
  f.param = static_cast<std::uint64_t>(bsp::UdnDir::kEast);
  ASSERT_EQ(bsp::fault_plan_add(f), bsp::FaultError::kOk);
  (void)bsp::run_for(kQuantum);
  const auto got = all_pairs_round();
  std::uint64_t expected_lost = 0U;
  for (bsp::TileId s = 0; s < 64U; ++s) {
    for (bsp::TileId d = 0; d < 64U; ++d) {
      if (s == d) {
        continue;
      }
      const auto p = reference_path(8U, s, d);
      bool crosses = false;
      for (std::size_t k = 0; k + 1U < p.size(); ++k) {
        crosses = crosses || (p[k] == a && p[k + 1U] == b) || (p[k] == b && p[k + 1U] == a);
      }
      expected_lost += crosses ? 1U : 0U;
      EXPECT_EQ(got.count({s, d}), crosses ? 0U : 1U) << s << "->" << d;
    }
  }
  EXPECT_EQ(bsp::udn_net_stats().lost[static_cast<std::size_t>(bsp::UdnLoss::kFailedLink)], expected_lost);
}

TEST(UdnNetFaults, RandomPacketBitFlipsFromTheInjectorRateArmAndApply) {
  init_board();
  ASSERT_EQ(bsp::fault_set_rate(bsp::FaultKind::kPacketBitFlip, 2000.0), bsp::FaultError::kOk);  // ~128 per ms
  for (int q = 0; q < 20; ++q) {
    for (bsp::TileId s = 0; s < 64U; ++s) {
      const bsp::TileId d = 63U - s;
      ASSERT_EQ(bsp::udn_net_send_from(s, bsp::board_time(), packet(d % 8U, d / 8U, 1U, 4U)), bsp::NetError::kOk);
    }
    (void)bsp::run_for(kQuantum);
  }
  std::uint64_t applied = 0U;
  for (const bsp::FaultRecord& r : bsp::fault_log()) {
    ASSERT_EQ(r.spec.kind, bsp::FaultKind::kPacketBitFlip);
    EXPECT_TRUE(r.status == bsp::FaultStatus::kApplied || r.status == bsp::FaultStatus::kArmed ||
                r.status == bsp::FaultStatus::kScheduled);
    if (r.status == bsp::FaultStatus::kApplied) {
      ++applied;
      EXPECT_LT(r.offset, 6U) << "a word of the 6-word packet";
      EXPECT_LT(r.bit, 32U);
    }
  }
  EXPECT_GT(applied, 0U);
  EXPECT_EQ(bsp::udn_net_stats().bit_flips, applied);
}

struct RunDigest {
  bsp::NetStats stats;
  std::uint64_t trace_hash;
  std::uint32_t in_flight;
};

/** Random traffic and a random bit-error rate from @p seed; a digest of the outcome. */
RunDigest random_run(std::uint64_t seed) {
  init_board(bsp::kTile64, seed);
  bsp::udn_net_set_ber(0.002);
  bsp::Rng rng(seed, bsp::StreamId::kTest);
  for (int q = 0; q < 50; ++q) {
    for (bsp::TileId s = 0; s < 64U; ++s) {
      const auto d = static_cast<bsp::TileId>(rng.below(64U));
      const auto words = static_cast<std::uint32_t>(1U + rng.below(20U));
      const bsp::Cycles at = bsp::board_time() + rng.below(kQuantum);
      if (bsp::udn_net_can_send(s)) {
        EXPECT_EQ(bsp::udn_net_send_from(s, at, packet(d % 8U, d / 8U, 1U, words)), bsp::NetError::kOk);
      }
    }
    (void)bsp::run_for(kQuantum);
    for (bsp::TileId d = 0; d < 64U; ++d) {
      (void)drain(d);
    }
  }
  return {bsp::udn_net_stats(), bsp::trace_hash(), bsp::udn_net_in_flight()};
}

TEST(UdnNet, StatisticsAreDeterministicForASeedAndDifferForAnother) {
  constexpr std::uint64_t kSeed = 2024U;
  const RunDigest a = random_run(kSeed);
  const RunDigest b = random_run(kSeed);
  const RunDigest c = random_run(kSeed + 1U);
  SCOPED_TRACE(testing::Message() << "seed " << kSeed);
  EXPECT_GT(a.stats.sent, 3000U);
  EXPECT_GT(a.stats.bit_flips, 0U);
  EXPECT_EQ(a.stats.sent, b.stats.sent);
  EXPECT_EQ(a.stats.delivered, b.stats.delivered);
  EXPECT_EQ(a.stats.latency_sum, b.stats.latency_sum);
  EXPECT_EQ(a.stats.lost_total(), b.stats.lost_total());
  EXPECT_EQ(a.trace_hash, b.trace_hash);
  EXPECT_NE(a.trace_hash, c.trace_hash);
  EXPECT_NE(a.stats.latency_sum, c.stats.latency_sum);
  EXPECT_EQ(a.stats.delivered + a.stats.lost_total() + a.in_flight, a.stats.sent);
}

}  // namespace
