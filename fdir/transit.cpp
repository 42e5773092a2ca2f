/**
 * @file transit.cpp
 * @brief The transit plan (coverage, then telling subjects apart) and the verdict on lost transits.
 */
#include "fdir/transit.hpp"

#include <bit>

namespace fdir {
namespace {

constexpr std::uint64_t bit(std::uint32_t t) noexcept { return std::uint64_t{1} << t; }

bool has(std::uint64_t mask, std::uint32_t t) noexcept { return t < 64U && (mask & bit(t)) != 0U; }

bool neighbours(std::uint32_t cols, std::uint32_t a, std::uint32_t b) noexcept {
  const std::uint32_t ax = a % cols;
  const std::uint32_t bx = b % cols;
  const std::uint32_t ay = a / cols;
  const std::uint32_t by = b / cols;
  const std::uint32_t dx = ax > bx ? ax - bx : bx - ax;
  const std::uint32_t dy = ay > by ? ay - by : by - ay;
  return dx + dy == 1U;
}

/** Switches a transit tests: its round trip without its two ends. */
std::uint64_t interior(const Transit& t) noexcept { return t.path & ~bit(t.prober) & ~bit(t.target); }

std::uint64_t through(const TransitPlan& p, std::uint32_t tile) noexcept {
  std::uint64_t m = 0U;
  for (std::uint32_t i = 0; i < p.count; ++i) {
    m |= has(interior(p.t[i]), tile) ? bit(i) : 0U;
  }
  return m;
}

/** Transits a failed switch of @p tile kills: every one whose round trip crosses it, its own included. */
std::uint64_t touching(const TransitPlan& p, std::uint32_t tile) noexcept {
  std::uint64_t m = 0U;
  for (std::uint32_t i = 0; i < p.count; ++i) {
    m |= has(p.t[i].path, tile) ? bit(i) : 0U;
  }
  return m;
}

/** Subject @p s is told apart from subject @p x: their failed switches kill different transits. */
bool apart(const TransitPlan& p, std::uint32_t s, std::uint32_t x) noexcept {
  return through(p, s) != 0U && touching(p, s) != touching(p, x);
}

struct Search {
  const udn::FaultMap* map;
  std::uint64_t probers;
  std::uint64_t subjects;
  std::uint32_t tiles;
  std::array<std::uint32_t, 64> load;  ///< targets per prober so far
};

bool chosen(const TransitPlan& p, std::uint32_t a, std::uint32_t b) noexcept {
  for (std::uint32_t i = 0; i < p.count; ++i) {
    if (p.t[i].prober == a && p.t[i].target == b) {
      return true;
    }
  }
  return false;
}

/**
 * Adds the transit through @p need and not through @p avoid (kNoTile: any)
 * that crosses the fewest subjects, then the fewest switches, then comes
 * first in (prober, target) order. @return false when there is none or the plan is full.
 */
bool add_best(TransitPlan& p, Search& s, std::uint32_t need, std::uint32_t avoid) noexcept {
  if (p.count >= kMaxTransits) {
    return false;
  }
  Transit best{};
  int best_subjects = 65;
  int best_len = 129;
  for (std::uint32_t a = 0; a < s.tiles; ++a) {
    if (!has(s.probers, a) || s.load[a] >= kTransitsPerProber) {
      continue;
    }
    for (std::uint32_t b = 0; b < s.tiles; ++b) {
      if (a == b || !has(s.probers, b) || neighbours(s.map->cols, a, b) || chosen(p, a, b)) {
        continue;
      }
      const auto ta = static_cast<bsp::TileId>(a);
      const auto tb = static_cast<bsp::TileId>(b);
      const Transit t{ta, tb, udn::path_tiles(*s.map, ta, tb) | udn::path_tiles(*s.map, tb, ta)};
      const std::uint64_t in = interior(t);
      if (!has(in, need) || (avoid < 64U && has(t.path, avoid))) {
        continue;
      }
      const int ns = std::popcount(in & s.subjects);
      const int len = std::popcount(t.path);
      if (ns < best_subjects || (ns == best_subjects && len < best_len)) {
        best = t;
        best_subjects = ns;
        best_len = len;
      }
    }
  }
  if (best.prober == bsp::kNoTile) {
    return false;
  }
  p.t[p.count] = best;
  ++p.count;
  ++s.load[best.prober];
  return true;
}

/** Subjects some leg between two probers passes through (the ones that carry traffic). */
std::uint64_t reachable(const Search& s) noexcept {
  std::uint64_t m = 0U;
  for (std::uint32_t a = 0; a < s.tiles; ++a) {
    for (std::uint32_t b = 0; b < s.tiles && has(s.probers, a); ++b) {
      if (a != b && has(s.probers, b)) {
        const auto ta = static_cast<bsp::TileId>(a);
        const auto tb = static_cast<bsp::TileId>(b);
        m |= udn::path_tiles(*s.map, ta, tb) & ~bit(a) & ~bit(b);
      }
    }
  }
  return m & s.subjects;
}

}  // namespace

TransitError plan_transits(const udn::FaultMap& map, std::uint64_t probers, std::uint64_t subjects,
                           TransitPlan& out) noexcept {
  const std::uint32_t tiles = map.cols * map.rows;
  if (map.cols == 0U || tiles == 0U || tiles > 64U) {
    return TransitError::kBadArgs;
  }
  out = TransitPlan{};
  Search s{&map, probers, subjects, tiles, {}};
  const std::uint64_t want = reachable(s);
  // Coverage: every subject crossed by kTransitsPerSpare transits.
  for (std::uint32_t x = 0; x < tiles; ++x) {
    for (std::uint32_t k = 0; k < kTransitsPerSpare && has(want, x); ++k) {
      if (std::popcount(through(out, x)) < static_cast<int>(kTransitsPerSpare) && !add_best(out, s, x, 64U)) {
        break;
      }
    }
  }
  // Told apart: no two subjects kill the same transits. (A live switch that
  // kills a subject's transits is voted by its neighbours first, and its
  // transits then tell nothing.) Each pass adds at most one transit per pair.
  constexpr std::uint32_t kPasses = 3U;
  for (std::uint32_t pass = 0; pass < kPasses; ++pass) {
    bool added = false;
    for (std::uint32_t x = 0; x < tiles; ++x) {
      for (std::uint32_t y = 0; y < tiles && has(want, x); ++y) {
        if (y != x && has(subjects, y) && !apart(out, x, y) && through(out, x) != 0U && add_best(out, s, x, y)) {
          added = true;
        }
      }
    }
    if (!added) {
      break;
    }
  }
  for (std::uint32_t x = 0; x < tiles; ++x) {
    if (!has(want, x)) {
      continue;
    }
    bool ok = std::popcount(through(out, x)) >= static_cast<int>(kTransitsPerSpare);
    for (std::uint32_t y = 0; y < tiles && ok; ++y) {
      ok = y == x || !has(subjects, y) || apart(out, x, y);
    }
    out.tested |= ok ? bit(x) : 0U;
  }
  out.untested = want & ~out.tested;
  return TransitError::kOk;
}

std::uint64_t under_observed(const udn::FaultMap& map, std::uint64_t live, std::uint32_t votes) noexcept {
  const std::uint32_t tiles = map.cols * map.rows;
  std::uint64_t m = 0U;
  for (std::uint32_t t = 0; t < tiles && t < 64U && map.cols != 0U; ++t) {
    if (!has(live, t)) {
      continue;
    }
    const std::uint32_t x = t % map.cols;
    const std::uint32_t y = t / map.cols;
    std::uint32_t n = 0U;
    n += (x > 0U && has(live, t - 1U)) ? 1U : 0U;
    n += (x + 1U < map.cols && has(live, t + 1U)) ? 1U : 0U;
    n += (y > 0U && has(live, t - map.cols)) ? 1U : 0U;
    n += (y + 1U < map.rows && has(live, t + map.cols)) ? 1U : 0U;
    m |= n < votes ? bit(t) : 0U;
  }
  return m;
}

std::uint64_t transit_targets(const TransitPlan& plan, bsp::TileId prober) noexcept {
  std::uint64_t m = 0U;
  for (std::uint32_t i = 0; i < plan.count && i < kMaxTransits; ++i) {
    m |= plan.t[i].prober == prober ? bit(plan.t[i].target) : 0U;
  }
  return m;
}

std::uint32_t transit_index(const TransitPlan& plan, bsp::TileId prober, bsp::TileId target) noexcept {
  for (std::uint32_t i = 0; i < plan.count && i < kMaxTransits; ++i) {
    if (plan.t[i].prober == prober && plan.t[i].target == target) {
      return i;
    }
  }
  return kMaxTransits;
}

std::uint64_t transits_through(const TransitPlan& plan, bsp::TileId tile) noexcept { return through(plan, tile); }

bsp::TileId transit_verdict(const TransitPlan& plan, std::uint64_t lost, std::uint64_t subjects,
                            std::uint64_t known_failed) noexcept {
  // Candidates: subjects with enough telling transits, all lost. A failed
  // switch kills every transit through it, so a switch whose transits are a
  // part of another candidate's is explained by that one: the answer is the
  // one candidate whose lost transits no other candidate's include.
  std::array<std::uint64_t, 64> counted{};
  std::uint64_t candidates = 0U;
  for (std::uint32_t x = 0; x < 64U; ++x) {
    if (!has(subjects, x) || has(known_failed, x)) {
      continue;
    }
    for (std::uint32_t i = 0; i < plan.count && i < kMaxTransits; ++i) {
      const Transit& t = plan.t[i];
      const bool tells = has(t.path, x) && (t.path & known_failed) == 0U;
      counted[x] |= tells ? bit(i) : 0U;
    }
    const bool fits = std::popcount(counted[x]) >= static_cast<int>(kTransitsPerSpare) && (counted[x] & ~lost) == 0U;
    candidates |= fits ? bit(x) : 0U;
  }
  bsp::TileId found = bsp::kNoTile;
  for (std::uint32_t x = 0; x < 64U; ++x) {
    if (!has(candidates, x)) {
      continue;
    }
    bool maximal = true;
    for (std::uint32_t y = 0; y < 64U && maximal; ++y) {
      maximal = y == x || !has(candidates, y) || (counted[x] & ~counted[y]) != 0U;
    }
    if (maximal) {
      if (found != bsp::kNoTile) {
        return bsp::kNoTile;  // two candidates explain different losses: no one switch does
      }
      found = static_cast<bsp::TileId>(x);
    }
  }
  return found;
}

}  // namespace fdir
