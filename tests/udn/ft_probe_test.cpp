/**
 * @file ft_probe_test.cpp
 * @brief The neighbour probe reports a failed switch after exactly N missed rounds, never a healthy one,
 *        and its hook can update the fault map.
 */
#include "udn/ft_probe.hpp"

#include "tests/udn/ft_link_fixture.hpp"

#include <gtest/gtest.h>

#include <array>
#include <cstdint>
#include <utility>
#include <vector>

namespace {

using ft_test::g_nodes;

struct Suspects {
  std::vector<std::pair<bsp::TileId, bsp::TileId>> seen;
  udn::FaultMap* map = nullptr;
};

void on_suspect(void* ctx, bsp::TileId reporter, bsp::TileId suspect) {
  auto* s = static_cast<Suspects*>(ctx);
  s->seen.emplace_back(reporter, suspect);
  if (s->map != nullptr) (void)udn::fault_map_fail_tile(*s->map, suspect);
}

std::array<udn::FtProbe, 64> g_probes{};

/** The tile whose switch fails: its own software is not run (it would suspect all its neighbours). */
constexpr bsp::TileId kDead = 27U;

/** One probe round on every other tile, then two ticks of polling (a ping and its pong take about 2 quanta each). */
void round_and_tick() {
  for (bsp::TileId t = 0; t < 64U; ++t) {
    if (t != kDead) (void)udn::ft_probe_round(g_probes[t], g_nodes[t], ft_test::now_tick());
  }
  for (bsp::Cycles c = 0; c < 2U * ft_test::kTick; c += ft_test::kQuantum) ft_test::step();
}

void check_threshold(std::uint32_t n) {
  SCOPED_TRACE(testing::Message() << "threshold " << n);
  udn::FaultMap map = ft_test::grid_map();
  ft_test::boot(map);
  Suspects suspects{{}, &map};
  for (bsp::TileId t = 0; t < 64U; ++t) {
    ASSERT_EQ(udn::ft_probe_init(g_probes[t], g_nodes[t], udn::ProbeConfig{n}, &on_suspect, &suspects),
              udn::ProbeError::kOk);
  }
  ASSERT_EQ(bsp::udn_net_fail_switch(kDead), bsp::NetError::kOk);
  round_and_tick();  // round 1 sends the first pings; nothing to score yet
  for (std::uint32_t r = 1; r < n; ++r) {
    round_and_tick();
    EXPECT_TRUE(suspects.seen.empty()) << "reported after " << r << " misses";
  }
  round_and_tick();  // the n-th miss
  std::vector<bsp::TileId> reporters;
  for (const auto& [reporter, suspect] : suspects.seen) {
    EXPECT_EQ(suspect, 27U);
    reporters.push_back(reporter);
  }
  std::sort(reporters.begin(), reporters.end());
  EXPECT_EQ(reporters, (std::vector<bsp::TileId>{19U, 26U, 28U, 35U}));
  EXPECT_EQ(map.failed_tiles, std::uint64_t{1} << 27U);
  const std::vector<udn::FtEvent> log = ft_test::events_of(19U, udn::FtCause::kSuspectNeighbour);
  ASSERT_EQ(log.size(), 1U);
  EXPECT_EQ(log[0].peer, 27U);
  for (int r = 0; r < 5; ++r) round_and_tick();
  EXPECT_EQ(suspects.seen.size(), 4U) << "reported once, and no healthy neighbour ever";
}

TEST(FtProbe, ReportsAFailedNeighbourSwitchAfterNMissesAndNotBefore) {
  for (std::uint32_t n : {1U, 3U, 5U}) check_threshold(n);
}

TEST(FtProbe, RejectsAZeroThreshold) {
  const udn::FaultMap map = ft_test::grid_map();
  ft_test::boot(map);
  EXPECT_EQ(udn::ft_probe_init(g_probes[0], g_nodes[0], udn::ProbeConfig{0U}, nullptr, nullptr),
            udn::ProbeError::kBadArgs);
}

}  // namespace
