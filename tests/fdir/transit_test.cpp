/**
 * @file transit_test.cpp
 * @brief Transit plans on the mission's tile map and the verdict on lost transits.
 */
#include "fdir/transit.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cstdio>
#include <vector>

namespace {

constexpr std::uint64_t bit(std::uint32_t t) { return std::uint64_t{1} << t; }

/**
 * The mission's live tiles (trn/tasks/tile_map.hpp): supervisor 0, coordinator 1, filter and vision
 * supervisors 6 and 7, I/O 9, filter 18, replicas 19..21, vision 24..63. The coordinator and the filter
 * do not ping (trn::tasks::tile_map_transits): the other live tiles are the probers.
 */
constexpr std::uint64_t kLive = bit(0) | bit(1) | bit(6) | bit(7) | bit(9) | bit(18) | bit(19) | bit(20) | bit(21) |
                                (~std::uint64_t{0} << 24U);
constexpr std::uint64_t kProbers = kLive & ~bit(1) & ~bit(18);
constexpr std::uint64_t kSpares = ~kLive;

udn::FaultMap grid() {
  udn::FaultMap m{};
  EXPECT_EQ(udn::fault_map_init(m, 8, 8), udn::RouteError::kOk);
  return m;
}

TEST(Transit, UnderObservedTilesAreThoseWithOneLiveNeighbour) {
  const udn::FaultMap m = grid();
  // 9 has only 1 (8, 10, 17 are spares); 0 has only 1; 6 and 7 only each other; 1 has 0 and 9;
  // 18 has 19 and 26.
  EXPECT_EQ(fdir::under_observed(m, kLive, 2), bit(0) | bit(6) | bit(7) | bit(9));
}

TEST(Transit, MissionPlanTestsEverySpareThatCarriesTrafficAndTellsThemApart) {
  const udn::FaultMap m = grid();
  const std::uint64_t subjects = kSpares | fdir::under_observed(m, kLive, 2);
  fdir::TransitPlan p{};
  ASSERT_EQ(fdir::plan_transits(m, kProbers, subjects, p), fdir::TransitError::kOk);
  for (std::uint32_t i = 0; i < p.count; ++i) {
    std::printf("transit %2u: %2u -> %2u  spares on the way %d\n", i, p.t[i].prober, p.t[i].target,
                std::popcount(p.t[i].path & kSpares & ~bit(p.t[i].prober) & ~bit(p.t[i].target)));
  }
  std::uint64_t probers = 0;
  for (std::uint32_t i = 0; i < p.count; ++i) {
    probers |= bit(p.t[i].prober);
  }
  std::printf("transits %u from %d probers, tested %d, untested %d\n", p.count, std::popcount(probers),
              std::popcount(p.tested), std::popcount(p.untested));
  // Every subject on a leg between live tiles is tested but the vision supervisor's tile 7: a corner
  // whose every heard transit enters it over link 6-7 or from spare 15, and the planner finds no two
  // that one failed link or one tile cannot both lose. (Before, its own pings counted, which a dead
  // switch never reports: it was never nameable, only called tested.)
  EXPECT_EQ(p.untested, bit(7)) << std::hex << p.untested;
  EXPECT_NE(p.tested & bit(11), 0U);
  EXPECT_NE(p.tested & bit(23), 0U);
  EXPECT_NE(p.tested & bit(9), 0U);
  // No prober pings more than its share; no transit pairs mesh neighbours.
  for (bsp::TileId t = 0; t < 64; ++t) {
    EXPECT_LE(std::popcount(fdir::transit_targets(p, t)), static_cast<int>(fdir::kTransitsPerProber));
  }
}

/** The transits a failed switch @p x kills: every one whose round trip crosses it. */
std::uint64_t killed_by(const fdir::TransitPlan& p, bsp::TileId x) {
  std::uint64_t lost = 0;
  for (std::uint32_t i = 0; i < p.count; ++i) {
    lost |= (p.t[i].path & bit(x)) != 0U ? bit(i) : 0U;
  }
  return lost;
}

/** The transits tile @p x pings itself. */
std::uint64_t pinged_by(const fdir::TransitPlan& p, bsp::TileId x) {
  std::uint64_t m = 0;
  for (std::uint32_t i = 0; i < p.count; ++i) {
    m |= p.t[i].prober == x ? bit(i) : 0U;
  }
  return m;
}

TEST(Transit, EverySingleFailedSwitchIsNamedAndNoOtherIsBlamed) {
  const udn::FaultMap m = grid();
  const std::uint64_t subjects = kSpares | fdir::under_observed(m, kLive, 2);
  fdir::TransitPlan p{};
  ASSERT_EQ(fdir::plan_transits(m, kProbers, subjects, p), fdir::TransitError::kOk);
  for (bsp::TileId x = 0; x < 64; ++x) {
    const std::uint64_t lost = killed_by(p, x);
    const bsp::TileId v = fdir::transit_verdict(p, lost, subjects, 0U);
    if ((p.tested & bit(x)) != 0U) {
      EXPECT_EQ(v, x) << "a tested switch that fails is named";
      // FDIR-TR-10: what the health tile hears: a dead switch's own pings are lost with nobody
      // told (the I/O tile's, tile 9, four of its nine transits, kept it from being named).
      EXPECT_EQ(fdir::transit_verdict(p, lost & ~pinged_by(p, x), subjects, 0U), x)
          << "tile " << x << ": named without its own reports";
    } else if ((subjects & bit(x)) == 0U) {
      // A live switch the neighbours vote on: once voted (known failed), its transits tell nothing.
      EXPECT_EQ(fdir::transit_verdict(p, lost, subjects, bit(x)), bsp::kNoTile) << "tile " << x;
    }
  }
}

TEST(Transit, AHungCoreIsNoFailedSwitch) {
  // A hung core answers no ping, so the transits it is an end of are lost,
  // but its switch still carries the transits through it: no switch is named.
  const udn::FaultMap m = grid();
  const std::uint64_t subjects = kSpares | fdir::under_observed(m, kLive, 2);
  fdir::TransitPlan p{};
  ASSERT_EQ(fdir::plan_transits(m, kProbers, subjects, p), fdir::TransitError::kOk);
  for (const bsp::TileId x : {bsp::TileId{0}, bsp::TileId{9}}) {
    const std::uint64_t ends = killed_by(p, x) & ~fdir::transits_through(p, x);
    ASSERT_NE(fdir::transits_through(p, x), 0U) << "transits cross tile " << x;
    EXPECT_EQ(fdir::transit_verdict(p, ends, subjects, 0U), bsp::kNoTile) << "tile " << x;
    EXPECT_EQ(fdir::transit_verdict(p, killed_by(p, x), subjects, 0U), x) << "its switch failing is named";
  }
}

TEST(Transit, OneLostTransitIsNeverEnough) {
  const udn::FaultMap m = grid();
  fdir::TransitPlan p{};
  ASSERT_EQ(fdir::plan_transits(m, kProbers, kSpares, p), fdir::TransitError::kOk);
  for (std::uint32_t i = 0; i < p.count; ++i) {
    EXPECT_EQ(fdir::transit_verdict(p, bit(i), kSpares, 0U), bsp::kNoTile);
  }
  EXPECT_EQ(fdir::transit_verdict(p, 0U, kSpares, 0U), bsp::kNoTile);
}

TEST(Transit, BadGridIsRefused) {
  udn::FaultMap m{};
  fdir::TransitPlan p{};
  EXPECT_EQ(fdir::plan_transits(m, kProbers, kSpares, p), fdir::TransitError::kBadArgs);
}

}  // namespace

namespace {

/** The transits tile @p t is an end of in @p p: it pings them or answers them (bit per plan index). */
std::uint64_t ended_by(const fdir::TransitPlan& p, bsp::TileId t) {
  std::uint64_t m = 0;
  for (std::uint32_t i = 0; i < p.count; ++i) {
    m |= (p.t[i].prober == t || p.t[i].target == t) ? bit(i) : 0U;
  }
  return m;
}

/** Two transits of @p mask with no end in common (neither's prober or target is the other's). */
bool independent_pair(const fdir::TransitPlan& p, std::uint64_t mask) {
  for (std::uint32_t i = 0; i < p.count; ++i) {
    for (std::uint32_t j = 0; j < p.count; ++j) {
      const fdir::Transit& a = p.t[i];
      const fdir::Transit& b = p.t[j];
      const bool apart = a.prober != b.prober && a.prober != b.target && a.target != b.prober && a.target != b.target;
      if ((mask & bit(i)) != 0U && (mask & bit(j)) != 0U && apart) {
        return true;
      }
    }
  }
  return false;
}

fdir::TransitPlan mission_plan(std::uint64_t& subjects) {
  const udn::FaultMap m = grid();
  subjects = kSpares | fdir::under_observed(m, kLive, 2);
  fdir::TransitPlan p{};
  EXPECT_EQ(fdir::plan_transits(m, kProbers, subjects, p), fdir::TransitError::kOk);
  return p;
}

}  // namespace

// FDIR-TR-06: transit reports are voted like neighbour reports: every tested subject's switch is
// crossed by two transits with no end in common, and a switch is failed only when two such are lost.
TEST(Transit, EveryTestedSubjectIsCrossedByTwoIndependentTransits) {
  std::uint64_t subjects = 0;
  const fdir::TransitPlan p = mission_plan(subjects);
  for (bsp::TileId x = 0; x < 64; ++x) {
    if ((p.tested & bit(x)) != 0U) {
      EXPECT_TRUE(independent_pair(p, killed_by(p, x))) << "subject " << x;
    }
  }
}

// FDIR-TR-07: one faulty tile, whatever it does to the transits it is an end of (a prober that
// reports them lost, a target that answers none, an end whose own links failed), fails no switch.
TEST(Transit, NoOneFaultyTileFailsASwitch) {
  std::uint64_t subjects = 0;
  const fdir::TransitPlan p = mission_plan(subjects);
  for (bsp::TileId t = 0; t < 64; ++t) {
    const std::uint64_t mine = ended_by(p, t);
    ASSERT_LE(std::popcount(mine), 12) << "tile " << t;  // every part below is tried
    for (std::uint64_t part = mine; part != 0U; part = (part - 1U) & mine) {
      EXPECT_EQ(fdir::transit_verdict(p, part, subjects, 0U), bsp::kNoTile) << "tile " << t << " alone, lost " << part;
    }
  }
}

namespace {

/** The tiles of the X-then-Y leg from @p a to @p b, in order (8 x 8 grid). */
std::vector<std::uint32_t> leg(std::uint32_t a, std::uint32_t b) {
  std::vector<std::uint32_t> v{a};
  std::uint32_t x = a % 8U;
  std::uint32_t y = a / 8U;
  while (x != b % 8U) {
    x = (b % 8U > x) ? x + 1U : x - 1U;
    v.push_back(y * 8U + x);
  }
  while (y != b / 8U) {
    y = (b / 8U > y) ? y + 1U : y - 1U;
    v.push_back(y * 8U + x);
  }
  return v;
}

/** The transits of @p p whose round trip crosses the link between neighbours @p u and @p w. */
std::uint64_t across(const fdir::TransitPlan& p, std::uint32_t u, std::uint32_t w) {
  std::uint64_t m = 0;
  for (std::uint32_t i = 0; i < p.count; ++i) {
    for (const auto& v : {leg(p.t[i].prober, p.t[i].target), leg(p.t[i].target, p.t[i].prober)}) {
      for (std::size_t k = 1; k < v.size(); ++k) {
        m |= ((v[k - 1] == u && v[k] == w) || (v[k - 1] == w && v[k] == u)) ? bit(i) : 0U;
      }
    }
  }
  return m;
}

}  // namespace

// FDIR-TR-08: a failed link, a prober's own included, loses transits of several subjects but all
// of none: it fails no switch (nobody votes a link to a spare, so the transits are all there is).
TEST(Transit, NoOneFailedLinkFailsASwitch) {
  std::uint64_t subjects = 0;
  const fdir::TransitPlan p = mission_plan(subjects);
  for (std::uint32_t u = 0; u < 64U; ++u) {
    for (const std::uint32_t w : {u + 1U, u + 8U}) {
      if (w >= 64U || (w == u + 1U && u % 8U == 7U)) {
        continue;
      }
      EXPECT_EQ(fdir::transit_verdict(p, across(p, u, w), subjects, 0U), bsp::kNoTile) << "link " << u << "-" << w;
    }
  }
}

// FDIR-TR-09: a link the neighbours voted failed (both ends live) is in the map: the transits across
// it tell nothing more, so it and one faulty tile besides still fail no switch.
TEST(Transit, AVotedLinkAndOneFaultyTileFailNoSwitch) {
  std::uint64_t subjects = 0;
  const fdir::TransitPlan p = mission_plan(subjects);
  udn::FaultMap m = grid();
  std::uint32_t voted_links = 0;
  for (std::uint32_t u = 0; u < 64U; ++u) {
    for (const bsp::UdnDir dir : {bsp::UdnDir::kEast, bsp::UdnDir::kSouth}) {
      const std::uint32_t w = dir == bsp::UdnDir::kEast ? u + 1U : u + 8U;
      if (w >= 64U || (dir == bsp::UdnDir::kEast && u % 8U == 7U) || (kLive & bit(u)) == 0U || (kLive & bit(w)) == 0U) {
        continue;
      }
      udn::FaultMap with = m;
      ASSERT_EQ(udn::fault_map_fail_link(with, static_cast<bsp::TileId>(u), dir, true), udn::RouteError::kOk);
      const std::uint64_t mute = fdir::transits_across(p, udn::failed_link_set(with));
      EXPECT_EQ(mute, across(p, u, w)) << "link " << u << "-" << w;
      ++voted_links;
      for (bsp::TileId e = 0; e < 64; ++e) {
        EXPECT_EQ(fdir::transit_verdict(p, mute | ended_by(p, e), subjects, 0U, mute), bsp::kNoTile)
            << "link " << u << "-" << w << " and tile " << e;
      }
    }
  }
  EXPECT_GT(voted_links, 0U);
}

namespace {

/** How the mission probers' reports come to the health tile 0: their route and its twin. */
fdir::ReportWays ways_to_0(const fdir::TransitPlan& p) {
  fdir::ReportWays w{};
  bsp::Work work{};
  fdir::report_ways(p, grid(), 0U, 0U, w, work);
  return w;
}

/** The links the verdict on the health tile 0 names, as (west or north tile, east or south tile). */
std::vector<std::pair<std::uint32_t, std::uint32_t>> named_links(const fdir::TransitPlan& p, std::uint64_t lost,
                                                                 std::uint64_t known_failed = 0U) {
  const fdir::LinkVerdict v = fdir::transit_link_verdict(p, 8U, 8U, ways_to_0(p), lost, known_failed, 0U);
  std::vector<std::pair<std::uint32_t, std::uint32_t>> out;
  for (std::uint32_t l = 0; l < 128U; ++l) {
    if ((v.links.w[l / 64U] >> (l % 64U) & 1U) != 0U) {
      out.emplace_back(l / 2U, (l % 2U) == 0U ? l / 2U + 1U : l / 2U + 8U);
    }
  }
  EXPECT_EQ(out.size(), v.count);
  if (v.count == 0U) {
    EXPECT_EQ(v.a, bsp::kNoTile);
    EXPECT_EQ(v.transits, 0U);
  } else {
    EXPECT_EQ(std::make_pair(std::uint32_t{v.a}, std::uint32_t{v.b}), out.front());
    EXPECT_EQ(v.transits, static_cast<std::uint32_t>(std::popcount(lost))) << "every lost one is across it";
  }
  return out;
}

/** The one link the verdict names, (64, 64) for none or a chain. */
std::pair<std::uint32_t, std::uint32_t> named_link(const fdir::TransitPlan& p, std::uint64_t lost,
                                                   std::uint64_t known_failed = 0U) {
  const auto v = named_links(p, lost, known_failed);
  return v.size() == 1U ? v.front() : std::make_pair(64U, 64U);
}

/** The tiles of the way prober @p t's reports take to tile 0 through its twin (empty: no twin). */
std::vector<std::uint32_t> twin_way(std::uint32_t t) {
  const udn::FaultMap m = grid();
  const auto s = static_cast<bsp::TileId>(t);
  bsp::Work work{};
  const bsp::TileId via =
      udn::route_twin_via(m, s, 0U, udn::path_tiles(m, s, 0U), udn::path_links(m, s, 0U), 0U, work);
  if (via == bsp::kNoTile) {
    return {};
  }
  std::vector<std::uint32_t> v = leg(t, via);
  const std::vector<std::uint32_t> rest = leg(via, 0U);
  v.insert(v.end(), rest.begin() + 1, rest.end());
  return v;
}

bool crosses(const std::vector<std::uint32_t>& v, std::uint32_t u, std::uint32_t w) {
  for (std::size_t k = 1; k < v.size(); ++k) {
    if ((v[k - 1] == u && v[k] == w) || (v[k - 1] == w && v[k] == u)) {
      return true;
    }
  }
  return false;
}

/** The transits whose prober's reports cannot reach tile 0 with the link @p u - @p w failed: both ways cross it. */
std::uint64_t cut_off(const fdir::TransitPlan& p, std::uint32_t u, std::uint32_t w) {
  std::uint64_t m = 0;
  for (std::uint32_t i = 0; i < p.count; ++i) {
    const std::vector<std::uint32_t> twin = twin_way(p.t[i].prober);
    const bool twin_cut = twin.empty() || crosses(twin, u, w);
    m |= p.t[i].prober != 0U && crosses(leg(p.t[i].prober, 0U), u, w) && twin_cut ? bit(i) : 0U;
  }
  return m;
}

/** What the health tile 0 hears of a failed link @p u - @p w: its transits, but those whose reports it cuts off. */
std::uint64_t heard_across(const fdir::TransitPlan& p, std::uint32_t u, std::uint32_t w) {
  return across(p, u, w) & ~cut_off(p, u, w);
}

/**
 * What the health tile 0 hears of switch @p x failed: the transits through it, but those it pings
 * itself and those whose reports it cuts off (both ways to tile 0 cross it).
 */
std::uint64_t heard_of_switch(const fdir::TransitPlan& p, bsp::TileId x) {
  const udn::FaultMap m = grid();
  std::uint64_t cut = 0;
  for (std::uint32_t i = 0; i < p.count; ++i) {
    const std::vector<std::uint32_t> twin = twin_way(p.t[i].prober);
    bool twin_cut = twin.empty();
    for (const std::uint32_t t : twin) {
      twin_cut = twin_cut || t == x;
    }
    cut |= x != 0U && (udn::path_tiles(m, p.t[i].prober, 0U) & bit(x)) != 0U && twin_cut ? bit(i) : 0U;
  }
  return killed_by(p, x) & ~pinged_by(p, x) & ~cut;
}

}  // namespace

// FDIR-TR-12: a failed link no neighbour vote can name (a spare at one end, or an end that does not
// probe) is named by the transits across it when they can vote it, and never is another link or a
// switch named. The coordinator's east link to spare 2 was silent: its traffic to the vision tiles
// given up for the rest of the flight, and the coordinator's frames lost.
TEST(Transit, EverySingleFailedLinkIsNamedOrNothingIs) {
  std::uint64_t subjects = 0;
  const fdir::TransitPlan p = mission_plan(subjects);
  std::uint32_t crossed = 0;
  std::uint32_t named = 0;
  std::uint32_t unvoted_named = 0;
  std::uint32_t chains = 0;
  for (std::uint32_t u = 0; u < 64U; ++u) {
    for (const std::uint32_t w : {u + 1U, u + 8U}) {
      if (w >= 64U || (w == u + 1U && u % 8U == 7U) || across(p, u, w) == 0U) {
        continue;
      }
      ++crossed;
      const auto chain = named_links(p, heard_across(p, u, w));
      if (chain.size() > 1U) {
        // Links every transit crosses together: named whole, the failed one among them.
        EXPECT_NE(std::find(chain.begin(), chain.end(), std::make_pair(u, w)), chain.end()) << "link " << u << "-" << w;
        for (const auto& c : chain) {
          EXPECT_EQ(across(p, c.first, c.second), across(p, u, w)) << c.first << "-" << c.second;
        }
        ++chains;
      }
      const auto v = named_link(p, heard_across(p, u, w));
      if (v.first != 64U) {
        EXPECT_EQ(v, std::make_pair(u, w)) << "link " << u << "-" << w << " names another";
        const std::uint64_t unsure =
            fdir::transit_link_verdict(p, 8U, 8U, ways_to_0(p), heard_across(p, u, w), 0U, 0U).unsure;
        EXPECT_EQ(unsure & ~(bit(u) | bit(w)), 0U) << "link " << u << "-" << w;
        ++named;
        const bool voted = (kProbers & bit(u)) != 0U && (kProbers & bit(w)) != 0U;
        unvoted_named += voted ? 0U : 1U;
      }
    }
  }
  std::printf("links crossed by transits %u, named when they fail %u (%u that no neighbour vote names), %u more "
              "in a chain taken out whole\n", crossed, named, unvoted_named, chains);
  // Those the plan set out to name (an end that does not probe, on a leg between probers) are named.
  std::uint32_t planned = 0;
  for (std::uint32_t l = 0; l < 128U; ++l) {
    if ((p.links_named.w[l / 64U] >> (l % 64U) & 1U) == 0U) {
      continue;
    }
    ++planned;
    const std::uint32_t u = l / 2U;
    const std::uint32_t w = (l % 2U) == 0U ? u + 1U : u + 8U;
    EXPECT_EQ(named_link(p, heard_across(p, u, w)), std::make_pair(u, w)) << "planned link " << u << "-" << w;
  }
  std::printf("links the plan names: %u\n", planned);
  EXPECT_EQ(planned, 23U);
  // The coordinator's east link: the reports of tiles 6 and 7 cross it on their way to tile 0 and
  // come by their twins.
  EXPECT_EQ(cut_off(p, 1U, 2U), 0U);
  EXPECT_EQ(named_link(p, across(p, 1U, 2U)), std::make_pair(1U, 2U)) << "the coordinator's east link";
  EXPECT_EQ(fdir::transit_link_verdict(p, 8U, 8U, ways_to_0(p), across(p, 1U, 2U), 0U, 0U).unsure, 0U)
      << "spare 2's other transits are heard: its switch routes";
  EXPECT_EQ(named, 40U);
  EXPECT_EQ(unvoted_named, 28U);
}

// FDIR-TR-13: a failed switch loses every transit through it, and the reports that would cross it
// never come; a live switch with two live neighbours is voted first. What the health tile hears then
// names no link, or one of the switch's own links with the switch marked unsure (from here they look
// the same: the health tile takes a spare's switch out, fdir/net_health.cpp). A hung core, whose
// transits are lost where it is their end, names no link.
TEST(Transit, NoFailedSwitchOrHungCoreNamesALink) {
  std::uint64_t subjects = 0;
  const fdir::TransitPlan p = mission_plan(subjects);
  std::uint32_t unsure = 0;
  for (bsp::TileId x = 0; x < 64; ++x) {
    const std::uint64_t lost = heard_of_switch(p, x);
    const std::uint64_t voted = (subjects & bit(x)) == 0U ? bit(x) : 0U;
    if ((p.tested & bit(x)) != 0U) {
      // What the health tile hears of a tested switch's failure names it: the reports its switch
      // cuts off come through their twins (spares 3, 4, 8, 16 and 17 were never named before).
      EXPECT_EQ(fdir::transit_verdict(p, lost, subjects, 0U), x) << "switch " << x << " from what is heard";
    }
    if (voted == 0U && fdir::transit_verdict(p, lost, subjects, 0U) == x) {
      continue;  // named as a switch: the link verdict is not asked
    }
    const fdir::LinkVerdict v = fdir::transit_link_verdict(p, 8U, 8U, ways_to_0(p), lost, voted, 0U);
    EXPECT_LE(v.count, 1U) << "switch " << x << " names no chain";
    if (v.a != bsp::kNoTile) {
      EXPECT_TRUE(v.a == x || v.b == x) << "switch " << x << " names link " << v.a << "-" << v.b;
      EXPECT_NE(v.unsure & bit(x), 0U) << "switch " << x;
      EXPECT_NE(kSpares & bit(x), 0U) << "switch " << x << ": a live tile's switch is only ever unsure for a spare";
      ++unsure;
    }
    EXPECT_EQ(named_link(p, (killed_by(p, x) & ~fdir::transits_through(p, x)) & ~pinged_by(p, x)).first, 64U)
        << "core " << x;
  }
  std::printf("failed switches that look like one of their links from the health tile: %u\n", unsure);
}

// FDIR-TR-14: one faulty tile, whatever it does to the transits it is an end of, names no link.
TEST(Transit, NoOneFaultyTileNamesALink) {
  std::uint64_t subjects = 0;
  const fdir::TransitPlan p = mission_plan(subjects);
  for (bsp::TileId t = 0; t < 64; ++t) {
    const std::uint64_t mine = ended_by(p, t);
    for (std::uint64_t part = mine; part != 0U; part = (part - 1U) & mine) {
      EXPECT_EQ(named_link(p, part).first, 64U) << "tile " << t << " alone, lost " << part;
    }
  }
}

// FDIR-TR-16: a link whose lost transits all share one end, a tile heard (its own reports of lost
// transits come), is named when that tile is an end of the link: the I/O tile's links to its spare
// neighbours, which no neighbour vote and no two independent transits name (two single-fault
// campaign runs ended silent with the I/O tile's east link failed, its IMU stream to the filter
// given up for the rest of the descent). Never another link, and never without the tile heard.
TEST(Transit, ALinkOfAHeardTileTheLostTransitsShareIsNamed) {
  std::uint64_t subjects = 0;
  const fdir::TransitPlan p = mission_plan(subjects);
  const auto verdict = [&](std::uint64_t lost, std::uint64_t heard, std::uint64_t voted = 0U) {
    return fdir::transit_link_verdict(p, 8U, 8U, ways_to_0(p), lost, voted, 0U, heard);
  };
  // The I/O tile's east link to spare 10.
  const std::uint64_t io_east = heard_across(p, 9U, 10U);
  ASSERT_GE(std::popcount(io_east), 2);
  EXPECT_EQ(verdict(io_east, 0U).count, 0U) << "every lost transit has tile 9 at an end: no two independent";
  const fdir::LinkVerdict v = verdict(io_east, bit(9));
  EXPECT_EQ(v.count, 1U);
  EXPECT_EQ(std::make_pair(std::uint32_t{v.a}, std::uint32_t{v.b}), std::make_pair(9U, 10U));
  EXPECT_EQ(v.unsure & bit(9), 0U) << "a heard tile's switch forwards its reports";
  EXPECT_EQ(verdict(io_east, kProbers & ~bit(9)).count, 0U) << "heard tiles elsewhere name nothing";
  // Every link: with every prober heard, what is named is the failed link (or a chain holding it).
  std::uint32_t more = 0;
  for (std::uint32_t u = 0; u < 64U; ++u) {
    for (const std::uint32_t w : {u + 1U, u + 8U}) {
      if (w >= 64U || (w == u + 1U && u % 8U == 7U) || across(p, u, w) == 0U) {
        continue;
      }
      const fdir::LinkVerdict h = verdict(heard_across(p, u, w), kProbers);
      if (h.count == 1U) {
        EXPECT_EQ(std::make_pair(std::uint32_t{h.a}, std::uint32_t{h.b}), std::make_pair(u, w)) << "link " << u << "-" << w;
      }
      more += h.count != 0U && named_links(p, heard_across(p, u, w)).empty() ? 1U : 0U;
    }
  }
  std::printf("links named only through a heard end: %u\n", more);
  EXPECT_EQ(more, 3U) << "6-14, 8-9 and 9-10 (the filter supervisor's and the I/O tile's links to spares)";
  // A hung core is not heard: what its transits lose names no link even when every other prober is.
  // A failed switch names one of its own links at most, with the switch unsure (taken out instead).
  for (bsp::TileId t = 0; t < 64; ++t) {
    EXPECT_EQ(verdict(ended_by(p, t), kProbers & ~bit(t)).count, 0U) << "core " << t;
    // A switch with two live neighbours is voted by them first (known failed then), as in FDIR-TR-13.
    const std::uint64_t voted = (subjects & bit(t)) == 0U ? bit(t) : 0U;
    const fdir::LinkVerdict sw = verdict(heard_of_switch(p, t), kProbers & ~bit(t), voted);
    if (sw.count != 0U && (voted != 0U || fdir::transit_verdict(p, heard_of_switch(p, t), subjects, 0U) != t)) {
      EXPECT_TRUE(sw.a == t || sw.b == t) << "switch " << t << " names link " << sw.a << "-" << sw.b;
      EXPECT_NE(sw.unsure & bit(t), 0U) << "switch " << t;
    }
  }
}
