/**
 * @file ft_link_state_test.cpp
 * @brief A node's own state in tile RAM takes an upset (issue 54 item 6): every index, count and
 *        length the node follows is checked before use, a bad one resets its part, is counted and
 *        reported (FtCause::kStateRepaired), and the node goes on delivering.
 *
 * AddressSanitizer cannot see an index that stays inside the tile's RAM, so each test sets the
 * corrupted value itself and checks what the node does with it.
 */
#include "tests/udn/ft_link_fixture.hpp"

#include <gtest/gtest.h>

#include <cstdint>
#include <vector>

namespace {

using ft_test::g_nodes;

constexpr std::uint32_t kWords = 3U;

std::vector<std::uint32_t> message(std::uint32_t src, std::uint32_t ch, std::uint32_t seq) {
  std::vector<std::uint32_t> d(kWords);
  for (std::uint32_t i = 0; i < kWords; ++i) d[i] = ft_test::pattern(src, ch, seq, i);
  return d;
}

void settle(std::uint32_t max_steps = 600U) {
  for (std::uint32_t i = 0; i < max_steps && ft_test::outstanding() > 0U; ++i) ft_test::step();
  for (int i = 0; i < 3; ++i) ft_test::step();
}

bool intact(const udn::FtMessage& m) {
  if (m.data_words != kWords) return false;
  for (std::uint32_t i = 0; i < kWords; ++i) {
    if (m.data[i] != ft_test::pattern(m.source, m.channel, m.seq, i)) return false;
  }
  return true;
}

std::vector<udn::FtMessage> drain(bsp::TileId dst, std::uint32_t ch) {
  std::vector<udn::FtMessage> out;
  udn::FtMessage m{};
  for (int i = 0; i < 64 && udn::ft_receive(g_nodes[dst], ch, m) == udn::FtError::kOk; ++i) out.push_back(m);
  return out;
}

/** The repairs @p tile reported, as (part, index). */
std::vector<std::pair<udn::FtRepair, std::uint32_t>> repairs(bsp::TileId tile) {
  std::vector<std::pair<udn::FtRepair, std::uint32_t>> out;
  for (const udn::FtEvent& e : ft_test::events_of(tile, udn::FtCause::kStateRepaired)) {
    out.emplace_back(static_cast<udn::FtRepair>(e.channel), e.peer);
  }
  return out;
}

/** Sends messages @p first..@p last from 3 to 5 on channel 1 and lets them arrive. */
void send_run(std::uint32_t first, std::uint32_t last) {
  for (std::uint32_t s = first; s <= last; ++s) {
    ASSERT_EQ(udn::ft_send(g_nodes[3], 5U, 1U, message(3U, 1U, s), ft_test::now_tick()), udn::FtError::kOk);
  }
  settle();
}

// A receive queue's head or count off its ring empties the queue (its messages lost, the tile
// reports it); the next message arrives and is taken as usual.
TEST(FtLinkState, AnUpsetReceiveQueueIsEmptiedAndReported) {
  for (const bool head : {true, false}) {
    ft_test::boot(ft_test::grid_map());
    send_run(0U, 1U);
    udn::detail::RxQueue& q = g_nodes[5].rxq[1];
    ASSERT_EQ(q.count, 2U);
    (head ? q.head : q.count) ^= 1U << 20U;  // far off the ring of 8
    udn::FtMessage m{};
    EXPECT_EQ(udn::ft_receive(g_nodes[5], 1U, m), udn::FtError::kEmpty) << head;
    EXPECT_EQ(q.head, 0U);
    EXPECT_EQ(q.count, 0U);
    ASSERT_EQ(repairs(5U).size(), 1U);
    EXPECT_EQ(repairs(5U)[0], std::make_pair(udn::FtRepair::kRxQueue, 1U));
    EXPECT_EQ(g_nodes[5].state_repairs, 1U);
    send_run(2U, 2U);
    const std::vector<udn::FtMessage> got = drain(5U, 1U);
    ASSERT_EQ(got.size(), 1U);
    EXPECT_EQ(got[0].seq, 2U);
    EXPECT_TRUE(intact(got[0]));
  }
}

// A queued message whose length or source no message has is dropped when taken; the one behind it
// is handed out whole. A flipped payload word is data: handed out as it is (the CRC guarded the wire).
TEST(FtLinkState, AQueuedMessageWithAnUpsetLengthOrSourceIsDropped) {
  ft_test::boot(ft_test::grid_map());
  send_run(0U, 3U);
  udn::detail::RxQueue& q = g_nodes[5].rxq[1];
  ASSERT_EQ(q.count, 4U);
  q.msg[q.head].data_words = 0x8003U;
  q.msg[(q.head + 1U) % udn::kFtRxDepth].source = 3U | 0x100U;
  q.msg[(q.head + 2U) % udn::kFtRxDepth].data_words = 0U;
  q.msg[(q.head + 3U) % udn::kFtRxDepth].data[0] ^= 1U;
  udn::FtMessage m{};
  ASSERT_EQ(udn::ft_receive(g_nodes[5], 1U, m), udn::FtError::kOk);
  EXPECT_EQ(m.seq, 3U) << "the three upset ones dropped";
  EXPECT_EQ(m.data_words, kWords);
  EXPECT_FALSE(intact(m)) << "a payload flip is a corrupted message, not the node's state";
  EXPECT_EQ(repairs(5U).size(), 3U);
  EXPECT_EQ(udn::ft_receive(g_nodes[5], 1U, m), udn::FtError::kEmpty);
  EXPECT_EQ(g_nodes[5].rx_ready, 0U);
}

// A send slot whose destination, channel or length is off its arrays is freed and its window
// counted again; the stream recovers (give-up and resync) and the next message arrives.
TEST(FtLinkState, AnUpsetSendSlotIsFreedAndTheStreamRecovers) {
  for (int field = 0; field < 3; ++field) {
    ft_test::boot(ft_test::grid_map(), 7U, udn::FtConfig{2U, 3U});
    ASSERT_EQ(udn::ft_send(g_nodes[3], 5U, 1U, message(3U, 1U, 0U), ft_test::now_tick()), udn::FtError::kOk);
    udn::detail::TxSlot* slot = nullptr;
    for (udn::detail::TxSlot& s : g_nodes[3].tx) slot = (slot == nullptr && s.used) ? &s : slot;
    ASSERT_NE(slot, nullptr);
    if (field == 0) slot->dest ^= 0x80U;
    if (field == 1) slot->channel ^= 0x40U;
    if (field == 2) slot->words ^= 1U << 12U;
    EXPECT_EQ(udn::ft_poll(g_nodes[3], ft_test::now_tick(), 0U), 0U);
    EXPECT_FALSE(slot->used) << field;
    EXPECT_EQ(g_nodes[3].in_window[5], 0U) << "counted again from the slots";
    const auto r = repairs(3U);
    ASSERT_EQ(r.size(), 2U) << field;
    EXPECT_EQ(r[0].first, udn::FtRepair::kTxSlot);
    EXPECT_EQ(r[1], std::make_pair(udn::FtRepair::kWindow, 5U));
    send_run(1U, 2U);
    const std::vector<udn::FtMessage> got = drain(5U, 1U);
    ASSERT_FALSE(got.empty()) << field;
    EXPECT_EQ(got.back().seq, 2U);
    EXPECT_TRUE(intact(got.back()));
  }
}

// A window count that no slot backs (it would refuse every send to the destination) is counted again.
TEST(FtLinkState, AnUpsetWindowCountIsCountedAgain) {
  ft_test::boot(ft_test::grid_map());
  g_nodes[3].in_window[5] = udn::kFtWindow;
  send_run(0U, 0U);
  EXPECT_EQ(drain(5U, 1U).size(), 1U);
  EXPECT_EQ(repairs(3U), (std::vector{std::make_pair(udn::FtRepair::kWindow, 5U)}));
}

// The route table's grid or tile upset: nothing is routed by it (no division by an upset grid, no
// index past the tables) until the owner rebuilds it from its map.
TEST(FtLinkState, AnUpsetRouteGridStopsTheNodeUntilItsRoutesAreRebuilt) {
  const udn::FaultMap map = ft_test::grid_map();
  for (int field = 0; field < 4; ++field) {
    ft_test::boot(map);
    udn::RouteTable& r = g_nodes[3].routes;
    if (field == 0) r.cols = 0U;
    if (field == 1) r.tiles |= 0x100U;
    if (field == 2) r.self ^= 1U;
    if (field == 3) r.cols = 7U;
    EXPECT_FALSE(udn::ft_routes_ok(g_nodes[3])) << field;
    EXPECT_EQ(udn::ft_poll(g_nodes[3], ft_test::now_tick(), 8U), 0U);
    EXPECT_EQ(udn::ft_send(g_nodes[3], 5U, 1U, message(3U, 1U, 0U), ft_test::now_tick()), udn::FtError::kBadArgs);
    EXPECT_EQ(udn::ft_send_control(g_nodes[3], 5U, udn::FtKind::kPing, 0U, 1U, false), udn::FtError::kBadArgs);
    bsp::Work w{};
    ASSERT_EQ(udn::ft_set_fault_map(g_nodes[3], map, w), udn::FtError::kOk);
    EXPECT_TRUE(udn::ft_routes_ok(g_nodes[3]));
    send_run(0U, 0U);
    EXPECT_EQ(drain(5U, 1U).size(), 1U) << field;
  }
}

// An intermediate off the grid in a route is no route (not a hop to a tile that is not there).
TEST(FtLinkState, AnUpsetIntermediateIsNoRoute) {
  ft_test::boot(ft_test::grid_map());
  udn::Route& route = g_nodes[3].routes.to[5];
  route.via_count = 1U;
  route.via[0] = 0xC8U;
  bsp::TileId next = 0U;
  EXPECT_EQ(udn::route_next_hop(g_nodes[3].routes, 5U, next), udn::RouteError::kUnreachable);
  EXPECT_EQ(next, bsp::kNoTile);
  EXPECT_EQ(udn::ft_send(g_nodes[3], 5U, 1U, message(3U, 1U, 0U), ft_test::now_tick()), udn::FtError::kUnreachable);
}

// The epoch past its three bits, the queues-ready bits, a forward slot's length and a SYNC slot's
// stream: each reset and reported.
TEST(FtLinkState, TheOtherIndicesAreCheckedToo) {
  ft_test::boot(ft_test::grid_map());
  udn::FtNode& n = g_nodes[3];
  n.epoch = 0x0BU;
  n.rx_ready = 0x04U;
  n.fwd[2].used = true;
  n.fwd[2].dest = 5U;
  n.fwd[2].words = 0x10006U;
  n.fwd_hint = true;
  n.sync[1].used = true;
  n.sync[1].dest = 0xC5U;
  n.sync_hint = true;
  EXPECT_EQ(udn::ft_poll(n, ft_test::now_tick(), 8U), 0U);
  EXPECT_EQ(n.epoch, 3U);
  EXPECT_EQ(n.rx_ready, 0U);
  EXPECT_FALSE(n.fwd[2].used);
  EXPECT_FALSE(n.sync[1].used);
  EXPECT_EQ(repairs(3U), (std::vector{std::make_pair(udn::FtRepair::kEpoch, 0U),
                                      std::make_pair(udn::FtRepair::kRxReady, 0U),
                                      std::make_pair(udn::FtRepair::kFwdSlot, 2U),
                                      std::make_pair(udn::FtRepair::kSyncSlot, 1U)}));
  EXPECT_EQ(n.state_repairs, 4U);
  send_run(0U, 0U);
  EXPECT_EQ(drain(5U, 1U).size(), 1U);
}

// A node whose state is whole reports nothing however much traffic it carries.
TEST(FtLinkState, AWholeStateIsNeverRepaired) {
  ft_test::boot(ft_test::grid_map());
  for (std::uint32_t s = 0; s < 40U; ++s) {
    (void)udn::ft_send(g_nodes[3], 5U, 1U, message(3U, 1U, s), ft_test::now_tick());
    (void)udn::ft_send(g_nodes[60], 5U, 1U, message(60U, 1U, s), ft_test::now_tick());
    ft_test::step();
    (void)drain(5U, 1U);
  }
  settle();
  for (bsp::TileId t = 0; t < 64U; ++t) {
    EXPECT_EQ(g_nodes[t].state_repairs, 0U) << t;
  }
}

}  // namespace
