/**
 * @file ft_link_test.cpp
 * @brief Fault-tolerant messaging end to end on the emulated network: every single-bit flip of a
 *        packet (hardware header included) delivered exactly once and intact, double errors recovered
 *        by retransmission, Figure 6 forwarding, unreachable destinations and give-ups reported.
 */
#include "tests/udn/ft_link_fixture.hpp"

#include "bsp_tile64/faults/fault_injector.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cstdint>
#include <functional>
#include <utility>
#include <vector>

namespace {

using ft_test::g_nodes;

constexpr std::uint32_t kWords = 3U;

std::vector<std::uint32_t> message(std::uint32_t src, std::uint32_t ch, std::uint32_t seq) {
  std::vector<std::uint32_t> d(kWords);
  for (std::uint32_t i = 0; i < kWords; ++i) d[i] = ft_test::pattern(src, ch, seq, i);
  return d;
}

/** Runs until nothing is outstanding (or @p max_steps quanta). */
void settle(std::uint32_t max_steps = 400U) {
  for (std::uint32_t i = 0; i < max_steps && ft_test::outstanding() > 0U; ++i) ft_test::step();
  for (int i = 0; i < 3; ++i) ft_test::step();  // late duplicates would show here
}

/** Drains channel @p ch of @p dst, checking pattern and order; returns the messages. */
std::vector<udn::FtMessage> drain(bsp::TileId dst, std::uint32_t ch) {
  std::vector<udn::FtMessage> out;
  udn::FtMessage m{};
  while (udn::ft_receive(g_nodes[dst], ch, m) == udn::FtError::kOk) out.push_back(m);
  return out;
}

bool intact(const udn::FtMessage& m) {
  if (m.data_words != kWords) return false;
  for (std::uint32_t i = 0; i < kWords; ++i) {
    if (m.data[i] != ft_test::pattern(m.source, m.channel, m.seq, i)) return false;
  }
  return true;
}

TEST(FtLink, EverySingleBitFlipIsDeliveredOnceIntactAtTheRightTile) {
  const udn::FaultMap map = ft_test::grid_map();
  const bsp::TileId src = 9U;
  const bsp::TileId dst = 46U;
  const std::uint32_t image_words = static_cast<std::uint32_t>(udn::ft_packet_words(kWords, true));
  std::uint64_t corrected = 0;
  std::uint64_t forwarded = 0;
  for (std::uint32_t w = 0; w < image_words; ++w) {
    ft_test::boot(map);  // a fresh board per word: the injector's plan holds 256 entries
    for (std::uint32_t b = 0, seq = 0; b < 32U; ++b, ++seq) {
      SCOPED_TRACE(testing::Message() << "word " << w << " bit " << b);
      // The injector arms a flip of (word, bit) for the next packet src sends: the network
      // flips it in transit, so header flips really misroute, resize or drop the packet.
      bsp::FaultSpec f{};
      f.cycle = bsp::board_time();
      f.kind = bsp::FaultKind::kPacketBitFlip;
      f.tile = src;
      f.offset = w;
      f.bit = b;
      ASSERT_EQ(bsp::fault_plan_add(f), bsp::FaultError::kOk);
      ft_test::step();  // the plan entry arms at this barrier
      std::array<std::size_t, 64> before{};
      for (bsp::TileId t = 0; t < 64U; ++t) {
        before[t] = ft_test::g_events[t].size();
      }
      const auto d = message(src, 1U, seq & 0xFFU);
      ASSERT_EQ(udn::ft_send(g_nodes[src], dst, 1U, d, ft_test::now_tick()), udn::FtError::kOk);
      settle();
      // FDIR-EV-01: every flip is reported by the tile that saw it, naming the source where it can
      // (a correction or a forward), or as damage, or by the source's own resend after its timeout.
      std::uint32_t reports = 0;
      for (bsp::TileId t = 0; t < 64U; ++t) {
        for (std::size_t i = before[t]; i < ft_test::g_events[t].size(); ++i) {
          const udn::FtEvent& e = ft_test::g_events[t][i];
          const bool names_src = (e.cause == udn::FtCause::kCorrected || e.cause == udn::FtCause::kForwarded) &&
                                 e.peer == src;
          reports += (names_src || e.cause == udn::FtCause::kDamaged ||
                      (t == src && e.cause == udn::FtCause::kResentTimeout)) ? 1U : 0U;
        }
      }
      // Bits 24-31 of the hardware header are not read by the network: such a flip changes nothing
      // the packet does (the receiver rebuilds the word) and is masked.
      const bool masked = w == 0U && b >= 24U;
      if (masked) {
        EXPECT_EQ(reports, 0U) << "a masked flip changes nothing the packet does: nothing to report";
      } else {
        EXPECT_GE(reports, 1U) << "a flip nobody reported";
      }
      const auto got = drain(dst, 1U);
      ASSERT_EQ(got.size(), 1U);
      EXPECT_EQ(got[0].source, src);
      EXPECT_EQ(got[0].seq, seq & 0xFFU);
      EXPECT_TRUE(intact(got[0]));
      for (bsp::TileId t = 0; t < 64U; ++t) {
        if (t != dst) {
          EXPECT_TRUE(drain(t, 1U).empty()) << "delivered at tile " << t;
        }
      }
    }
    corrected += ft_test::total([](const udn::FtStats& s) { return s.corrected; });
    forwarded += ft_test::total([](const udn::FtStats& s) { return s.forwarded; });
    EXPECT_EQ(ft_test::total([](const udn::FtStats& s) { return s.gave_up; }), 0U);
  }
  EXPECT_GT(corrected, 200U);
  EXPECT_GT(forwarded, 0U) << "a flipped x or y bit must misdeliver and be forwarded";
}

TEST(FtLink, DoubleErrorsAreDetectedAndRecoveredByRetransmission) {
  const udn::FaultMap map = ft_test::grid_map();
  ft_test::boot(map);
  // Two bits in one data word (data code: NACK path), two in the channel word (route code:
  // no trusted source, timeout path), and data plus CRC word together.
  const std::vector<std::vector<std::pair<std::uint32_t, std::uint32_t>>> cases = {
      {{5U, 0U}, {5U, 7U}}, {{4U, 3U}, {4U, 20U}}, {{6U, 1U}, {8U, 30U}}};
  std::uint32_t seq = 0;
  for (const auto& bits : cases) {
    ft_test::g_flip = ft_test::FlipPlan{0U, bits, 1U};
    ASSERT_EQ(udn::ft_send(g_nodes[0], 63U, 0U, message(0U, 0U, seq), ft_test::now_tick()), udn::FtError::kOk);
    settle();
    const auto got = drain(63U, 0U);
    ASSERT_EQ(got.size(), 1U);
    EXPECT_TRUE(intact(got[0]));
    ++seq;
  }
  EXPECT_GE(ft_test::total([](const udn::FtStats& s) { return s.uncorrectable_detected; }), 3U);
  EXPECT_GE(g_nodes[0].stats.retransmitted, 3U);
  EXPECT_GE(g_nodes[63].stats.nacks_sent, 1U);
  // Each damaged packet is an event at the receiver; the NACKed one names its source.
  EXPECT_GE(ft_test::events_of(63U, udn::FtCause::kDamaged).size(), 3U);
  EXPECT_GE(ft_test::events_of(0U, udn::FtCause::kResentNack).size(), 1U);
}

TEST(FtLink, Figure6TrafficIsForwardedByTheIntermediateTile) {
  udn::FaultMap map = ft_test::grid_map();
  ASSERT_EQ(udn::fault_map_fail_tile(map, 8U), udn::RouteError::kOk);
  ASSERT_EQ(udn::fault_map_fail_tile(map, 9U), udn::RouteError::kOk);
  ft_test::boot(map);
  ASSERT_EQ(bsp::udn_net_fail_switch(8U), bsp::NetError::kOk);
  ASSERT_EQ(bsp::udn_net_fail_switch(9U), bsp::NetError::kOk);
  for (std::uint32_t s = 0; s < 5U; ++s) {
    ASSERT_EQ(udn::ft_send(g_nodes[0], 17U, 2U, message(0U, 2U, s), ft_test::now_tick()), udn::FtError::kOk);
  }
  settle();
  const auto got = drain(17U, 2U);
  ASSERT_EQ(got.size(), 5U);
  for (std::uint32_t s = 0; s < 5U; ++s) {
    EXPECT_EQ(got[s].seq, s);
    EXPECT_TRUE(intact(got[s]));
  }
  EXPECT_EQ(g_nodes[18].stats.forwarded, 5U);
  EXPECT_EQ(g_nodes[0].stats.retransmitted, 0U);
  // A detour leg passing through is routing, not a fault: no event.
  EXPECT_TRUE(ft_test::events_of(18U, udn::FtCause::kForwarded).empty());
}

// FDIR-TR-15: a packet sent with a twin goes by its route and, as a copy, through the twin, which
// forwards it: the receiver takes one and drops the other. A failed link on the route the map does not
// know of (it is silent) loses nothing: the copy arrives, in order.
TEST(FtLink, ATwinCopyArrivesWhenTheRouteIsCutAndIsADuplicateWhenItIsNot) {
  udn::FaultMap map = ft_test::grid_map();
  ft_test::boot(map);
  // Tile 6 to tile 0 goes along row 0; twin 19's legs (6-5-4-3-11-19, 19-18-17-16-8-0) avoid it.
  bsp::Work work{};
  const bsp::TileId twin =
      udn::route_twin_via(map, 6U, 0U, udn::path_tiles(map, 6U, 0U), udn::path_links(map, 6U, 0U), 0U, work);
  ASSERT_NE(twin, bsp::kNoTile);
  EXPECT_EQ(udn::path_tiles(map, 6U, twin) & udn::path_tiles(map, twin, 0U) & udn::path_tiles(map, 6U, 0U) &
                ~std::uint64_t{(1U << 6U) | 1U},
            0U);
  EXPECT_GT(work.int_ops, 0U) << "the search is counted";
  for (std::uint32_t s = 0; s < 3U; ++s) {
    ASSERT_EQ(udn::ft_send(g_nodes[6], 0U, 2U, message(6U, 2U, s), ft_test::now_tick(), twin), udn::FtError::kOk);
  }
  settle();
  auto got = drain(0U, 2U);
  ASSERT_EQ(got.size(), 3U);
  EXPECT_EQ(g_nodes[6].stats.twin_copies, 3U);
  EXPECT_EQ(g_nodes[twin].stats.forwarded, 3U);
  EXPECT_EQ(g_nodes[0].stats.duplicates_dropped + g_nodes[0].stats.out_of_order_dropped, 3U) << "one of each pair";
  // Link 1-2 fails, and nobody tells the map: the route's packets die there, the copies arrive.
  ASSERT_EQ(bsp::udn_net_fail_link(1U, bsp::UdnDir::kEast), bsp::NetError::kOk);
  for (std::uint32_t s = 3U; s < 6U; ++s) {
    ASSERT_EQ(udn::ft_send(g_nodes[6], 0U, 2U, message(6U, 2U, s), ft_test::now_tick(), twin), udn::FtError::kOk);
  }
  settle();
  got = drain(0U, 2U);
  ASSERT_EQ(got.size(), 3U);
  for (std::uint32_t s = 0; s < 3U; ++s) {
    EXPECT_EQ(got[s].seq, s + 3U);
    EXPECT_TRUE(intact(got[s]));
  }
  // Without a twin, the same packets are lost on the route.
  for (std::uint32_t s = 6U; s < 8U; ++s) {
    ASSERT_EQ(udn::ft_send(g_nodes[6], 0U, 2U, message(6U, 2U, s), ft_test::now_tick()), udn::FtError::kOk);
  }
  settle();
  EXPECT_TRUE(drain(0U, 2U).empty());
}

TEST(FtLink, UnreachableAndGiveUpAreLoggedEvents) {
  udn::FaultMap map = ft_test::grid_map();
  ASSERT_EQ(udn::fault_map_fail_tile(map, 1U), udn::RouteError::kOk);
  ASSERT_EQ(udn::fault_map_fail_tile(map, 8U), udn::RouteError::kOk);
  ft_test::boot(map, 7U, udn::FtConfig{2U, 3U});
  // Tile 0 is walled in by its two failed neighbours.
  EXPECT_EQ(udn::ft_send(g_nodes[0], 5U, 0U, message(0U, 0U, 0U), ft_test::now_tick()), udn::FtError::kUnreachable);
  ASSERT_EQ(ft_test::g_events[0].size(), 1U);
  EXPECT_EQ(ft_test::g_events[0][0].cause, udn::FtCause::kUnreachable);
  // A switch fails that the map does not know yet: sends go out and are never acknowledged.
  ASSERT_EQ(bsp::udn_net_fail_switch(30U), bsp::NetError::kOk);
  for (std::uint32_t s = 0; s < 3U; ++s) {
    ASSERT_EQ(udn::ft_send(g_nodes[27], 31U, 1U, message(27U, 1U, s), ft_test::now_tick()), udn::FtError::kOk);
  }
  settle();  // the give-up, then the SYNC that resynchronises the stream, unanswered too
  EXPECT_EQ(ft_test::outstanding(), 0U);
  EXPECT_EQ(g_nodes[27].stats.gave_up, 3U);
  const std::vector<udn::FtEvent> gave_up = ft_test::events_of(27U, udn::FtCause::kRetriesExhausted);
  ASSERT_EQ(gave_up.size(), 3U);
  for (const udn::FtEvent& e : gave_up) {
    EXPECT_EQ(e.peer, 31U);
  }
  // Each retry round was reported once per stream, as a resend after a timeout.
  EXPECT_EQ(ft_test::events_of(27U, udn::FtCause::kResentTimeout).size(), 3U);
  // The map learns of it: the stream resynchronises and the next message arrives, via a detour.
  ASSERT_EQ(udn::fault_map_fail_tile(map, 30U), udn::RouteError::kOk);
  for (auto& n : g_nodes) {
    bsp::Work w{};
    ASSERT_EQ(udn::ft_set_fault_map(n, map, w), udn::FtError::kOk);
  }
  ASSERT_EQ(udn::ft_send(g_nodes[27], 31U, 1U, message(27U, 1U, 3U), ft_test::now_tick()), udn::FtError::kOk);
  settle();
  const auto got = drain(31U, 1U);
  ASSERT_EQ(got.size(), 1U);
  EXPECT_EQ(got[0].seq, 3U);
  EXPECT_TRUE(intact(got[0]));
}

}  // namespace

namespace {

std::uint32_t g_credits = 8U;
std::uint32_t test_credits(void* /*ctx*/, bsp::TileId /*self*/) { return g_credits; }

}  // namespace

// A tile whose data waits in the network (say, for a hung tile's full queue) keeps
// kFtReplyReserve send credits for ACKs and PONGs, so it still answers its neighbours'
// probes and is not blamed; data, forwards and its own PINGs wait for credits beyond it.
TEST(FtLink, RepliesKeepTheirReserveOfSendCredits) {
  ft_test::boot(ft_test::grid_map());
  udn::FtPort port{&ft_test::host_send, &ft_test::host_receive, nullptr, &test_credits};
  ASSERT_EQ(udn::ft_init(g_nodes[9], 9U, ft_test::grid_map(), port, udn::FtConfig{}), udn::FtError::kOk);
  g_credits = udn::kFtReplyReserve;
  EXPECT_EQ(udn::ft_send(g_nodes[9], 10U, 0U, message(9U, 0U, 0U), ft_test::now_tick()), udn::FtError::kNetFull)
      << "data waits for credits beyond the reserve";
  EXPECT_EQ(udn::ft_send_control(g_nodes[9], 10U, udn::FtKind::kPing, 0U, 0x8000'0001U, false),
            udn::FtError::kNetFull)
      << "a probe is not a reply";
  EXPECT_EQ(udn::ft_send_control(g_nodes[9], 10U, udn::FtKind::kPong, 0U, 0x8000'0001U, false), udn::FtError::kOk);
  EXPECT_EQ(udn::ft_send_control(g_nodes[9], 10U, udn::FtKind::kAck, 0U, 0U, true), udn::FtError::kOk);
  // A PING from a neighbour is answered from the reserve.
  ASSERT_EQ(udn::ft_send_control(g_nodes[1], 9U, udn::FtKind::kPing, 0U, 0x8000'0042U, false), udn::FtError::kOk);
  for (int i = 0; i < 10; ++i) ft_test::step();  // a leg shows about two quanta after its send
  EXPECT_EQ(g_nodes[1].pong_nonce[9], 0x8000'0042U);
  // With credits beyond the reserve, data goes again.
  g_credits = udn::kFtReplyReserve + 1U;
  EXPECT_EQ(udn::ft_send(g_nodes[9], 10U, 0U, message(9U, 0U, 0U), ft_test::now_tick()), udn::FtError::kOk);
  settle();
  const auto got = drain(10U, 0U);
  ASSERT_EQ(got.size(), 1U);
  EXPECT_TRUE(intact(got[0]));
}

// A PONG the network refuses is owed and sent by the next polls: the prober scores it a round later.
namespace {
bool g_refuse = false;
bsp::NetError refusing_send(void* ctx, bsp::TileId self, std::span<const std::uint32_t> words) {
  return g_refuse ? bsp::NetError::kFull : ft_test::host_send(ctx, self, words);
}
}  // namespace

TEST(FtLink, ARefusedPongIsOwedAndSentLater) {
  ft_test::boot(ft_test::grid_map());
  const udn::FtPort port{&refusing_send, &ft_test::host_receive, nullptr, nullptr};
  ASSERT_EQ(udn::ft_init(g_nodes[9], 9U, ft_test::grid_map(), port, udn::FtConfig{}), udn::FtError::kOk);
  g_refuse = true;
  ASSERT_EQ(udn::ft_send_control(g_nodes[1], 9U, udn::FtKind::kPing, 0U, 0x8000'0077U, false), udn::FtError::kOk);
  for (int i = 0; i < 10; ++i) ft_test::step();
  EXPECT_EQ(g_nodes[9].pongs_owed, 1U) << "the answer could not leave: owed";
  EXPECT_NE(g_nodes[1].pong_nonce[9], 0x8000'0077U);
  g_refuse = false;
  for (int i = 0; i < 10; ++i) ft_test::step();
  EXPECT_EQ(g_nodes[9].pongs_owed, 0U);
  EXPECT_EQ(g_nodes[1].pong_nonce[9], 0x8000'0077U);
}

// ------------------------------------------------------------------ restarts

namespace {

/** Restarts node @p t as a reset tile's endpoint does: ft_init again, a new epoch. */
void restart(bsp::TileId t, std::uint32_t epoch) {
  const udn::FtPort port{&ft_test::host_send, &ft_test::host_receive, nullptr};
  ASSERT_EQ(udn::ft_init(g_nodes[t], t, ft_test::grid_map(), port, udn::FtConfig{}), udn::FtError::kOk);
  udn::ft_set_event_sink(g_nodes[t], udn::FtEventSink{&ft_test::record_event, nullptr});
  udn::ft_set_epoch(g_nodes[t], epoch);
}

/** What tile 20 took on channel 2 since the last take_got(). */
std::vector<udn::FtMessage> g_got;

std::vector<udn::FtMessage> take_got() {
  std::vector<udn::FtMessage> out;
  out.swap(g_got);
  return out;
}

/** Sends @p count messages 10 -> 20 on channel 2 from sequence number @p first, taking each delivery. */
void send_run(std::uint32_t first, std::uint32_t count) {
  for (std::uint32_t s = first; s < first + count; ++s) {
    ASSERT_EQ(udn::ft_send(g_nodes[10], 20U, 2U, message(10U, 2U, s % 256U), ft_test::now_tick()),
              udn::FtError::kOk);
    settle();
    for (const udn::FtMessage& m : drain(20U, 2U)) g_got.push_back(m);
  }
}

}  // namespace

// A reset receiver expects sequence 0 while its peer goes on: it asks for a resync and joins
// the stream in progress at the sender's oldest outstanding packet.
TEST(FtLink, ARestartedReceiverJoinsTheStreamInProgress) {
  ft_test::boot(ft_test::grid_map());
  (void)take_got();
  send_run(0U, 20U);
  ASSERT_EQ(take_got().size(), 20U);
  restart(20U, 1U);
  send_run(20U, 5U);
  const auto got = take_got();
  ASSERT_EQ(got.size(), 5U);
  for (std::uint32_t i = 0; i < 5U; ++i) {
    EXPECT_EQ(got[i].seq, 20U + i);
    EXPECT_TRUE(intact(got[i]));
  }
  EXPECT_EQ(g_nodes[10].stats.gave_up, 0U);
  // One resend: the first packet after the restart asks for a resync and comes again, flagged.
  EXPECT_EQ(g_nodes[10].stats.retransmitted, 1U);
  EXPECT_EQ(g_nodes[20].stats.duplicates_dropped, 0U);
}

// A reset sender starts again at sequence 0 while the receiver expects 20: its first packet,
// flagged, starts the stream again; nothing is lost, nothing delivered twice.
TEST(FtLink, ARestartedSenderStartsItsStreamsAgain) {
  ft_test::boot(ft_test::grid_map());
  (void)take_got();
  send_run(0U, 20U);
  ASSERT_EQ(take_got().size(), 20U);
  restart(10U, 1U);
  send_run(0U, 5U);
  const auto got = take_got();
  ASSERT_EQ(got.size(), 5U);
  for (std::uint32_t i = 0; i < 5U; ++i) {
    EXPECT_EQ(got[i].seq, i);
    EXPECT_TRUE(intact(got[i]));
  }
  EXPECT_EQ(g_nodes[10].stats.gave_up, 0U);
  // Restarted twice with one message each time (a boot report): both arrive.
  restart(10U, 2U);
  send_run(0U, 1U);
  restart(10U, 3U);
  send_run(0U, 1U);
  EXPECT_EQ(take_got().size(), 2U);
  EXPECT_EQ(g_nodes[10].stats.gave_up, 0U);
}

// The flagged first packet of a restarted sender is delivered, its ACK lost: the
// retransmission is a duplicate, not a second delivery.
TEST(FtLink, ALostAckOfTheFirstPacketDoesNotDeliverItTwice) {
  ft_test::boot(ft_test::grid_map());
  (void)take_got();
  send_run(0U, 3U);
  ASSERT_EQ(take_got().size(), 3U);
  restart(10U, 5U);
  // Corrupt the receiver's next ACK beyond repair: both its data words flipped twice.
  ft_test::g_flip = ft_test::FlipPlan{20U, {{5U, 0U}, {5U, 1U}, {6U, 0U}, {6U, 1U}}, 1U};
  ASSERT_EQ(udn::ft_send(g_nodes[10], 20U, 2U, message(10U, 2U, 0U), ft_test::now_tick()), udn::FtError::kOk);
  settle();
  EXPECT_EQ(drain(20U, 2U).size(), 1U);
  EXPECT_EQ(ft_test::outstanding(), 0U);
}

// An ACK that answers a sender's previous incarnation is not taken for the new one's.
TEST(FtLink, AStaleAckIsNotTakenByTheRestartedSender) {
  ft_test::boot(ft_test::grid_map());
  (void)take_got();
  send_run(0U, 2U);
  ASSERT_EQ(take_got().size(), 2U);
  restart(10U, 1U);
  // The first packet of the new incarnation is damaged beyond repair: only its resend can deliver it.
  ft_test::g_flip = ft_test::FlipPlan{10U, {{5U, 0U}, {5U, 1U}}, 1U};
  ASSERT_EQ(udn::ft_send(g_nodes[10], 20U, 2U, message(10U, 2U, 0U), ft_test::now_tick()), udn::FtError::kOk);
  // Meanwhile an ACK of epoch 0 for sequence 5 comes in: it must not free the packet.
  ASSERT_EQ(udn::ft_send_control(g_nodes[20], 10U, udn::FtKind::kAck, 5U, 2U, true), udn::FtError::kOk);
  for (int i = 0; i < 2; ++i) ft_test::step();
  settle();
  const auto got = drain(20U, 2U);
  ASSERT_EQ(got.size(), 1U);  // resent, delivered, and acknowledged by the receiver, not by the stale ACK
  EXPECT_EQ(got[0].seq, 0U);
  EXPECT_TRUE(intact(got[0]));
  EXPECT_GE(g_nodes[10].stats.retransmitted, 1U);
  EXPECT_EQ(g_nodes[10].stats.gave_up, 0U);
}

// ------------------------------------------------------------------ give-ups

namespace {

/** Packets the network loses on the way (the sender sees them leave): by sending tile and kind; none when empty. */
std::function<bool(bsp::TileId, udn::FtKind)> g_lose;

bsp::NetError losing_send(void* ctx, bsp::TileId self, std::span<const std::uint32_t> words) {
  const auto kind = static_cast<udn::FtKind>((words[udn::kWordChannel] >> 12U) & 0xFU);
  return (g_lose && g_lose(self, kind)) ? bsp::NetError::kOk : ft_test::host_send(ctx, self, words);
}

/** Tiles 10 and 20 on the losing port, timeouts of 1 tick and one retry: give-ups come fast. */
void boot_losing() {
  const udn::FtConfig cfg{1U, 1U};
  ft_test::boot(ft_test::grid_map(), 7U, cfg);
  const udn::FtPort port{&losing_send, &ft_test::host_receive, nullptr};
  for (const bsp::TileId t : {bsp::TileId{10}, bsp::TileId{20}}) {
    ASSERT_EQ(udn::ft_init(g_nodes[t], t, ft_test::grid_map(), port, cfg), udn::FtError::kOk);
    udn::ft_set_event_sink(g_nodes[t], udn::FtEventSink{&ft_test::record_event, nullptr});
  }
  g_lose = nullptr;
}

/** Boots the pair and delivers 3 messages 10 -> 20 on channel 2: the receiver follows the stream. */
void start_stream() {
  boot_losing();
  (void)take_got();
  send_run(0U, 3U);
  ASSERT_EQ(take_got().size(), 3U);
}

/** Sends messages @p first .. @p last - 1 10 -> 20 on channel 2 without waiting for them. */
void send_from(std::uint32_t first, std::uint32_t last) {
  for (std::uint32_t i = first; i < last; ++i) {
    ASSERT_EQ(udn::ft_send(g_nodes[10], 20U, 2U, message(10U, 2U, i), ft_test::now_tick()), udn::FtError::kOk);
  }
}

/** The receiver's ACKs are lost. */
bool acks_lost(bsp::TileId self, udn::FtKind k) { return self == 20U && k == udn::FtKind::kAck; }

/** Sends messages 10 -> 20 on channel 2 (payloads numbered from @p first) until @p count were given up. */
void give_up_in_a_row(std::uint32_t first, std::uint32_t count) {
  std::uint32_t sent = 0U;
  for (std::uint32_t i = 0U; i < 200000U && g_nodes[10].stats.gave_up < count; ++i) {
    if (sent < count &&
        udn::ft_send(g_nodes[10], 20U, 2U, message(10U, 2U, first + sent), ft_test::now_tick()) == udn::FtError::kOk) {
      ++sent;
    }
    ft_test::step();
  }
}

/** Sends one message 10 -> 20 on channel 2 and runs until it is acknowledged. @return what 20 got. */
std::vector<udn::FtMessage> send_one(const std::vector<std::uint32_t>& m) {
  EXPECT_EQ(udn::ft_send(g_nodes[10], 20U, 2U, m, ft_test::now_tick()), udn::FtError::kOk);
  settle();
  return drain(20U, 2U);
}

/** What tile 10's events said of the packets it gave up: (seq, FtDelivery) of its give-ups, then of its settlings. */
std::vector<std::pair<std::uint32_t, udn::FtDelivery>> claims(udn::FtCause cause) {
  std::vector<std::pair<std::uint32_t, udn::FtDelivery>> out;
  for (const udn::FtEvent& e : ft_test::events_of(10U, cause)) {
    out.emplace_back(e.seq, static_cast<udn::FtDelivery>(e.word));
  }
  return out;
}

}  // namespace

class FtLinkGiveUpsInARow : public testing::TestWithParam<std::uint32_t> {};

// FT-RESYNC-01: however many messages of one stream are given up in a row (the receiver's
// state kept all along), the stream resynchronises and the next message arrives, alone.
TEST_P(FtLinkGiveUpsInARow, TheStreamResynchronisesAndTheNextMessageArrives) {
  const std::uint32_t n = GetParam();
  start_stream();
  g_lose = [](bsp::TileId self, udn::FtKind) { return self == 10U; };
  give_up_in_a_row(3U, n);
  ASSERT_EQ(g_nodes[10].stats.gave_up, n);
  EXPECT_TRUE(drain(20U, 2U).empty());
  g_lose = nullptr;
  const auto last = message(10U, 2U, 3U + n);
  const auto got = send_one(last);
  ASSERT_EQ(got.size(), 1U) << "after " << n << " give-ups";
  EXPECT_TRUE(std::equal(last.begin(), last.end(), got[0].data.begin()));
  EXPECT_EQ(ft_test::outstanding(), 0U);
  // FT-GU-01: every one reported once; none said delivered, for none arrived.
  const udn::FtStats& st = g_nodes[10].stats;
  EXPECT_EQ(st.gave_up, n);
  EXPECT_EQ(claims(udn::FtCause::kRetriesExhausted).size(), n);
  EXPECT_EQ(st.gave_up_unknown + st.gave_up_not_delivered, n);
  EXPECT_GT(st.gave_up_not_delivered, 0U) << "packets waited for a SYNC, never left, and said so";
  // The SYNC that got through carried the receiver's record: every packet that left is settled, skipped.
  EXPECT_EQ(st.settled_not_delivered, st.gave_up_unknown);
  EXPECT_EQ(st.settled_delivered, 0U);
}

INSTANTIATE_TEST_SUITE_P(Counts, FtLinkGiveUpsInARow, testing::Values(128U, 200U, 255U, 256U, 1000U));

// FT-GU-01: packets that arrived, their ACKs lost, are given up with their delivery unknown, never
// as not delivered; the next packet's answer carries the receiver's record: delivered, ACKs lost.
TEST(FtLinkGiveUp, ArrivedPacketsWhoseAcksAreLostAreSettledDelivered) {
  start_stream();
  g_lose = &acks_lost;
  send_from(3U, 6U);
  settle();
  EXPECT_EQ(drain(20U, 2U).size(), 3U) << "they arrived";
  EXPECT_EQ(g_nodes[10].stats.gave_up, 3U) << "their ACKs did not";
  ASSERT_EQ(claims(udn::FtCause::kRetriesExhausted).size(), 3U) << "each give-up is reported";
  for (const auto& [seq, d] : claims(udn::FtCause::kRetriesExhausted)) {
    EXPECT_EQ(d, udn::FtDelivery::kUnknown) << "seq " << seq;
  }
  g_lose = nullptr;
  EXPECT_EQ(send_one(message(10U, 2U, 6U)).size(), 1U);
  const auto settled = claims(udn::FtCause::kSettled);
  ASSERT_EQ(settled.size(), 3U);
  for (std::uint32_t i = 0; i < 3U; ++i) {
    EXPECT_EQ(settled[i].first, 3U + i);
    EXPECT_EQ(settled[i].second, udn::FtDelivery::kDelivered);
  }
  EXPECT_EQ(g_nodes[10].stats.settled_delivered, 3U);
  EXPECT_EQ(g_nodes[10].stats.settled_not_delivered, 0U);
}

// FT-GU-02: of a run given up, those the receiver took before are settled delivered, the rest
// not delivered (the receiver skipped them at the resync point), each by its sequence number.
TEST(FtLinkGiveUp, APartlyDeliveredRunIsSettledPacketByPacket) {
  start_stream();
  // Two arrive and lose their ACKs; the data of the next three is lost.
  g_lose = &acks_lost;
  send_from(3U, 5U);
  for (int i = 0; i < 4; ++i) ft_test::step();
  ASSERT_EQ(drain(20U, 2U).size(), 2U);
  g_lose = [](bsp::TileId self, udn::FtKind k) { return acks_lost(self, k) || (self == 10U && k == udn::FtKind::kData); };
  send_from(5U, 8U);
  settle();
  EXPECT_EQ(g_nodes[10].stats.gave_up, 5U);
  EXPECT_EQ(claims(udn::FtCause::kRetriesExhausted).size(), 5U);
  g_lose = nullptr;
  const auto got = send_one(message(10U, 2U, 8U));
  ASSERT_EQ(got.size(), 1U);
  EXPECT_EQ(got[0].seq, 8U);
  const auto settled = claims(udn::FtCause::kSettled);
  ASSERT_EQ(settled.size(), 5U);
  for (std::uint32_t i = 0; i < 5U; ++i) {
    EXPECT_EQ(settled[i].first, 3U + i);
    EXPECT_EQ(settled[i].second, i < 2U ? udn::FtDelivery::kDelivered : udn::FtDelivery::kNotDelivered) << i;
  }
}

// FT-GU-03: a receiver that restarted cannot tell what its previous incarnation took: the
// give-ups stay "unknown", nothing is settled, and the stream goes on.
TEST(FtLinkGiveUp, AReceiverThatRestartedSettlesNothing) {
  start_stream();
  g_lose = &acks_lost;
  send_from(3U, 4U);
  settle();
  EXPECT_EQ(drain(20U, 2U).size(), 1U);
  EXPECT_EQ(g_nodes[10].stats.gave_up, 1U);
  g_lose = nullptr;
  const udn::FtPort port{&losing_send, &ft_test::host_receive, nullptr};
  ASSERT_EQ(udn::ft_init(g_nodes[20], 20U, ft_test::grid_map(), port, udn::FtConfig{1U, 1U}), udn::FtError::kOk);
  udn::ft_set_epoch(g_nodes[20], 1U);
  EXPECT_EQ(send_one(message(10U, 2U, 4U)).size(), 1U);
  EXPECT_TRUE(claims(udn::FtCause::kSettled).empty());
  EXPECT_EQ(g_nodes[10].stats.gave_up_unknown, 1U);
}

// ------------------------------------------------------------------ flow control

namespace {

/** Sends of tile 9 the network refuses from now on (counted down). */
std::uint32_t g_refuse_next = 0U;
bsp::NetError counted_refusal_send(void* ctx, bsp::TileId self, std::span<const std::uint32_t> words) {
  if (self == 9U && g_refuse_next > 0U) {
    --g_refuse_next;
    return bsp::NetError::kFull;
  }
  return ft_test::host_send(ctx, self, words);
}

/** The events of every node that say a packet was resent as a recovery (NACK or timeout). */
std::size_t recovery_resends() {
  std::size_t n = 0;
  for (bsp::TileId t = 0; t < 64U; ++t) {
    n += ft_test::events_of(t, udn::FtCause::kResentNack).size() +
         ft_test::events_of(t, udn::FtCause::kResentTimeout).size();
  }
  return n;
}

}  // namespace

// FT-FC-01: a full receive queue is flow control, not a fault. The receiver answers BUSY and
// NACKs nothing behind the packet that waits; the sender's timeout resend is counted as flow
// control and logged as no recovery; once the application drains, every message arrives once,
// in order, intact.
TEST(FtLinkFlowControl, AFullReceiveQueueAnswersBusyAndItsResendIsNoRecovery) {
  ft_test::boot(ft_test::grid_map());
  const bsp::TileId src = 9U;
  const bsp::TileId dst = 12U;
  const std::uint32_t total = udn::kFtRxDepth + 6U;
  std::uint32_t sent = 0;
  // The receiver's application takes nothing for a while: its channel queue fills.
  for (std::uint32_t i = 0; i < 60U; ++i) {
    while (sent < total &&
           udn::ft_send(g_nodes[src], dst, 1U, message(src, 1U, sent), ft_test::now_tick()) == udn::FtError::kOk) {
      ++sent;
    }
    ft_test::step();
  }
  EXPECT_EQ(g_nodes[dst].rxq[1].count, udn::kFtRxDepth);
  EXPECT_GE(g_nodes[dst].stats.rx_full_dropped, 1U);
  EXPECT_GE(g_nodes[dst].stats.busy_sent, 1U);
  EXPECT_EQ(g_nodes[dst].stats.nacks_sent, 0U) << "nothing behind a packet that waits for room is NACKed";
  EXPECT_GE(g_nodes[src].stats.resent_busy, 1U);
  EXPECT_EQ(recovery_resends(), 0U) << "flow control is logged as no recovery";
  // The application drains; the rest comes on the sender's next timeouts.
  std::vector<udn::FtMessage> got;
  for (std::uint32_t i = 0; i < 400U && (got.size() < total || ft_test::outstanding() > 0U); ++i) {
    while (sent < total &&
           udn::ft_send(g_nodes[src], dst, 1U, message(src, 1U, sent), ft_test::now_tick()) == udn::FtError::kOk) {
      ++sent;
    }
    for (const udn::FtMessage& m : drain(dst, 1U)) got.push_back(m);
    ft_test::step();
  }
  ASSERT_EQ(got.size(), total);
  for (std::uint32_t s = 0; s < total; ++s) {
    EXPECT_EQ(got[s].seq, s);
    EXPECT_TRUE(intact(got[s])) << s;
  }
  EXPECT_EQ(g_nodes[src].stats.gave_up, 0U);
  EXPECT_EQ(recovery_resends(), 0U);
}

// FT-FC-02: a resend the network refuses holds its stream: the packets after it, and new ones,
// wait behind it and leave in order, so the receiver never sees a gap to NACK.
TEST(FtLinkFlowControl, ARefusedResendHoldsItsStreamSoNothingOvertakesIt) {
  ft_test::boot(ft_test::grid_map());
  const udn::FtPort port{&counted_refusal_send, &ft_test::host_receive, nullptr};
  ASSERT_EQ(udn::ft_init(g_nodes[9], 9U, ft_test::grid_map(), port, udn::FtConfig{}), udn::FtError::kOk);
  udn::ft_set_event_sink(g_nodes[9], udn::FtEventSink{&ft_test::record_event, nullptr});
  // The stream runs; then a packet is damaged in transit beyond correction (two data bits): the
  // receiver NACKs it, and the network refuses the resend that answers the NACK.
  ASSERT_EQ(udn::ft_send(g_nodes[9], 10U, 0U, message(9U, 0U, 0U), ft_test::now_tick()), udn::FtError::kOk);
  settle();
  ft_test::g_flip = ft_test::FlipPlan{9U, {{udn::kWordData, 3U}, {udn::kWordData, 17U}}, 1U};
  ASSERT_EQ(udn::ft_send(g_nodes[9], 10U, 0U, message(9U, 0U, 1U), ft_test::now_tick()), udn::FtError::kOk);
  g_refuse_next = 1U;
  for (std::uint32_t i = 0; i < 40U && g_nodes[9].held_streams == 0U; ++i) ft_test::step();
  ASSERT_EQ(g_nodes[9].held_streams, 1U) << "the refused resend holds the stream";
  EXPECT_EQ(g_refuse_next, 0U);
  // A new message of the held stream is queued behind it, not sent ahead of it.
  ASSERT_EQ(udn::ft_send(g_nodes[9], 10U, 0U, message(9U, 0U, 2U), ft_test::now_tick()), udn::FtError::kOk);
  settle();
  EXPECT_EQ(g_nodes[9].held_streams, 0U);
  const auto got = drain(10U, 0U);
  ASSERT_EQ(got.size(), 3U);
  for (std::uint32_t s = 0; s < 3U; ++s) {
    EXPECT_EQ(got[s].seq, s);
    EXPECT_TRUE(intact(got[s]));
  }
  EXPECT_EQ(g_nodes[10].stats.nacks_sent, 1U) << "the damaged packet's NACK only: no gap behind the held resend";
  EXPECT_EQ(ft_test::events_of(9U, udn::FtCause::kResentNack).size(), 1U);
}

// FT-FC-03: the retransmit timeout follows the measured round trip (RFC 6298 on ticks, Karn's
// rule, the timeout doubled after a timeout resend until a packet sent once is answered): towards
// a receiver whose answers take 5 ticks to leave it, the fixed three-tick timeout would resend
// every packet; once the round trip is measured, none is resent, and nothing is lost or doubled.
namespace {
struct Delayed {
  std::uint32_t release_tick;
  std::vector<std::uint32_t> words;
};
std::vector<Delayed> g_delayed;
constexpr std::uint32_t kAnswerDelayTicks = 5U;

bsp::NetError delaying_send(void* /*ctx*/, bsp::TileId /*self*/, std::span<const std::uint32_t> words) {
  g_delayed.push_back(Delayed{ft_test::now_tick() + kAnswerDelayTicks, {words.begin(), words.end()}});
  return bsp::NetError::kOk;
}

/** Sends the delayed packets of tile @p self whose time has come, in order. */
void release_delayed(bsp::TileId self) {
  std::size_t k = 0;
  for (; k < g_delayed.size() && g_delayed[k].release_tick <= ft_test::now_tick(); ++k) {
    ASSERT_EQ(ft_test::host_send(nullptr, self, g_delayed[k].words), bsp::NetError::kOk);
  }
  g_delayed.erase(g_delayed.begin(), g_delayed.begin() + static_cast<std::ptrdiff_t>(k));
}
}  // namespace

TEST(FtLinkFlowControl, TheRetransmitTimeoutFollowsTheMeasuredRoundTrip) {
  ft_test::boot(ft_test::grid_map());
  const bsp::TileId src = 9U;
  const bsp::TileId dst = 12U;
  g_delayed.clear();
  const udn::FtPort port{&delaying_send, &ft_test::host_receive, nullptr};
  ASSERT_EQ(udn::ft_init(g_nodes[dst], dst, ft_test::grid_map(), port, udn::FtConfig{}), udn::FtError::kOk);
  std::uint32_t sent = 0;
  std::vector<udn::FtMessage> got;
  std::uint64_t resent_at_half = 0;
  constexpr std::uint32_t kTicks = 200U;
  for (std::uint32_t q = 0; q < kTicks * 4U; ++q) {
    if (q % 4U == 0U &&
        udn::ft_send(g_nodes[src], dst, 2U, message(src, 2U, sent), ft_test::now_tick()) == udn::FtError::kOk) {
      ++sent;
    }
    release_delayed(dst);
    ft_test::step();
    for (const udn::FtMessage& m : drain(dst, 2U)) got.push_back(m);
    if (q == kTicks * 2U) {
      resent_at_half = g_nodes[src].stats.retransmitted;
    }
  }
  for (std::uint32_t q = 0; q < 400U && ft_test::outstanding() > 0U; ++q) {
    release_delayed(dst);
    ft_test::step();
  }
  for (const udn::FtMessage& m : drain(dst, 2U)) got.push_back(m);
  ASSERT_EQ(got.size(), sent);
  for (std::uint32_t s = 0; s < sent; ++s) {
    EXPECT_EQ(got[s].seq, s % 256U);
  }
  EXPECT_GT(sent, 100U);
  EXPECT_GT(resent_at_half, 0U) << "the first packets are resent before any round trip is measured";
  EXPECT_GE(g_nodes[src].srtt8[dst] / 8U, kAnswerDelayTicks) << "the measured round trip";
  EXPECT_EQ(g_nodes[src].stats.retransmitted, resent_at_half) << "no resend in the second half";
  EXPECT_EQ(g_nodes[src].stats.gave_up, 0U);
}
