/**
 * @file ft_soak_test.cpp
 * @brief Soak of the fault-tolerant layer: random all-to-all traffic at bit error rates 1e-5..1e-3 per
 *        word with failed switches (one failing mid-run): no message lost, duplicated, misordered or
 *        corrupted while a route exists. The 10^6-packet soak is `make soak` (mk/soak.mk).
 */
#include "tests/udn/ft_link_fixture.hpp"

#include "bsp_tile64/emu/rng.hpp"

#include <gtest/gtest.h>

#include <array>
#include <cstdint>
#include <cstdio>
#include <vector>

namespace {

using ft_test::g_nodes;

struct SoakResult {
  std::uint64_t sent = 0;
  std::uint64_t delivered = 0;
  std::uint64_t bad = 0;  ///< duplicated, misordered or corrupted deliveries
  std::uint64_t corrected = 0;
  std::uint64_t retransmitted = 0;
  std::uint64_t uncorrectable = 0;
  std::uint64_t forwarded = 0;
  std::uint64_t gave_up = 0;
  std::uint64_t unreachable = 0;
  std::uint64_t bit_flips = 0;  ///< words the network corrupted in transit (its own count)
};

constexpr std::uint32_t kChannels = udn::kFtChannels;
/** Messages handed to ft_send and received, per (source, destination, channel). */
std::array<std::array<std::array<std::uint32_t, kChannels>, 64>, 64> g_sent{};
std::array<std::array<std::array<std::uint32_t, kChannels>, 64>, 64> g_got{};

std::uint64_t receive_all(std::uint64_t& bad) {
  std::uint64_t n = 0;
  for (bsp::TileId d = 0; d < 64U; ++d) {
    for (std::uint32_t ch = 0; ch < kChannels; ++ch) {
      udn::FtMessage m{};
      while (udn::ft_receive(g_nodes[d], ch, m) == udn::FtError::kOk) {
        std::uint32_t& k = g_got[m.source][d][ch];
        bool ok = (m.seq == (k & 0xFFU)) && k < g_sent[m.source][d][ch];
        for (std::uint32_t i = 0; i < m.data_words; ++i) ok = ok && m.data[i] == ft_test::pattern(m.source, ch, m.seq, i);
        bad += ok ? 0U : 1U;
        ++k;
        ++n;
      }
    }
  }
  return n;
}

/** The health layer's part, done by hand: the map learns the failure and every node rebuilds. */
void publish_failure(udn::FaultMap& map, bsp::TileId t) {
  EXPECT_EQ(udn::fault_map_fail_tile(map, t), udn::RouteError::kOk);
  for (bsp::TileId n = 0; n < 64U; ++n) {
    bsp::Work w{};
    EXPECT_EQ(udn::ft_set_fault_map(g_nodes[n], map, w), udn::FtError::kOk);
  }
}

/** A quarter of the live tiles send one message of 1..12 words to a random live tile. */
void offer_traffic(const std::vector<bsp::TileId>& live, bsp::Rng& rng, SoakResult& r) {
  std::array<std::uint32_t, 12> data{};
  for (bsp::TileId s : live) {
    if (rng.below(4U) != 0U) continue;
    const bsp::TileId d = live[rng.below(live.size())];
    const auto ch = static_cast<std::uint32_t>(rng.below(kChannels));
    const auto words = 1U + static_cast<std::uint32_t>(rng.below(data.size()));
    const auto seq = static_cast<std::uint8_t>(g_nodes[s].tx_stream[d][ch].next_seq);
    for (std::uint32_t i = 0; i < words; ++i) data[i] = ft_test::pattern(s, ch, seq, i);
    const udn::FtError e = udn::ft_send(g_nodes[s], d, ch, std::span(data.data(), words), ft_test::now_tick());
    if (e == udn::FtError::kOk) {
      ++g_sent[s][d][ch];
      ++r.sent;
    }
    r.unreachable += (e == udn::FtError::kUnreachable) ? 1U : 0U;
  }
}

void report(double ber, const SoakResult& r) {
  const auto sum = [](auto f) { return static_cast<unsigned long long>(ft_test::total(f)); };
  std::printf("ber %.0e: sent %llu delivered %llu corrected %llu uncorrectable %llu retransmitted %llu "
              "forwarded %llu gave_up %llu bad %llu bit_flips %llu\n",
              ber, static_cast<unsigned long long>(r.sent), static_cast<unsigned long long>(r.delivered),
              static_cast<unsigned long long>(r.corrected), static_cast<unsigned long long>(r.uncorrectable),
              static_cast<unsigned long long>(r.retransmitted), static_cast<unsigned long long>(r.forwarded),
              static_cast<unsigned long long>(r.gave_up), static_cast<unsigned long long>(r.bad),
              static_cast<unsigned long long>(r.bit_flips));
  std::printf("  duplicates dropped %llu out of order %llu acks %llu nacks %llu net lost %llu\n",
              sum([](const udn::FtStats& s) { return s.duplicates_dropped; }),
              sum([](const udn::FtStats& s) { return s.out_of_order_dropped; }),
              sum([](const udn::FtStats& s) { return s.acks_sent; }),
              sum([](const udn::FtStats& s) { return s.nacks_sent; }),
              static_cast<unsigned long long>(bsp::udn_net_stats().lost_total()));
}

/**
 * Every working tile sends a message in a quarter of the quanta to a random working tile. Tile
 * @p late_fail's switch fails at a third of the run; the map learns it two ticks later.
 */
SoakResult soak(double ber, std::uint64_t seed, std::uint64_t packets, const std::vector<bsp::TileId>& failed,
                bsp::TileId late_fail) {
  g_sent = {};
  g_got = {};
  udn::FaultMap map = ft_test::grid_map();
  for (bsp::TileId t : failed) EXPECT_EQ(udn::fault_map_fail_tile(map, t), udn::RouteError::kOk);
  ft_test::boot(map, seed, udn::FtConfig{3U, 12U});
  for (bsp::TileId t : failed) EXPECT_EQ(bsp::udn_net_fail_switch(t), bsp::NetError::kOk);
  bsp::udn_net_set_ber(ber);
  std::vector<bsp::TileId> live;
  for (bsp::TileId t = 0; t < 64U; ++t) {
    if (((map.failed_tiles >> t) & 1U) == 0U && t != late_fail) live.push_back(t);
  }
  bsp::Rng rng(seed, bsp::StreamId::kTraffic);
  SoakResult r{};
  std::uint32_t fail_tick = 0;
  while (r.sent < packets) {
    if (late_fail != bsp::kNoTile && fail_tick == 0U && r.sent >= packets / 3U) {
      EXPECT_EQ(bsp::udn_net_fail_switch(late_fail), bsp::NetError::kOk);
      fail_tick = ft_test::now_tick() + 2U;
    }
    if (fail_tick != 0U && ft_test::now_tick() == fail_tick) {
      publish_failure(map, late_fail);
    }
    offer_traffic(live, rng, r);
    ft_test::step();
    r.delivered += receive_all(r.bad);
  }
  for (int i = 0; i < 2000 && ft_test::outstanding() > 0U; ++i) {
    ft_test::step();
    r.delivered += receive_all(r.bad);
  }
  for (int i = 0; i < 20; ++i) {
    ft_test::step();
    r.delivered += receive_all(r.bad);
  }
  r.corrected = ft_test::total([](const udn::FtStats& s) { return s.corrected; });
  r.retransmitted = ft_test::total([](const udn::FtStats& s) { return s.retransmitted; });
  r.uncorrectable = ft_test::total([](const udn::FtStats& s) { return s.uncorrectable_detected; });
  r.forwarded = ft_test::total([](const udn::FtStats& s) { return s.forwarded; });
  r.gave_up = ft_test::total([](const udn::FtStats& s) { return s.gave_up; });
  r.bit_flips = bsp::udn_net_stats().bit_flips;
  report(ber, r);
  return r;
}

void expect_perfect(const SoakResult& r, std::uint64_t seed) {
  SCOPED_TRACE(testing::Message() << "seed " << seed);
  EXPECT_EQ(r.bad, 0U);
  EXPECT_EQ(r.gave_up, 0U);
  EXPECT_EQ(r.delivered, r.sent) << "lost messages";
  EXPECT_EQ(ft_test::outstanding(), 0U);
  for (bsp::TileId s = 0; s < 64U; ++s) {
    for (bsp::TileId d = 0; d < 64U; ++d) {
      for (std::uint32_t ch = 0; ch < kChannels; ++ch) ASSERT_EQ(g_got[s][d][ch], g_sent[s][d][ch]);
    }
  }
}

TEST(FtSoak, BitErrorRate1e5WithFailedSwitchesLosesNothing) {
  const auto r = soak(1e-5, 11U, 100000U, {8U, 9U, 45U}, bsp::kNoTile);
  expect_perfect(r, 11U);
  EXPECT_GT(r.bit_flips, 0U) << "the soak must flip bits to test their correction";
  EXPECT_GT(r.corrected, 0U);
  EXPECT_GT(r.forwarded, 0U);
}

TEST(FtSoak, BitErrorRate1e4WithASwitchFailingMidRunLosesNothing) {
  const auto r = soak(1e-4, 12U, 100000U, {20U}, 36U);
  expect_perfect(r, 12U);
  EXPECT_GT(r.bit_flips, 0U);
  EXPECT_GT(r.corrected, 0U);
}

TEST(FtSoak, BitErrorRate1e3WithFailedSwitchesLosesNothing) {
  const auto r = soak(1e-3, 13U, 100000U, {8U, 9U, 27U}, bsp::kNoTile);
  expect_perfect(r, 13U);
  EXPECT_GT(r.bit_flips, 100U);
  EXPECT_GT(r.corrected, 100U);
  EXPECT_GT(r.retransmitted, 0U);
}

}  // namespace
