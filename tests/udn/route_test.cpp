/**
 * @file route_test.cpp
 * @brief Virtual routing: the paper's Figure 6, random fault maps against a brute-force reference
 *        and a BFS lower bound, unreachable pairs reported, legs avoid every failed element.
 */
#include "udn/route.hpp"

#include "bsp_tile64/emu/rng.hpp"

#include <gtest/gtest.h>

#include <cstdint>
#include <deque>
#include <vector>

namespace {

/** Tiles of the X-then-Y path s..d (reference walk). */
std::vector<std::uint32_t> walk(std::uint32_t cols, std::uint32_t s, std::uint32_t d) {
  std::uint32_t x = s % cols;
  std::uint32_t y = s / cols;
  std::vector<std::uint32_t> p{s};
  while (x != d % cols) {
    x = (d % cols > x) ? x + 1U : x - 1U;
    p.push_back(y * cols + x);
  }
  while (y != d / cols) {
    y = (d / cols > y) ? y + 1U : y - 1U;
    p.push_back(y * cols + x);
  }
  return p;
}

bsp::UdnDir dir_of(std::uint32_t cols, std::uint32_t a, std::uint32_t b) {
  if (b == a + 1U) return bsp::UdnDir::kEast;
  if (b + 1U == a) return bsp::UdnDir::kWest;
  return (b == a + cols) ? bsp::UdnDir::kSouth : bsp::UdnDir::kNorth;
}

bool ref_clear(const udn::FaultMap& m, std::uint32_t s, std::uint32_t d) {
  const auto p = walk(m.cols, s, d);
  for (std::size_t i = 0; i < p.size(); ++i) {
    if ((m.failed_tiles >> p[i]) & 1U) return false;
    if (i + 1 < p.size() && ((static_cast<unsigned>(m.failed_links[p[i]]) >> static_cast<unsigned>(dir_of(m.cols, p[i], p[i + 1]))) & 1U)) {
      return false;
    }
  }
  return true;
}

/** Shortest path length over working tiles and links (any path), -1 if none. */
int bfs(const udn::FaultMap& m, std::uint32_t s, std::uint32_t d) {
  const std::uint32_t n = m.cols * m.rows;
  if (((m.failed_tiles >> s) & 1U) || ((m.failed_tiles >> d) & 1U)) return -1;
  std::vector<int> dist(n, -1);
  std::deque<std::uint32_t> q{s};
  dist[s] = 0;
  while (!q.empty()) {
    const std::uint32_t a = q.front();
    q.pop_front();
    const std::uint32_t x = a % m.cols;
    const std::uint32_t y = a / m.cols;
    std::vector<std::uint32_t> nb;
    if (x + 1 < m.cols) nb.push_back(a + 1);
    if (x > 0) nb.push_back(a - 1);
    if (y > 0) nb.push_back(a - m.cols);
    if (y + 1 < m.rows) nb.push_back(a + m.cols);
    for (std::uint32_t b : nb) {
      if (dist[b] >= 0 || ((m.failed_tiles >> b) & 1U) ||
          ((static_cast<unsigned>(m.failed_links[a]) >> static_cast<unsigned>(dir_of(m.cols, a, b))) & 1U)) {
        continue;
      }
      dist[b] = dist[a] + 1;
      q.push_back(b);
    }
  }
  return dist[d];
}

/** Every route of every table: legs clear, hops add up, at least the BFS length, brute-force optimal. */
void check_all(const udn::FaultMap& m, std::uint64_t seed) {
  const std::uint32_t n = m.cols * m.rows;
  udn::RouteTable t{};
  for (std::uint32_t s = 0; s < n; ++s) {
    bsp::Work w{};
    ASSERT_EQ(udn::route_table_build(m, s, t, w), udn::RouteError::kOk);
    for (std::uint32_t d = 0; d < n; ++d) {
      SCOPED_TRACE(testing::Message() << "seed " << seed << " s " << s << " d " << d);
      // Reference: brute force over 0, 1, 2 intermediates with the documented tie-break.
      std::uint32_t best = ~0U;
      std::vector<std::uint32_t> best_via;
      auto consider = [&](const std::vector<std::uint32_t>& chain, const std::vector<std::uint32_t>& via) {
        std::uint32_t h = 0;
        for (std::size_t i = 0; i + 1 < chain.size(); ++i) {
          if (!ref_clear(m, chain[i], chain[i + 1])) return;
          h += udn::path_hops(m.cols, chain[i], chain[i + 1]);
        }
        if (h < best) {
          best = h;
          best_via = via;
        }
      };
      consider({s, d}, {});
      for (std::uint32_t a = 0; a < n; ++a) {
        if (a != s && a != d) consider({s, a, d}, {a});
      }
      for (std::uint32_t a = 0; a < n; ++a) {
        for (std::uint32_t b = 0; b < n; ++b) {
          if (a != s && a != d && b != s && b != d && a != b) consider({s, a, b, d}, {a, b});
        }
      }
      const udn::Route& r = t.to[d];
      const int lower = bfs(m, s, d);
      if (best == ~0U) {
        EXPECT_EQ(r.status, udn::RouteError::kUnreachable);
        bsp::TileId next = 0;
        EXPECT_EQ(udn::route_next_hop(t, d, next), udn::RouteError::kUnreachable);
        EXPECT_EQ(next, bsp::kNoTile);
        continue;
      }
      ASSERT_EQ(r.status, udn::RouteError::kOk);
      ASSERT_GE(lower, 0);
      EXPECT_EQ(r.hops, best);
      EXPECT_GE(static_cast<int>(r.hops), lower);
      ASSERT_EQ(r.via_count, best_via.size());
      for (std::size_t i = 0; i < best_via.size(); ++i) EXPECT_EQ(r.via[i], best_via[i]);
      std::vector<std::uint32_t> chain{s};
      for (std::size_t i = 0; i < r.via_count; ++i) chain.push_back(r.via[i]);
      chain.push_back(d);
      for (std::size_t i = 0; i + 1 < chain.size(); ++i) EXPECT_TRUE(ref_clear(m, chain[i], chain[i + 1]));
    }
  }
}

TEST(Route, Figure6OnThePapersFourColumnGridGoesVia10) {
  // The paper numbers tiles row-major on a 4-wide grid: only then does X-then-Y
  // from 0 to 9 pass through 5 (0 -> 1 -> 5 -> 9), as its text says.
  udn::FaultMap m{};
  ASSERT_EQ(udn::fault_map_init(m, 4U, 4U), udn::RouteError::kOk);
  ASSERT_EQ(udn::fault_map_fail_tile(m, 4U), udn::RouteError::kOk);
  ASSERT_EQ(udn::fault_map_fail_tile(m, 5U), udn::RouteError::kOk);
  EXPECT_FALSE(udn::path_clear(m, 0U, 9U));
  udn::RouteTable t{};
  bsp::Work w{};
  ASSERT_EQ(udn::route_table_build(m, 0U, t, w), udn::RouteError::kOk);
  EXPECT_EQ(t.to[9].status, udn::RouteError::kOk);
  EXPECT_EQ(t.to[9].via_count, 1U);
  EXPECT_EQ(t.to[9].via[0], 10U);
  EXPECT_EQ(t.to[9].hops, 5U);
  bsp::TileId next = 0;
  ASSERT_EQ(udn::route_next_hop(t, 9U, next), udn::RouteError::kOk);
  EXPECT_EQ(next, 10U);
  EXPECT_GT(w.int_ops, 0U);
  check_all(m, 0U);
}

TEST(Route, Figure6MappedOntoTheEightByEightGridGoesViaTile18) {
  // Same (x, y) positions on our 8-wide grid: paper 4,5,0,9,10 = (0,1),(1,1),(0,0),(1,2),(2,2) = 8,9,0,17,18.
  udn::FaultMap m{};
  ASSERT_EQ(udn::fault_map_init(m, 8U, 8U), udn::RouteError::kOk);
  ASSERT_EQ(udn::fault_map_fail_tile(m, 8U), udn::RouteError::kOk);
  ASSERT_EQ(udn::fault_map_fail_tile(m, 9U), udn::RouteError::kOk);
  udn::RouteTable t{};
  bsp::Work w{};
  ASSERT_EQ(udn::route_table_build(m, 0U, t, w), udn::RouteError::kOk);
  EXPECT_EQ(t.to[17].via_count, 1U);
  EXPECT_EQ(t.to[17].via[0], 18U);
  EXPECT_EQ(t.to[17].hops, 5U);
}

TEST(Route, DirectWhenNothingFailedAndUnreachableWhenWalledOff) {
  udn::FaultMap m{};
  ASSERT_EQ(udn::fault_map_init(m, 4U, 4U), udn::RouteError::kOk);
  udn::RouteTable t{};
  bsp::Work w{};
  ASSERT_EQ(udn::route_table_build(m, 5U, t, w), udn::RouteError::kOk);
  for (std::uint32_t d = 0; d < 16U; ++d) {
    EXPECT_EQ(t.to[d].via_count, 0U);
    EXPECT_EQ(t.to[d].hops, udn::path_hops(4U, 5U, d));
  }
  // Corner 0 cut off by both of its links (undirected failures).
  ASSERT_EQ(udn::fault_map_fail_link(m, 0U, bsp::UdnDir::kEast, true), udn::RouteError::kOk);
  ASSERT_EQ(udn::fault_map_fail_link(m, 0U, bsp::UdnDir::kSouth, true), udn::RouteError::kOk);
  ASSERT_EQ(udn::route_table_build(m, 5U, t, w), udn::RouteError::kOk);
  EXPECT_EQ(t.to[0].status, udn::RouteError::kUnreachable);
  EXPECT_EQ(udn::fault_map_fail_link(m, 3U, bsp::UdnDir::kEast, false), udn::RouteError::kBadTile);
  EXPECT_EQ(udn::fault_map_fail_tile(m, 16U), udn::RouteError::kBadTile);
  EXPECT_EQ(udn::fault_map_init(m, 9U, 8U), udn::RouteError::kBadGrid);
  check_all(m, 1U);
}

TEST(Route, RandomFaultMapsMatchBruteForceAndAvoidEveryFailure) {
  constexpr std::uint64_t kSeed = 20261122U;
  bsp::Rng rng(kSeed, bsp::StreamId::kTest);
  for (int trial = 0; trial < 6; ++trial) {
    udn::FaultMap m{};
    const std::uint64_t cols = 4U + static_cast<std::uint32_t>(rng.below(3U));
    const std::uint64_t rows = 4U + static_cast<std::uint32_t>(rng.below(2U));
    ASSERT_EQ(udn::fault_map_init(m, static_cast<std::uint32_t>(cols), static_cast<std::uint32_t>(rows)), udn::RouteError::kOk);
    const auto tiles_failed = rng.below(4U);
    for (std::uint64_t i = 0; i < tiles_failed; ++i) {
      ASSERT_EQ(udn::fault_map_fail_tile(m, static_cast<bsp::TileId>(rng.below(cols * rows))), udn::RouteError::kOk);
    }
    const auto links_failed = rng.below(5U);
    for (std::uint64_t i = 0; i < links_failed; ++i) {
      const auto t = static_cast<bsp::TileId>(rng.below(cols * rows));
      const auto d = static_cast<bsp::UdnDir>(rng.below(4U));
      (void)udn::fault_map_fail_link(m, t, d, rng.below(2U) == 0U);  // off-grid picks are refused: fine
    }
    check_all(m, kSeed + static_cast<std::uint64_t>(trial));
  }
}

}  // namespace

// FDIR-TR-15: the twin of a route is a second way that shares none of its switches (but the two ends)
// and none of its links, clear of failed tiles and links, through a tile that can forward; the
// fewest hops of those. On an 8 x 8 grid with nothing failed every pair has one; a failed tile is
// never the twin nor on its legs.
TEST(RouteTwin, ASecondWayThatSharesNoSwitchAndNoLinkWithTheRoute) {
  udn::FaultMap map{};
  ASSERT_EQ(udn::fault_map_init(map, 8U, 8U), udn::RouteError::kOk);
  udn::FaultMap failed = map;
  ASSERT_EQ(udn::fault_map_fail_tile(failed, 27U), udn::RouteError::kOk);
  failed.no_forward = std::uint64_t{1} << 19U;
  std::uint32_t pairs = 0;
  std::uint32_t with_twin = 0;
  for (const udn::FaultMap* m : {&map, &failed}) {
    for (bsp::TileId s = 0; s < 64U; ++s) {
      for (bsp::TileId d = 0; d < 64U; ++d) {
        if (s == d || !udn::path_clear(*m, s, d)) {
          continue;
        }
        ++pairs;
        const std::uint64_t tiles = udn::path_tiles(*m, s, d);
        const udn::LinkSet links = udn::path_links(*m, s, d);
        bsp::Work work{};
        const bsp::TileId v = udn::route_twin_via(*m, s, d, tiles, links, std::uint64_t{1} << 20U, work);
        if (v == bsp::kNoTile) {
          EXPECT_NE(m, &map) << s << " -> " << d << ": nothing failed, a twin exists";
          continue;
        }
        ++with_twin;
        const std::uint64_t ends = (std::uint64_t{1} << s) | (std::uint64_t{1} << d);
        const std::uint64_t way = udn::path_tiles(*m, s, v) | udn::path_tiles(*m, v, d);
        const udn::LinkSet l1 = udn::path_links(*m, s, v);
        const udn::LinkSet l2 = udn::path_links(*m, v, d);
        EXPECT_EQ(way & tiles & ~ends, 0U) << s << " -> " << d << " via " << v;
        EXPECT_EQ((l1.w[0] | l2.w[0]) & links.w[0], 0U) << s << " -> " << d << " via " << v;
        EXPECT_EQ((l1.w[1] | l2.w[1]) & links.w[1], 0U) << s << " -> " << d << " via " << v;
        EXPECT_TRUE(udn::path_clear(*m, s, v) && udn::path_clear(*m, v, d));
        EXPECT_TRUE(m != &failed || v != 19U) << "no_forward";
        EXPECT_NE(v, 20U) << "off";
        EXPECT_EQ(way & m->failed_tiles, 0U);
      }
    }
  }
  EXPECT_GT(with_twin, pairs * 9U / 10U);
}
