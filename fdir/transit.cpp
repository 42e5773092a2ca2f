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

/** The two tiles whose software a transit relies on: the prober that reports it and the target that answers. */
std::uint64_t ends(const Transit& t) noexcept { return bit(t.prober) | bit(t.target); }

/**
 * Transits @p mask hold two independent ones: no end in common. One tile,
 * however faulty (it reports its transits lost, answers none, or lost its
 * own links), is an end of at most one of them, as a switch fault the neighbours
 * vote on needs two neighbours.
 */
bool independent(const TransitPlan& p, std::uint64_t mask) noexcept {
  for (std::uint32_t i = 0; i < p.count && i < kMaxTransits; ++i) {
    for (std::uint32_t j = i + 1U; j < p.count && j < kMaxTransits && has(mask, i); ++j) {
      if (has(mask, j) && (ends(p.t[i]) & ends(p.t[j])) == 0U) {
        return true;
      }
    }
  }
  return false;
}

bool empty(const udn::LinkSet& l) noexcept { return l.w[0] == 0U && l.w[1] == 0U; }

bool meet(const udn::LinkSet& a, const udn::LinkSet& b) noexcept {
  return (a.w[0] & b.w[0]) != 0U || (a.w[1] & b.w[1]) != 0U;
}

/** Links every transit of @p mask crosses (none for an empty mask): one of them failing would lose them all. */
udn::LinkSet common_links(const TransitPlan& p, std::uint64_t mask) noexcept {
  udn::LinkSet c{{~std::uint64_t{0}, ~std::uint64_t{0}}};
  bool any = false;
  for (std::uint32_t i = 0; i < p.count && i < kMaxTransits; ++i) {
    if (has(mask, i)) {
      c.w[0] &= p.t[i].links.w[0];
      c.w[1] &= p.t[i].links.w[1];
      any = true;
    }
  }
  return any ? c : udn::LinkSet{};
}

/** Ends of the first transit of @p mask (0 for none): a second one avoiding them makes the pair independent. */
std::uint64_t first_ends(const TransitPlan& p, std::uint64_t mask) noexcept {
  for (std::uint32_t i = 0; i < p.count && i < kMaxTransits; ++i) {
    if (has(mask, i)) {
      return ends(p.t[i]);
    }
  }
  return 0U;
}

std::uint64_t through(const TransitPlan& p, std::uint32_t tile) noexcept {
  std::uint64_t m = 0U;
  for (std::uint32_t i = 0; i < p.count; ++i) {
    m |= has(interior(p.t[i]), tile) ? bit(i) : 0U;
  }
  return m;
}

/**
 * The transits @p mask can vote a switch failed: kTransitsPerSpare of them at
 * least, two with no end in common, and no link all of them cross. Then one
 * tile (a lying prober, a silent target, one end's failed link) or one failed
 * link cannot lose them all.
 */
bool can_vote(const TransitPlan& p, std::uint64_t mask) noexcept {
  return std::popcount(mask) >= static_cast<int>(kTransitsPerSpare) && independent(p, mask) &&
         empty(common_links(p, mask));
}

/**
 * The transits touching @p tile that the health tile hears of when its switch
 * fails: not those it pings itself (a dead switch reports nothing, so they are
 * never reported lost).
 */
std::uint64_t heard(const TransitPlan& p, std::uint32_t tile) noexcept {
  std::uint64_t m = 0U;
  for (std::uint32_t i = 0; i < p.count; ++i) {
    m |= has(p.t[i].path, tile) && p.t[i].prober != tile ? bit(i) : 0U;
  }
  return m;
}

/** Subject @p x is crossed by a transit and the transits heard of it can vote it failed. */
bool voted(const TransitPlan& p, std::uint32_t x) noexcept {
  return through(p, x) != 0U && can_vote(p, heard(p, x));
}

/** Subject @p s is told apart from subject @p x: their failed switches lose different heard transits. */
bool apart(const TransitPlan& p, std::uint32_t s, std::uint32_t x) noexcept {
  return through(p, s) != 0U && heard(p, s) != heard(p, x);
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

/** What a transit added to the plan must do. */
struct Want {
  std::uint32_t need;            ///< the subject it tests
  bool need_inside;              ///< through @p need (else touching it: an end may be @p need)
  std::uint32_t avoid;           ///< a tile it must not touch (64: none)
  std::uint64_t avoid_ends;      ///< tiles that must be neither its prober nor its target
  std::uint32_t not_prober;      ///< a tile that must not ping it (64: none): the subject, whose reports die with its switch
  udn::LinkSet shrink;           ///< links all transits of the subject cross so far: it must miss one at least
};

int popcount(const udn::LinkSet& l) noexcept { return std::popcount(l.w[0]) + std::popcount(l.w[1]); }

/** The links of @p a that @p b crosses too. */
udn::LinkSet both(const udn::LinkSet& a, const udn::LinkSet& b) noexcept {
  return udn::LinkSet{{a.w[0] & b.w[0], a.w[1] & b.w[1]}};
}

/** The round trip of (a, b) if it is a transit @p w accepts. */
bool acceptable(const Search& s, const Want& w, std::uint32_t a, std::uint32_t b, Transit& t) noexcept {
  const auto ta = static_cast<bsp::TileId>(a);
  const auto tb = static_cast<bsp::TileId>(b);
  t = Transit{ta, tb, udn::path_tiles(*s.map, ta, tb) | udn::path_tiles(*s.map, tb, ta), {}};
  const udn::LinkSet l1 = udn::path_links(*s.map, ta, tb);
  const udn::LinkSet l2 = udn::path_links(*s.map, tb, ta);
  t.links = udn::LinkSet{{l1.w[0] | l2.w[0], l1.w[1] | l2.w[1]}};
  const bool tests = w.need_inside ? has(interior(t), w.need) : has(t.path, w.need);
  const bool shrinks = empty(w.shrink) || popcount(both(w.shrink, t.links)) < popcount(w.shrink);
  return tests && shrinks && !(w.avoid < 64U && has(t.path, w.avoid));
}

/**
 * Adds the transit @p w accepts that leaves the fewest links common to the
 * subject's transits, then crosses the fewest subjects, then the fewest
 * switches, then comes first in (prober, target) order.
 * @return false when there is none or the plan is full.
 */
bool add_best(TransitPlan& p, Search& s, const Want& w) noexcept {
  if (p.count >= kMaxTransits) {
    return false;
  }
  Transit best{};
  int best_common = 129;
  int best_subjects = 65;
  int best_len = 129;
  for (std::uint32_t a = 0; a < s.tiles; ++a) {
    if (!has(s.probers, a) || s.load[a] >= kTransitsPerProber || has(w.avoid_ends, a) || a == w.not_prober) {
      continue;
    }
    for (std::uint32_t b = 0; b < s.tiles; ++b) {
      Transit t{};
      if (a == b || !has(s.probers, b) || has(w.avoid_ends, b) || neighbours(s.map->cols, a, b) || chosen(p, a, b) ||
          !acceptable(s, w, a, b, t)) {
        continue;
      }
      const int nc = empty(w.shrink) ? 0 : popcount(both(w.shrink, t.links));
      const int ns = std::popcount(interior(t) & s.subjects);
      const int len = std::popcount(t.path);
      if (nc < best_common || (nc == best_common && (ns < best_subjects || (ns == best_subjects && len < best_len)))) {
        best = t;
        best_common = nc;
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

/** The tiles at the two ends of link bit @p l (udn::LinkSet: 2t east of t, 2t + 1 south); false off the grid. */
bool link_ends(std::uint32_t cols, std::uint32_t tiles, std::uint32_t l, std::uint32_t& a, std::uint32_t& b) noexcept {
  a = l / 2U;
  b = (l % 2U) == 0U ? a + 1U : a + cols;
  return cols != 0U && b < tiles && !((l % 2U) == 0U && b % cols == 0U);
}

bool crosses(const Transit& t, std::uint32_t l) noexcept { return (t.links.w[l / 64U] >> (l % 64U) & 1U) != 0U; }

/** Transits of @p p across link bit @p l. */
std::uint64_t across_link(const TransitPlan& p, std::uint32_t l) noexcept {
  std::uint64_t m = 0U;
  for (std::uint32_t i = 0; i < p.count && i < kMaxTransits; ++i) {
    m |= crosses(p.t[i], l) ? bit(i) : 0U;
  }
  return m;
}

/** Switches every transit of @p mask passes (all for an empty mask). */
std::uint64_t common_switches(const TransitPlan& p, std::uint64_t mask) noexcept {
  std::uint64_t c = ~std::uint64_t{0};
  for (std::uint32_t i = 0; i < p.count && i < kMaxTransits; ++i) {
    c &= has(mask, i) ? p.t[i].path : ~std::uint64_t{0};
  }
  return c;
}

/** What a transit added for a link must do (plan_transits, links). */
struct LinkWant {
  std::uint32_t link;         ///< it crosses this link...
  std::uint32_t not_link;     ///< ...and not this one (128: no such)
  std::uint64_t avoid_ends;   ///< tiles that must be neither its prober nor its target
  std::uint64_t miss_one_of;  ///< switches of which it must miss one at least (0: none)
};

/** Adds the shortest transit @p w accepts (then the first in (prober, target) order); false if none or full. */
bool add_link_transit(TransitPlan& p, Search& s, const LinkWant& w) noexcept {
  if (p.count >= kMaxTransits) {
    return false;
  }
  Transit best{};
  int best_len = 129;
  for (std::uint32_t a = 0; a < s.tiles; ++a) {
    if (!has(s.probers, a) || s.load[a] >= kTransitsPerProber || has(w.avoid_ends, a)) {
      continue;
    }
    for (std::uint32_t b = 0; b < s.tiles; ++b) {
      if (a == b || !has(s.probers, b) || has(w.avoid_ends, b) || neighbours(s.map->cols, a, b) || chosen(p, a, b)) {
        continue;
      }
      Transit t{};
      // Any transit through a tile tests it: the subject is not the point here.
      if (!acceptable(s, Want{a, false, 64U, 0U, 64U, {}}, a, b, t) || !crosses(t, w.link) ||
          (w.not_link < 128U && crosses(t, w.not_link)) || (w.miss_one_of != 0U && (w.miss_one_of & ~t.path) == 0U)) {
        continue;
      }
      const int len = std::popcount(t.path);
      if (len < best_len) {
        best = t;
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

/**
 * Links no neighbour vote can name (an end that does not probe) that some
 * leg between probers crosses: the ones the transits are to name.
 */
udn::LinkSet links_to_name(const Search& s) noexcept {
  udn::LinkSet m{};
  for (std::uint32_t a = 0; a < s.tiles; ++a) {
    for (std::uint32_t b = 0; b < s.tiles && has(s.probers, a); ++b) {
      if (a != b && has(s.probers, b)) {
        const udn::LinkSet l = udn::path_links(*s.map, static_cast<bsp::TileId>(a), static_cast<bsp::TileId>(b));
        m.w[0] |= l.w[0];
        m.w[1] |= l.w[1];
      }
    }
  }
  for (std::uint32_t l = 0; l < 128U; ++l) {
    std::uint32_t a = 0U;
    std::uint32_t b = 0U;
    if (!link_ends(s.map->cols, s.tiles, l, a, b) || (has(s.probers, a) && has(s.probers, b))) {
      m.w[l / 64U] &= ~(std::uint64_t{1} << (l % 64U));
    }
  }
  return m;
}

/**
 * Plans transits for the links to name: each crossed by two with no end in
 * common and no third switch on all of them, and no two such links lost by
 * the same transits. Adds at most one transit per need and pass, within the
 * probers' loads. @return the links told apart so.
 */
udn::LinkSet plan_links(TransitPlan& p, Search& s) noexcept {
  const udn::LinkSet want = links_to_name(s);
  constexpr std::uint32_t kPasses = 3U;
  for (std::uint32_t pass = 0; pass < kPasses; ++pass) {
    bool added = false;
    for (std::uint32_t l = 0; l < 128U; ++l) {
      std::uint32_t a = 0U;
      std::uint32_t b = 0U;
      if ((want.w[l / 64U] >> (l % 64U) & 1U) == 0U || !link_ends(s.map->cols, s.tiles, l, a, b)) {
        continue;
      }
      const std::uint64_t m = across_link(p, l);
      const std::uint64_t third = common_switches(p, m) & ~bit(a) & ~bit(b);
      if (std::popcount(m) < static_cast<int>(kTransitsPerSpare) || !independent(p, m) || (m != 0U && third != 0U)) {
        const LinkWant w{l, 128U, independent(p, m) ? 0U : first_ends(p, m), m == 0U ? 0U : third};
        added = add_link_transit(p, s, w) || added;
        continue;
      }
      for (std::uint32_t o = 0; o < 128U; ++o) {
        std::uint32_t oa = 0U;
        std::uint32_t ob = 0U;
        if (o != l && link_ends(s.map->cols, s.tiles, o, oa, ob) && across_link(p, o) == m) {
          added = add_link_transit(p, s, LinkWant{l, o, 0U, 0U}) || add_link_transit(p, s, LinkWant{o, l, 0U, 0U}) ||
                  added;
        }
      }
    }
    if (!added) {
      break;
    }
  }
  udn::LinkSet named{};
  for (std::uint32_t l = 0; l < 128U; ++l) {
    std::uint32_t a = 0U;
    std::uint32_t b = 0U;
    if ((want.w[l / 64U] >> (l % 64U) & 1U) == 0U || !link_ends(s.map->cols, s.tiles, l, a, b)) {
      continue;
    }
    const std::uint64_t m = across_link(p, l);
    bool ok = std::popcount(m) >= static_cast<int>(kTransitsPerSpare) && independent(p, m) &&
              (common_switches(p, m) & ~bit(a) & ~bit(b)) == 0U;
    for (std::uint32_t o = 0; o < 128U && ok; ++o) {
      std::uint32_t oa = 0U;
      std::uint32_t ob = 0U;
      ok = o == l || !link_ends(s.map->cols, s.tiles, o, oa, ob) || across_link(p, o) != m;
    }
    named.w[l / 64U] |= ok ? std::uint64_t{1} << (l % 64U) : 0U;
  }
  return named;
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
  // Coverage: every subject crossed by transits that can vote it failed (two
  // with no end in common, no link all of them cross), so no one tile's
  // reports and no one failed link fail it. Each try adds what is missing.
  constexpr std::uint32_t kTries = 3U * kTransitsPerSpare;
  for (std::uint32_t x = 0; x < tiles; ++x) {
    for (std::uint32_t k = 0; k < kTries && has(want, x) && !voted(out, x); ++k) {
      const std::uint64_t m = heard(out, x);
      const Want w{x, through(out, x) == 0U, 64U, independent(out, m) ? 0U : first_ends(out, through(out, x)), x,
                   common_links(out, m)};
      if (!add_best(out, s, w)) {
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
        if (y != x && has(subjects, y) && !apart(out, x, y) && through(out, x) != 0U &&
            add_best(out, s, Want{x, true, y, 0U, x, {}})) {
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
    bool ok = voted(out, x);
    for (std::uint32_t y = 0; y < tiles && ok; ++y) {
      ok = y == x || !has(subjects, y) || apart(out, x, y);
    }
    out.tested |= ok ? bit(x) : 0U;
  }
  out.untested = want & ~out.tested;
  out.links_named = plan_links(out, s);
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

std::uint64_t transits_across(const TransitPlan& plan, const udn::LinkSet& links) noexcept {
  std::uint64_t m = 0U;
  for (std::uint32_t i = 0; i < plan.count && i < kMaxTransits; ++i) {
    m |= meet(plan.t[i].links, links) ? bit(i) : 0U;
  }
  return m;
}

bsp::TileId end_tile_verdict(const TransitPlan& plan, std::uint64_t lost, std::uint64_t candidates,
                             std::uint64_t known_failed, std::uint64_t mute, std::uint64_t reported,
                             std::uint64_t& transits_out) noexcept {
  transits_out = 0U;
  for (std::uint32_t x = 0; x < 64U; ++x) {
    if (!has(candidates, x) || has(known_failed, x)) {
      continue;
    }
    std::uint64_t counted = 0U;
    bool targeted = false;
    std::uint64_t probers = 0U;
    for (std::uint32_t i = 0; i < plan.count && i < kMaxTransits; ++i) {
      const Transit& t = plan.t[i];
      const bool on = t.target == x || has(interior(t), x);
      if (!on || t.prober == x || (t.path & known_failed) != 0U || has(mute, i)) {
        continue;
      }
      counted |= bit(i);
      targeted = targeted || t.target == x;
      probers |= bit(t.prober);
    }
    const bool independent = std::popcount(probers) >= 2 && empty(common_links(plan, counted));
    if (targeted && counted != 0U && (counted & ~lost) == 0U && (independent || has(reported, x))) {
      transits_out = counted;
      return static_cast<bsp::TileId>(x);
    }
  }
  return bsp::kNoTile;
}

bsp::TileId transit_verdict(const TransitPlan& plan, std::uint64_t lost, std::uint64_t subjects,
                            std::uint64_t known_failed, std::uint64_t mute) noexcept {
  // Candidates: subjects with enough telling transits, all lost. A failed
  // switch kills every transit through it, so a switch whose transits are a
  // part of another candidate's is explained by that one: the answer is the
  // one candidate whose lost transits no other candidate's include.
  std::array<std::uint64_t, 64> counted{};
  std::uint64_t candidates = 0U;
  for (std::uint32_t x = 0; x < 64U; ++x) {
    if (!has(subjects, x) || !has(plan.tested, x) || has(known_failed, x)) {
      continue;  // a subject the plan cannot vote on is never failed by transits
    }
    for (std::uint32_t i = 0; i < plan.count && i < kMaxTransits; ++i) {
      const Transit& t = plan.t[i];
      // A transit the subject itself pings tells nothing of its switch: a failed switch silences its
      // own reports too, so such a transit is never reported lost (the I/O tile's switch, tile 9, was
      // never named: four of its nine transits were its own, lost with nobody told).
      const bool tells = has(t.path, x) && t.prober != x && (t.path & known_failed) == 0U && !has(mute, i);
      counted[x] |= tells ? bit(i) : 0U;
    }
    // Voted: two of the lost transits have no end in common and no link is
    // crossed by all, so one faulty prober or target, or one failed link,
    // cannot lose them all.
    const bool fits = (counted[x] & ~lost) == 0U && can_vote(plan, counted[x]);
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

void report_ways(const TransitPlan& plan, const udn::FaultMap& map, bsp::TileId health, std::uint64_t parked,
                 ReportWays& out, bsp::Work& work) noexcept {
  out = ReportWays{};
  out.version = map.version;
  out.parked = parked;
  if (map.cols == 0U || map.cols * map.rows > 64U) {
    return;
  }
  for (std::uint32_t i = 0; i < plan.count && i < kMaxTransits; ++i) {
    const Transit& t = plan.t[i];
    if (t.prober == health || !udn::path_clear(map, t.prober, health)) {
      continue;  // routed through intermediates: taken as heard
    }
    out.route[i] = udn::path_links(map, t.prober, health);
    const bsp::TileId m =
        udn::route_twin_via(map, t.prober, health, udn::path_tiles(map, t.prober, health), out.route[i], parked, work);
    if (m == bsp::kNoTile) {
      out.twin[i] = out.route[i];
      continue;
    }
    const udn::LinkSet l1 = udn::path_links(map, t.prober, m);
    const udn::LinkSet l2 = udn::path_links(map, m, health);
    out.twin[i] = udn::LinkSet{{l1.w[0] | l2.w[0], l1.w[1] | l2.w[1]}};
  }
}

namespace {

/** What the transits say of one link: the ones across it that count, those whose reports it cuts, and whether it fits. */
struct LinkLoss {
  std::uint64_t across = 0U;  ///< transits across it that count
  std::uint64_t cut = 0U;     ///< transits whose reports both cross it: they never come
  std::uint64_t heard_end = 0U;  ///< its end every lost transit shares, heard (see transit_link_verdict)
  bool fits = false;
};

/**
 * Link bit @p l, between tiles @p a and @p b: does its failure explain the
 * lost transits @p lost (those that count: @p counts)? See transit_link_verdict.
 */
LinkLoss link_loss(const TransitPlan& plan, const ReportWays& ways, std::uint32_t l, std::uint32_t a,
                   std::uint32_t b, std::uint64_t counts, std::uint64_t lost, std::uint64_t heard_ends) noexcept {
  LinkLoss r{};
  const std::uint32_t w = l / 64U;
  const std::uint64_t word = std::uint64_t{1} << (l % 64U);
  const std::uint64_t lost_counted = lost & counts;
  std::uint64_t on_all = ~std::uint64_t{0};  // switches every lost transit passes
  std::uint64_t ends_all = ~std::uint64_t{0};  // tiles at an end of every lost transit
  for (std::uint32_t i = 0; i < plan.count && i < kMaxTransits; ++i) {
    r.across |= has(counts, i) && (plan.t[i].links.w[w] & word) != 0U ? bit(i) : 0U;
    r.cut |= (ways.route[i].w[w] & word) != 0U && (ways.twin[i].w[w] & word) != 0U ? bit(i) : 0U;
    on_all &= has(lost_counted, i) ? plan.t[i].path : ~std::uint64_t{0};
    ends_all &= has(lost_counted, i) ? ends(plan.t[i]) : ~std::uint64_t{0};
  }
  // One end of the link at an end of every lost transit, and heard: its own reports come, so its
  // core runs and its switch forwards them; only its way across the link is gone.
  r.heard_end = ends_all & (bit(a) | bit(b)) & heard_ends;
  std::uint64_t routes = 0U;  // switches on heard transits that answer: they route
  for (std::uint32_t i = 0; i < plan.count && i < kMaxTransits; ++i) {
    routes |= has(counts, i) && !has(lost, i) && !has(r.cut, i) ? plan.t[i].path : 0U;
  }
  // It explains every lost transit that counts, and every one across it that can be heard is lost
  // (so every other transit heard through its two switches answers: they route); the lost ones
  // can vote (two with no end in common), and no third switch is on all of them unless a heard
  // transit through it answers (else its failure would lose the same ones).
  r.fits = (lost_counted & ~r.across) == 0U && (r.across & ~r.cut & ~lost_counted) == 0U &&
           std::popcount(lost_counted) >= static_cast<int>(kTransitsPerSpare) &&
           (independent(plan, lost_counted) || r.heard_end != 0U) &&
           (on_all & ~bit(a) & ~bit(b) & ~routes) == 0U;
  return r;
}

}  // namespace

LinkVerdict transit_link_verdict(const TransitPlan& plan, std::uint32_t cols, std::uint32_t rows,
                                 const ReportWays& ways, std::uint64_t lost, std::uint64_t known_failed,
                                 std::uint64_t mute, std::uint64_t heard_ends) noexcept {
  constexpr std::uint32_t kLinkBits = 128U;  // udn::LinkSet: two links per tile
  if (cols == 0U || cols * rows > 64U) {
    return LinkVerdict{};
  }
  std::uint64_t counts = 0U;  // transits whose answer tells about the switches and links they cross
  for (std::uint32_t i = 0; i < plan.count && i < kMaxTransits; ++i) {
    counts |= (plan.t[i].path & known_failed) == 0U && !has(mute, i) ? bit(i) : 0U;
  }
  LinkVerdict found{};
  std::uint64_t found_across = 0U;
  for (std::uint32_t l = 0; l < kLinkBits && (lost & counts) != 0U; ++l) {
    std::uint32_t a = 0U;
    std::uint32_t b = 0U;
    if (!link_ends(cols, cols * rows, l, a, b)) {
      continue;  // off the grid's east or south edge
    }
    const LinkLoss r = link_loss(plan, ways, l, a, b, counts, lost, heard_ends);
    if (!r.fits) {
      continue;
    }
    if (found.count != 0U && r.across != found_across) {
      return LinkVerdict{};  // two links explain the losses differently: neither is told apart
    }
    found.links.w[l / 64U] |= std::uint64_t{1} << (l % 64U);
    ++found.count;
    if (found.count > 1U) {
      found.unsure = 0U;  // a chain: taken out whole
      continue;
    }
    found_across = r.across;
    found.a = static_cast<bsp::TileId>(a);
    found.b = static_cast<bsp::TileId>(b);
    found.transits = static_cast<std::uint32_t>(std::popcount(lost & counts));
    // An end whose switch nothing heard crosses but over the link: its failure would look the same.
    std::uint64_t elsewhere = 0U;
    for (std::uint32_t i = 0; i < plan.count && i < kMaxTransits; ++i) {
      elsewhere |= has(counts, i) && !has(r.across, i) && !has(r.cut, i) ? plan.t[i].path : 0U;
    }
    found.unsure = (bit(a) | bit(b)) & ~elsewhere & ~r.heard_end;  // a heard end's switch forwards
  }
  return found;
}

}  // namespace fdir
