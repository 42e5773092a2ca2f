/**
 * @file udn_ft_bench.cpp
 * @brief Host cost of a fault-tolerant send/receive (udn/ft_link.hpp) against a raw one, end to end on
 *        the emulated network, and of the codec alone.
 *
 * Both end-to-end cases move batches of 8 messages of 8 words from tile 0 to
 * tile 27 (6 hops) on an idle board, host-driven (no tile runs code), until the
 * receiver holds them all; the fault-tolerant case also waits for the ACKs, as
 * a sender must before its window frees. items_per_second = messages.
 */
#include "bsp_tile64/emu/board.hpp"
#include "bsp_tile64/emu/udn_net.hpp"
#include "udn/ft_link.hpp"
#include "udn/ft_packet.hpp"

#include <benchmark/benchmark.h>

#include <array>
#include <cstdint>
#include <cstdlib>
#include <span>

namespace {

constexpr bsp::Cycles kQuantum = 1000U;
constexpr std::uint32_t kBatch = 8U;
constexpr std::uint32_t kWords = 8U;
constexpr bsp::TileId kSrc = 0U;
constexpr bsp::TileId kDst = 27U;

void boot() {
  bsp::BoardConfig cfg = bsp::default_config(bsp::kTile64);
  cfg.quantum_cycles = kQuantum;
  cfg.tick_cycles = 4U * kQuantum;
  cfg.powered_at_start = 0U;
  cfg.monitor_tile = bsp::kNoTile;
  bsp::NetConfig net{};
  net.max_in_flight_per_tile = 16U;
  if (bsp::board_init(cfg) != bsp::BoardError::kOk || bsp::udn_net_init(net) != bsp::NetError::kOk) {
    std::abort();
  }
}

void BM_RawSendReceive(benchmark::State& state) {
  boot();
  std::array<std::uint32_t, kWords + 2U> pkt{};
  std::array<std::uint32_t, bsp::kUdnMaxLength> sink{};
  pkt[0] = bsp::udn_make_header(kDst % 8U, kDst / 8U, kWords + 1U);
  pkt[1] = 1U;
  for (auto _ : state) {
    for (std::uint32_t i = 0; i < kBatch; ++i) {
      pkt[2] = i;
      if (bsp::udn_net_send_from(kSrc, bsp::board_time(), pkt) != bsp::NetError::kOk) std::abort();
    }
    std::uint32_t got = 0;
    while (got < kBatch) {
      (void)bsp::run_for(kQuantum);
      bsp::RxPacket rx{};
      while (bsp::udn_net_receive_on(kDst, bsp::kUdnCatchAll, rx, sink) == bsp::NetError::kOk) ++got;
    }
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations()) * kBatch);
}
BENCHMARK(BM_RawSendReceive)->Unit(benchmark::kMicrosecond);

bsp::NetError host_send(void* /*ctx*/, bsp::TileId self, std::span<const std::uint32_t> words) {
  return bsp::udn_net_send_from(self, bsp::board_time(), words);
}
bsp::NetError host_receive(void* /*ctx*/, bsp::TileId self, std::uint32_t queue, bsp::RxPacket& rx,
                           std::span<std::uint32_t> payload) {
  return bsp::udn_net_receive_on(self, queue, rx, payload);
}

udn::FtNode g_src;
udn::FtNode g_dst;

void BM_FtSendReceive(benchmark::State& state) {
  boot();
  udn::FaultMap map{};
  if (udn::fault_map_init(map, 8U, 8U) != udn::RouteError::kOk) std::abort();
  const udn::FtPort port{&host_send, &host_receive, nullptr};
  if (udn::ft_init(g_src, kSrc, map, port, udn::FtConfig{}) != udn::FtError::kOk ||
      udn::ft_init(g_dst, kDst, map, port, udn::FtConfig{}) != udn::FtError::kOk) {
    std::abort();
  }
  std::array<std::uint32_t, kWords> data{};
  udn::FtMessage m{};
  for (auto _ : state) {
    const auto tick = static_cast<std::uint32_t>(bsp::board_time() / (4U * kQuantum));
    for (std::uint32_t i = 0; i < kBatch; ++i) {
      data[0] = i;
      if (udn::ft_send(g_src, kDst, 0U, data, tick) != udn::FtError::kOk) std::abort();
    }
    std::uint32_t got = 0;
    while (got < kBatch || udn::ft_outstanding(g_src) > 0U) {
      (void)bsp::run_for(kQuantum);
      const auto now = static_cast<std::uint32_t>(bsp::board_time() / (4U * kQuantum));
      (void)udn::ft_poll(g_dst, now, 64U);
      (void)udn::ft_poll(g_src, now, 64U);
      while (udn::ft_receive(g_dst, 0U, m) == udn::FtError::kOk) ++got;
    }
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations()) * kBatch);
  state.counters["retransmitted"] = static_cast<double>(g_src.stats.retransmitted);
}
BENCHMARK(BM_FtSendReceive)->Unit(benchmark::kMicrosecond);

/** The codec alone: encode with CRC and decode (kRequired) one 8-word packet. */
void BM_FtCodecRoundTrip(benchmark::State& state) {
  std::array<std::uint32_t, kWords> data{};
  std::array<std::uint32_t, udn::kFtMaxPacketWords> image{};
  const udn::FtFields f{3U, 3U, static_cast<std::uint16_t>(kDst), udn::kFtHwTag, 0x1234U, true};
  for (auto _ : state) {
    std::size_t written = 0;
    data[0] += 1U;
    if (udn::encode_packet(f, data, image, written) != udn::EncodeStatus::kOk) std::abort();
    const udn::Decoded d =
        udn::decode_packet(std::span(image.data(), written), static_cast<std::uint16_t>(kDst), udn::CrcPolicy::kRequired);
    benchmark::DoNotOptimize(d);
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations()));
}
BENCHMARK(BM_FtCodecRoundTrip);

}  // namespace

BENCHMARK_MAIN();
