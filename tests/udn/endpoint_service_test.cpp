/**
 * @file endpoint_service_test.cpp
 * @brief The endpoint's service task is event-driven: it sleeps while nothing is in flight and
 *        nothing arrives, a packet's arrival wakes it, and a task waiting in endpoint_wait()
 *        wakes when its message is delivered, not at its timeout.
 */
#include "bsp_tile64/emu/board.hpp"
#include "bsp_tile64/emu/udn_net.hpp"
#include "kernel/kernel.hpp"
#include "udn/endpoint.hpp"

#include <gtest/gtest.h>

#include <array>
#include <cstdint>

namespace {

constexpr bsp::Cycles kTick = bsp::kTile64.cycles_per_ms();
constexpr bsp::TileId kSender = 9U;
constexpr bsp::TileId kReceiver = 12U;  // three hops east of the sender
constexpr std::uint32_t kChannel = 3U;
constexpr k::Ticks kSendAt = 40U;     // the sender's tick: long after both endpoints are open
constexpr std::uint32_t kWaitTicks = 200U;

udn::EndpointConfig g_cfg{};  // no health tile: no probes, so only the message moves

k::Ticks g_sent_tick = 0;
bsp::Cycles g_sent_cycle = 0;
bsp::Cycles g_received_cycle = 0;
std::uint32_t g_words = 0;
std::uint32_t g_waits = 0;
std::uint32_t g_first_word = 0;

void sender_main(void*) {
  if (!udn::endpoint_wait_ready(20U)) {
    return;
  }
  k::sleep_until(kSendAt);
  const std::array<std::uint32_t, 3> words{0xC0FFEEU, 2U, 3U};
  g_sent_tick = k::now_ticks();
  g_sent_cycle = bsp::now();
  EXPECT_EQ(udn::endpoint_send(kReceiver, kChannel, words, 10U), udn::FtError::kOk);
}

void receiver_main(void*) {
  if (!udn::endpoint_wait_ready(20U)) {
    return;
  }
  udn::FtMessage m{};
  for (std::uint32_t i = 0; i < 8U; ++i) {
    if (udn::endpoint_receive(kChannel, m) == udn::FtError::kOk) {
      g_received_cycle = bsp::now();
      g_words = m.data_words;
      g_first_word = m.data[0];
      return;
    }
    ++g_waits;
    EXPECT_TRUE(udn::endpoint_wait(kChannel, kWaitTicks));
  }
}

constexpr k::TaskSpec kSenderTable[] = {
    udn::endpoint_task_spec(&g_cfg),
    {"sender", &sender_main, nullptr, 2, 0, 0, 16U * 1024U, k::Policy::kPreemptive},
};
constexpr k::TaskSpec kReceiverTable[] = {
    udn::endpoint_task_spec(&g_cfg),
    {"receiver", &receiver_main, nullptr, 2, 0, 0, 16U * 1024U, k::Policy::kPreemptive},
};

class EndpointService : public ::testing::Test {
 protected:
  void SetUp() override {
    g_cfg = udn::EndpointConfig{};
    g_sent_tick = 0;
    g_sent_cycle = 0;
    g_received_cycle = 0;
    g_words = 0;
    g_waits = 0;
    g_first_word = 0;
    bsp::BoardConfig cfg = bsp::default_config(bsp::kTile64);
    cfg.powered_at_start = (1ULL << kSender) | (1ULL << kReceiver);
    cfg.monitor_tile = bsp::kNoTile;
    cfg.boot[kSender] = &k::boot_entry;
    cfg.boot[kReceiver] = &k::boot_entry;
    k::set_task_table(kSender, kSenderTable, kTick);
    k::set_task_table(kReceiver, kReceiverTable, kTick);
    ASSERT_EQ(bsp::board_init(cfg), bsp::BoardError::kOk);
    ASSERT_EQ(bsp::udn_net_init(bsp::NetConfig{}), bsp::NetError::kOk);
  }
};

// The message is in the receiver's hands within the tick after it was sent (woken by its
// delivery, not by its 200-tick timeout), and while nothing moved, both service tasks slept
// (at most kCommMaxSleepTicks at a time) instead of running every tick.
TEST_F(EndpointService, AnArrivalWakesTheServiceAndTheWaitingTask) {
  (void)bsp::run_for((kSendAt + 30U) * kTick);
  ASSERT_EQ(g_words, 3U);
  EXPECT_EQ(g_first_word, 0xC0FFEEU);
  EXPECT_EQ(g_sent_tick, kSendAt);
  EXPECT_GT(g_received_cycle, g_sent_cycle);
  EXPECT_LE(g_received_cycle - g_sent_cycle, 2U * kTick) << "delivered at the next barrier, not at the timeout";
  EXPECT_GE(g_waits, 1U);
  for (const bsp::TileId t : {kSender, kReceiver}) {
    k::TaskStats s{};
    ASSERT_EQ(k::task_stats(t, k::find_task(t, "comm"), &s), k::Status::kOk);
    // Idle for about 40 ticks: a pass every kCommMaxSleepTicks, plus the message's few (send, ACK).
    EXPECT_LE(s.activations, 70U / udn::kCommMaxSleepTicks + 8U) << "tile " << t;
    EXPECT_GE(s.activations, 3U) << "tile " << t;
    EXPECT_LE(s.max_checkin_gap, udn::kCommMaxSleepTicks) << "within its check-in budget";
  }
}

}  // namespace
