/**
 * @file udn_bench.cpp
 * @brief Host cost of the UDN: packets per host second for uniform random traffic on 64 tiles,
 *        for the network model alone and for the whole stack (kernels, raw API, udn_stress run).
 */
#include "bsp_tile64/emu/board.hpp"
#include "bsp_tile64/emu/rng.hpp"
#include "bsp_tile64/emu/udn_net.hpp"
#include "tools/common/udn_stress/udn_stress.hpp"

#include <benchmark/benchmark.h>

#include <array>
#include <cstdint>
#include <cstdlib>

namespace {

/**
 * The model alone: no tile runs code; the host sends one packet per tile per
 * quantum (1 us) to a uniform random other tile and drains every queue.
 */
void BM_NetModelUniform64(benchmark::State& state) {
  const auto words = static_cast<std::uint32_t>(state.range(0));
  bsp::BoardConfig cfg = bsp::default_config(bsp::kTile64);
  cfg.quantum_cycles = bsp::kTile64.clock_hz / 1'000'000U;
  cfg.powered_at_start = 0U;
  cfg.monitor_tile = bsp::kNoTile;
  if (bsp::board_init(cfg) != bsp::BoardError::kOk || bsp::udn_net_init(bsp::NetConfig{}) != bsp::NetError::kOk) {
    std::abort();
  }
  bsp::Rng rng(1U, bsp::StreamId::kTest);
  std::array<std::uint32_t, bsp::kUdnMaxPacketWords> pkt{};
  std::array<std::uint32_t, bsp::kUdnMaxLength> sink{};
  std::uint64_t sent = 0U;
  for (auto _ : state) {
    for (bsp::TileId s = 0; s < 64U; ++s) {
      auto d = static_cast<bsp::TileId>(rng.below(63U));
      d = d >= s ? d + 1U : d;
      pkt[0] = bsp::udn_make_header(d % 8U, d / 8U, words + 1U);
      pkt[1] = 1U;
      sent += bsp::udn_net_send_from(s, bsp::board_time(), std::span(pkt.data(), words + 2U)) == bsp::NetError::kOk;
    }
    (void)bsp::run_for(cfg.quantum_cycles);
    for (bsp::TileId d = 0; d < 64U; ++d) {
      bsp::RxPacket rx{};
      while (bsp::udn_net_receive_on(d, bsp::kUdnCatchAll, rx, sink) == bsp::NetError::kOk) {
      }
    }
  }
  state.counters["packets_per_s"] = benchmark::Counter(static_cast<double>(sent), benchmark::Counter::kIsRate);
}
BENCHMARK(BM_NetModelUniform64)->Arg(8)->Arg(64)->Unit(benchmark::kMicrosecond);

/** The whole stack: a kernel with a sender and a receiver task on each of 64 tiles (udn_stress). */
void BM_StressUniform64(benchmark::State& state) {
  tools::StressOptions o;
  o.packets = 20'000U;
  o.rate_per_us = static_cast<double>(state.range(0)) / 100.0;
  o.words = 8U;
  std::uint64_t delivered = 0U;
  double emulated_s = 0.0;
  for (auto _ : state) {
    const tools::StressResult r = tools::run_stress(o, bsp::heap::SealMode::kCount);
    if (!r.completed()) {
      state.SkipWithError("run did not complete");
      return;
    }
    delivered += r.net.delivered;
    emulated_s += r.emulated_s;
  }
  state.counters["packets_per_s"] = benchmark::Counter(static_cast<double>(delivered), benchmark::Counter::kIsRate);
  state.counters["emulated_s_per_run"] =
      benchmark::Counter(emulated_s / static_cast<double>(state.iterations()));
}
BENCHMARK(BM_StressUniform64)->Arg(1)->Arg(50)->Unit(benchmark::kMillisecond);  // rate 0.01 and 0.5 per tile per us

}  // namespace

BENCHMARK_MAIN();
