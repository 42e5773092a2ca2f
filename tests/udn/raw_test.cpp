/**
 * @file raw_test.cpp
 * @brief Raw UDN API on booted kernels: blocking send under back-pressure, ordered delivery,
 *        receive timeouts, tag binding and argument errors.
 */
#include "udn/raw.hpp"

#include "udn/ft_packet.hpp"

#include "bsp_tile64/emu/board.hpp"
#include "bsp_tile64/emu/udn_net.hpp"
#include "kernel/kernel.hpp"

#include <gtest/gtest.h>

#include <array>
#include <cstdint>
#include <vector>

namespace {

constexpr bsp::Cycles kTick = bsp::kTile64.cycles_per_ms();
constexpr bsp::Cycles kQuantum = kTick / 100U;  // 10 us: packets cross at most 10 us late
constexpr std::uint32_t kStack = 16U * 1024U;
constexpr bsp::TileId kSender = 0U;
constexpr bsp::TileId kReceiver = 27U;  // (3, 3)

/** Boots @p sender_table on kSender and @p receiver_table on kReceiver with the network up. */
void boot(k::TaskTable sender_table, k::TaskTable receiver_table) {
  bsp::BoardConfig cfg = bsp::default_config(bsp::kTile64);
  cfg.quantum_cycles = kQuantum;
  cfg.tick_cycles = kTick;
  cfg.powered_at_start = (1ULL << kSender) | (1ULL << kReceiver);
  cfg.monitor_tile = bsp::kNoTile;
  cfg.boot[kSender] = &k::boot_entry;
  cfg.boot[kReceiver] = &k::boot_entry;
  k::set_task_table(kSender, sender_table, kTick);
  k::set_task_table(kReceiver, receiver_table, kTick);
  ASSERT_EQ(bsp::board_init(cfg), bsp::BoardError::kOk);
  ASSERT_EQ(bsp::udn_net_init(bsp::NetConfig{}), bsp::NetError::kOk);
}

// ------------------------------------------------------------------ back-pressure

constexpr std::uint32_t kPackets = 300U;
constexpr std::uint32_t kWords = 20U;
constexpr std::uint32_t kReaderStartTick = 30U;

struct BackPressure {
  std::uint32_t sent = 0U;
  std::uint32_t sent_at_reader_start = 0U;
  std::vector<udn::RawError> send_errors;
  std::uint32_t received = 0U;
  std::uint32_t out_of_order = 0U;
  std::uint32_t bad_payload = 0U;
  udn::RawError last_rx = udn::RawError::kOk;
};
BackPressure g_bp;

void bp_sender(void*) {
  if (udn::activate() != udn::RawError::kOk) {
    return;
  }
  std::array<std::uint32_t, kWords> data{};
  for (std::uint32_t i = 0; i < kPackets; ++i) {
    for (std::uint32_t w = 0; w < kWords; ++w) {
      data[w] = i * 1000U + w;
    }
    const udn::RawError e = udn::send(kReceiver, 0x51U, data, k::kForever);
    if (e != udn::RawError::kOk) {
      g_bp.send_errors.push_back(e);
    }
    ++g_bp.sent;
  }
  for (;;) {
    k::sleep(1000);
  }
}

void bp_receiver(void*) {
  if (udn::activate() != udn::RawError::kOk || udn::bind(0x51U, 1U) != udn::RawError::kOk) {
    return;
  }
  k::sleep(kReaderStartTick);  // the reader is stopped: senders must block, nothing may be lost
  g_bp.sent_at_reader_start = g_bp.sent;
  std::array<std::uint32_t, kWords> data{};
  for (std::uint32_t i = 0; i < kPackets; ++i) {
    udn::RxInfo info{};
    g_bp.last_rx = udn::receive(1U, info, data, k::Timeout{50U});
    if (g_bp.last_rx != udn::RawError::kOk) {
      break;
    }
    g_bp.out_of_order += (data[0] != i * 1000U) ? 1U : 0U;
    g_bp.bad_payload += (info.data_words != kWords || info.source != kSender || data[kWords - 1U] != i * 1000U + kWords - 1U) ? 1U : 0U;
    ++g_bp.received;
  }
  for (;;) {
    k::sleep(1000);
  }
}

TEST(UdnRaw, SendersBlockWhileTheReceiverStopsAndEveryPacketArrivesOnceInOrder) {
  g_bp = BackPressure{};
  g_bp.send_errors.reserve(kPackets);  // tasks must not reallocate mid-run
  static constexpr k::TaskSpec kTx[] = {{"tx", &bp_sender, nullptr, 3, 0, 0, kStack, k::Policy::kPreemptive}};
  static constexpr k::TaskSpec kRx[] = {{"rx", &bp_receiver, nullptr, 3, 0, 0, kStack, k::Policy::kPreemptive}};
  boot(kTx, kRx);
  (void)bsp::run_for(kTick * 200U);
  // Queue 1 holds floor(256 / 21) = 12 packets and the sender has 8 in flight: 20 sends complete,
  // the 21st blocks until the reader starts.
  EXPECT_EQ(g_bp.sent_at_reader_start, 20U);
  EXPECT_EQ(g_bp.sent, kPackets);
  EXPECT_TRUE(g_bp.send_errors.empty());
  EXPECT_EQ(g_bp.received, kPackets) << "last receive status " << static_cast<int>(g_bp.last_rx);
  EXPECT_EQ(g_bp.out_of_order, 0U);
  EXPECT_EQ(g_bp.bad_payload, 0U);
  const bsp::NetStats s = bsp::udn_net_stats();
  EXPECT_EQ(s.sent, kPackets);
  EXPECT_EQ(s.delivered, kPackets);
  EXPECT_EQ(s.lost_total(), 0U);
  EXPECT_GT(s.refused_full, 0U);
  EXPECT_GT(s.queue_full_retries, 0U);
}

// ------------------------------------------------------------------ timeouts, binding, errors

struct Api {
  udn::RawError before_activate = udn::RawError::kOk;
  udn::RawError no_wait = udn::RawError::kOk;
  udn::RawError timed = udn::RawError::kOk;
  k::Ticks timed_elapsed = 0U;
  udn::RawError bad_bind = udn::RawError::kOk;
  udn::RawError bad_queue = udn::RawError::kOk;
  udn::RawError bad_tile = udn::RawError::kOk;
  udn::RawError empty_send = udn::RawError::kOk;
  udn::RawError bound_rx = udn::RawError::kOk;
  udn::RawError catch_rx = udn::RawError::kOk;
  std::uint32_t bound_tag = 0U;
  std::uint32_t catch_tag = 0U;
  std::uint32_t bound_word = 0U;
};
Api g_api;

void api_sender(void*) {
  std::array<std::uint32_t, 1> one{42U};
  g_api.before_activate = udn::send(kReceiver, 1U, one, k::kNoWait);
  if (udn::activate() != udn::RawError::kOk) {
    return;
  }
  g_api.bad_tile = udn::send(64U, 1U, one, k::kNoWait);
  g_api.empty_send = udn::send(kReceiver, 1U, std::span<const std::uint32_t>{}, k::kNoWait);
  k::sleep(20U);  // after the receiver's timeout tests
  one[0] = 7U;
  static_cast<void>(udn::send(kReceiver, 0x99U, one, k::kForever));
  one[0] = 8U;
  static_cast<void>(udn::send(kReceiver, 0x77U, one, k::kForever));
  for (;;) {
    k::sleep(1000);
  }
}

void api_receiver(void*) {
  if (udn::activate() != udn::RawError::kOk) {
    return;
  }
  std::array<std::uint32_t, 4> data{};
  udn::RxInfo info{};
  g_api.no_wait = udn::receive(udn::kCatchAll, info, data, k::kNoWait);
  const k::Ticks t0 = k::now_ticks();
  g_api.timed = udn::receive(udn::kCatchAll, info, data, k::Timeout{5U});
  g_api.timed_elapsed = k::now_ticks() - t0;
  g_api.bad_bind = udn::bind(0x99U, udn::kCatchAll);
  g_api.bad_queue = udn::receive(udn::kQueues, info, data, k::kNoWait);
  if (udn::bind(0x99U, 3U) != udn::RawError::kOk) {
    return;
  }
  g_api.bound_rx = udn::receive(3U, info, data, k::Timeout{100U});
  g_api.bound_tag = info.tag;
  g_api.bound_word = data[0];
  g_api.catch_rx = udn::receive(udn::kCatchAll, info, data, k::Timeout{100U});
  g_api.catch_tag = info.tag;
  for (;;) {
    k::sleep(1000);
  }
}

TEST(UdnRaw, TimeoutsBindingAndArgumentErrors) {
  g_api = Api{};
  static constexpr k::TaskSpec kTx[] = {{"tx", &api_sender, nullptr, 3, 0, 0, kStack, k::Policy::kPreemptive}};
  static constexpr k::TaskSpec kRx[] = {{"rx", &api_receiver, nullptr, 3, 0, 0, kStack, k::Policy::kPreemptive}};
  boot(kTx, kRx);
  (void)bsp::run_for(kTick * 60U);
  EXPECT_EQ(g_api.before_activate, udn::RawError::kNotActive);
  EXPECT_EQ(g_api.bad_tile, udn::RawError::kBadTile);
  EXPECT_EQ(g_api.empty_send, udn::RawError::kBadLength);
  EXPECT_EQ(g_api.no_wait, udn::RawError::kWouldBlock);
  EXPECT_EQ(g_api.timed, udn::RawError::kTimeout);
  EXPECT_EQ(g_api.timed_elapsed, 5U);
  EXPECT_EQ(g_api.bad_bind, udn::RawError::kBadQueue);
  EXPECT_EQ(g_api.bad_queue, udn::RawError::kBadQueue);
  EXPECT_EQ(g_api.bound_rx, udn::RawError::kOk);
  EXPECT_EQ(g_api.bound_tag, 0x99U);
  EXPECT_EQ(g_api.bound_word, 7U);
  EXPECT_EQ(g_api.catch_rx, udn::RawError::kOk);
  EXPECT_EQ(g_api.catch_tag, 0x77U);
}

TEST(UdnRaw, HeadersFromCoordinatesAndIndices) {
  bsp::BoardConfig cfg = bsp::default_config(bsp::kMaestro);
  cfg.powered_at_start = 0U;
  ASSERT_EQ(bsp::board_init(cfg), bsp::BoardError::kOk);
  ASSERT_EQ(bsp::udn_net_init(bsp::NetConfig{}), bsp::NetError::kOk);
  std::uint32_t h = 0U;
  ASSERT_EQ(udn::header_for(20U, 5U, h), udn::RawError::kOk);  // 7x7: (6, 2)
  EXPECT_EQ(h, udn::header_xy(6U, 2U, 5U));
  EXPECT_EQ(bsp::udn_header_length(h), 6U) << "length counts the tag";
  EXPECT_EQ(udn::header_for(49U, 5U, h), udn::RawError::kBadTile);
  EXPECT_EQ(udn::header_for(0U, 0U, h), udn::RawError::kBadLength);
  EXPECT_EQ(udn::header_for(0U, udn::kMaxDataWords + 1U, h), udn::RawError::kBadLength);
  EXPECT_EQ(udn::header_for(0U, udn::kMaxDataWords, h), udn::RawError::kOk);
}

TEST(UdnRaw, BoardHeaderLayoutIsTheFaultTolerantCodecsLayout) {
  for (std::uint32_t x = 0; x < 256U; x += 5U) {
    for (std::uint32_t y = 0; y < 256U; y += 3U) {
      for (std::uint32_t len = 0; len < 256U; len += 7U) {
        const std::uint32_t h = bsp::udn_make_header(x, y, len);
        ASSERT_EQ(h, udn::make_hw_header(static_cast<std::uint8_t>(x), static_cast<std::uint8_t>(y),
                                         static_cast<std::uint8_t>(len)))
            << x << "," << y << " len " << len;
        ASSERT_EQ(bsp::udn_header_x(h), x);
        ASSERT_EQ(bsp::udn_header_y(h), y);
        ASSERT_EQ(bsp::udn_header_length(h), len);
      }
    }
  }
  EXPECT_LE(udn::kFtMaxPacketWords - 1U, bsp::kUdnMaxLength) << "a fault-tolerant packet fits one send";
}

}  // namespace
