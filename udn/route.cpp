/**
 * @file route.cpp
 * @brief Fault map, X-then-Y path checks and shortest one- or two-intermediate route tables.
 */
#include "udn/route.hpp"

namespace udn {
namespace {

constexpr std::uint64_t bit_of(std::uint32_t t) noexcept { return std::uint64_t{1} << t; }

constexpr bool grid_ok(std::uint32_t cols, std::uint32_t rows) noexcept {
  // Each side checked first: the product of two upset sides could wrap to a small number.
  return cols != 0U && rows != 0U && cols <= 0xFFU && rows <= 0xFFU && cols * rows <= kRouteMaxTiles;
}

/** On the grid of a valid map (an upset grid has no tile: nothing is indexed by it, nothing divides by 0). */
bool on_grid(const FaultMap& map, bsp::TileId t) noexcept {
  return grid_ok(map.cols, map.rows) && t < map.cols * map.rows;
}

bool link_failed(const FaultMap& map, bsp::TileId from, bsp::UdnDir dir) noexcept {
  return (map.failed_links[from] & (1U << static_cast<unsigned>(dir))) != 0U;
}

/** Neighbour of t in dir, kNoTile off the grid. */
bsp::TileId neighbour(const FaultMap& map, bsp::TileId t, bsp::UdnDir dir) noexcept {
  const std::uint32_t x = t % map.cols;
  const std::uint32_t y = t / map.cols;
  switch (dir) {
    case bsp::UdnDir::kEast:
      return (x + 1U < map.cols) ? t + 1U : bsp::kNoTile;
    case bsp::UdnDir::kWest:
      return (x > 0U) ? t - 1U : bsp::kNoTile;
    case bsp::UdnDir::kNorth:
      return (y > 0U) ? t - map.cols : bsp::kNoTile;
    case bsp::UdnDir::kSouth:
      return (y + 1U < map.rows) ? t + map.cols : bsp::kNoTile;
  }
  return bsp::kNoTile;
}

bsp::UdnDir opposite(bsp::UdnDir d) noexcept {
  switch (d) {
    case bsp::UdnDir::kEast:
      return bsp::UdnDir::kWest;
    case bsp::UdnDir::kWest:
      return bsp::UdnDir::kEast;
    case bsp::UdnDir::kNorth:
      return bsp::UdnDir::kSouth;
    case bsp::UdnDir::kSouth:
      return bsp::UdnDir::kNorth;
  }
  return bsp::UdnDir::kEast;
}

/** A candidate route and its ordering key. */
struct Candidate {
  std::uint32_t hops = 0xFFFF'FFFFU;
  std::uint32_t vias = 0U;
  std::uint32_t m1 = 0U;
  std::uint32_t m2 = 0U;
};

bool better(const Candidate& a, const Candidate& b) noexcept {
  if (a.hops != b.hops) {
    return a.hops < b.hops;
  }
  if (a.vias != b.vias) {
    return a.vias < b.vias;
  }
  return (a.m1 != b.m1) ? a.m1 < b.m1 : a.m2 < b.m2;
}

/** Best route to d with one intermediate (m1 = m, vias = 1); hops stays max if none. */
Candidate best_one_via(const RouteTable& t, bsp::TileId d, bsp::Work& work) noexcept {
  Candidate best{};
  for (std::uint32_t m = 0U; m < t.tiles; ++m) {
    ++work.int_ops;
    if (m == t.self || m == d || (t.no_forward & bit_of(m)) != 0U || (t.clear[t.self] & bit_of(m)) == 0U ||
        (t.clear[m] & bit_of(d)) == 0U) {
      continue;
    }
    const Candidate c{path_hops(t.cols, t.self, m) + path_hops(t.cols, m, d), 1U, m, 0U};
    if (better(c, best)) {
      best = c;
    }
  }
  return best;
}

Candidate best_two_vias(const RouteTable& t, bsp::TileId d, bsp::Work& work) noexcept {
  Candidate best{};
  for (std::uint32_t m1 = 0U; m1 < t.tiles; ++m1) {
    if (m1 == t.self || m1 == d || (t.no_forward & bit_of(m1)) != 0U || (t.clear[t.self] & bit_of(m1)) == 0U) {
      continue;
    }
    const std::uint32_t first = path_hops(t.cols, t.self, m1);
    for (std::uint32_t m2 = 0U; m2 < t.tiles; ++m2) {
      ++work.int_ops;
      if (m2 == m1 || m2 == t.self || m2 == d || (t.no_forward & bit_of(m2)) != 0U || (t.clear[m1] & bit_of(m2)) == 0U ||
          (t.clear[m2] & bit_of(d)) == 0U) {
        continue;
      }
      const Candidate c{first + path_hops(t.cols, m1, m2) + path_hops(t.cols, m2, d), 2U, m1, m2};
      if (better(c, best)) {
        best = c;
      }
    }
  }
  return best;
}

Route route_to(const RouteTable& t, bsp::TileId d, bsp::Work& work) noexcept {
  Route r{};
  if ((t.clear[t.self] & bit_of(d)) != 0U) {
    r.status = RouteError::kOk;
    r.hops = static_cast<std::uint8_t>(path_hops(t.cols, t.self, d));
    return r;
  }
  Candidate c = best_one_via(t, d, work);
  const Candidate c2 = best_two_vias(t, d, work);
  if (better(c2, c)) {
    c = c2;
  }
  if (c.vias == 0U) {
    return r;  // kUnreachable
  }
  r.status = RouteError::kOk;
  r.hops = static_cast<std::uint8_t>(c.hops);
  r.via_count = static_cast<std::uint8_t>(c.vias);
  r.via[0] = static_cast<std::uint8_t>(c.m1);
  r.via[1] = static_cast<std::uint8_t>(c.m2);
  return r;
}

}  // namespace

bool fault_map_valid(const FaultMap& map) noexcept { return grid_ok(map.cols, map.rows); }

RouteError fault_map_init(FaultMap& map, std::uint32_t cols, std::uint32_t rows) noexcept {
  if (!grid_ok(cols, rows)) {
    return RouteError::kBadGrid;
  }
  map = FaultMap{};
  map.cols = cols;
  map.rows = rows;
  return RouteError::kOk;
}

RouteError fault_map_fail_tile(FaultMap& map, bsp::TileId t) noexcept {
  if (!on_grid(map, t)) {
    return RouteError::kBadTile;
  }
  map.failed_tiles |= bit_of(t);
  ++map.version;
  return RouteError::kOk;
}

RouteError fault_map_fail_link(FaultMap& map, bsp::TileId t, bsp::UdnDir dir, bool both_ways) noexcept {
  if (!on_grid(map, t)) {
    return RouteError::kBadTile;
  }
  const bsp::TileId n = neighbour(map, t, dir);
  if (n == bsp::kNoTile) {
    return RouteError::kBadTile;
  }
  map.failed_links[t] = static_cast<std::uint8_t>(map.failed_links[t] | (1U << static_cast<unsigned>(dir)));
  if (both_ways) {
    const auto back = static_cast<unsigned>(opposite(dir));
    map.failed_links[n] = static_cast<std::uint8_t>(map.failed_links[n] | (1U << back));
  }
  ++map.version;
  return RouteError::kOk;
}

std::uint32_t path_hops(std::uint32_t cols, bsp::TileId s, bsp::TileId d) noexcept {
  const std::uint32_t sx = s % cols;
  const std::uint32_t sy = s / cols;
  const std::uint32_t dx = d % cols;
  const std::uint32_t dy = d / cols;
  return ((sx > dx) ? sx - dx : dx - sx) + ((sy > dy) ? sy - dy : dy - sy);
}

namespace {

/** Direction of the next X-then-Y hop from @p t towards @p d (t != d, both on the grid). */
bsp::UdnDir xy_step(const FaultMap& map, bsp::TileId t, bsp::TileId d) noexcept {
  const std::uint32_t x = t % map.cols;
  const std::uint32_t dx = d % map.cols;
  if (x != dx) {
    return (dx > x) ? bsp::UdnDir::kEast : bsp::UdnDir::kWest;
  }
  return (d > t) ? bsp::UdnDir::kSouth : bsp::UdnDir::kNorth;
}

}  // namespace

bool path_clear(const FaultMap& map, bsp::TileId s, bsp::TileId d) noexcept {
  if (!on_grid(map, s) || !on_grid(map, d)) {
    return false;
  }
  bsp::TileId t = s;
  // At most cols + rows steps: each moves one column or row toward d.
  for (std::uint32_t step = 0U; step <= map.cols + map.rows; ++step) {
    if ((map.failed_tiles & bit_of(t)) != 0U) {
      return false;
    }
    if (t == d) {
      return true;
    }
    const bsp::UdnDir dir = xy_step(map, t, d);
    if (link_failed(map, t, dir)) {
      return false;
    }
    t = neighbour(map, t, dir);
  }
  return false;
}

std::uint64_t path_tiles(const FaultMap& map, bsp::TileId s, bsp::TileId d) noexcept {
  if (!on_grid(map, s) || !on_grid(map, d)) {
    return 0U;
  }
  std::uint64_t on_path = 0U;
  bsp::TileId t = s;
  // At most cols + rows steps: each moves one column or row toward d.
  for (std::uint32_t step = 0U; step <= map.cols + map.rows; ++step) {
    on_path |= bit_of(t);
    if (t == d) {
      break;
    }
    const bsp::UdnDir dir = xy_step(map, t, d);
    t = neighbour(map, t, dir);
  }
  return on_path;
}

namespace {

/** Adds the link leaving @p t in @p dir to @p set (its lower or left tile names it). */
void add_link(const FaultMap& map, LinkSet& set, bsp::TileId t, bsp::UdnDir dir) noexcept {
  const bsp::TileId n = neighbour(map, t, dir);
  if (n == bsp::kNoTile) {
    return;
  }
  const bool horizontal = dir == bsp::UdnDir::kEast || dir == bsp::UdnDir::kWest;
  const bsp::TileId low = (n < t) ? n : t;
  const std::uint32_t index = 2U * low + (horizontal ? 0U : 1U);
  set.w[index / 64U] |= std::uint64_t{1} << (index % 64U);
}

}  // namespace

LinkSet path_links(const FaultMap& map, bsp::TileId s, bsp::TileId d) noexcept {
  LinkSet set{};
  if (!on_grid(map, s) || !on_grid(map, d)) {
    return set;
  }
  bsp::TileId t = s;
  // At most cols + rows steps: each moves one column or row toward d.
  for (std::uint32_t step = 0U; step <= map.cols + map.rows && t != d; ++step) {
    const bsp::UdnDir dir = xy_step(map, t, d);
    add_link(map, set, t, dir);
    t = neighbour(map, t, dir);
  }
  return set;
}

LinkSet failed_link_set(const FaultMap& map) noexcept {
  LinkSet set{};
  const std::uint32_t tiles = map.cols * map.rows;
  for (std::uint32_t t = 0U; t < tiles && t < kRouteMaxTiles; ++t) {
    for (const bsp::UdnDir dir : {bsp::UdnDir::kEast, bsp::UdnDir::kWest, bsp::UdnDir::kNorth, bsp::UdnDir::kSouth}) {
      if (link_failed(map, static_cast<bsp::TileId>(t), dir)) {
        add_link(map, set, static_cast<bsp::TileId>(t), dir);
      }
    }
  }
  return set;
}

bsp::TileId route_twin_via(const FaultMap& map, bsp::TileId s, bsp::TileId d, std::uint64_t avoid_tiles,
                           const LinkSet& avoid_links, std::uint64_t off, bsp::Work& work) noexcept {
  const std::uint32_t tiles = map.cols * map.rows;
  if (!on_grid(map, s) || !on_grid(map, d) || s == d || tiles > kRouteMaxTiles) {
    return bsp::kNoTile;
  }
  const std::uint64_t avoid = avoid_tiles & ~bit_of(s) & ~bit_of(d);
  const std::uint64_t cannot = map.failed_tiles | map.no_forward | off | bit_of(s) | bit_of(d);
  bsp::TileId best = bsp::kNoTile;
  std::uint32_t best_hops = 0U;
  for (std::uint32_t m = 0U; m < tiles; ++m) {
    work.int_ops += std::uint64_t{4U} * (map.cols + map.rows);
    if ((cannot & bit_of(m)) != 0U) {
      continue;
    }
    const auto tm = static_cast<bsp::TileId>(m);
    const LinkSet l1 = path_links(map, s, tm);
    const LinkSet l2 = path_links(map, tm, d);
    const bool apart = ((path_tiles(map, s, tm) | path_tiles(map, tm, d)) & avoid) == 0U &&
                       ((l1.w[0] | l2.w[0]) & avoid_links.w[0]) == 0U && ((l1.w[1] | l2.w[1]) & avoid_links.w[1]) == 0U;
    const std::uint32_t hops = path_hops(map.cols, s, tm) + path_hops(map.cols, tm, d);
    if (apart && path_clear(map, s, tm) && path_clear(map, tm, d) && (best == bsp::kNoTile || hops < best_hops)) {
      best = tm;
      best_hops = hops;
    }
  }
  return best;
}

RouteError route_table_build(const FaultMap& map, bsp::TileId self, RouteTable& table, bsp::Work& work) noexcept {
  const std::uint32_t tiles = map.cols * map.rows;
  if (!grid_ok(map.cols, map.rows)) {
    return RouteError::kBadGrid;
  }
  if (self >= tiles) {
    return RouteError::kBadTile;
  }
  table.self = self;
  table.cols = map.cols;
  table.tiles = tiles;
  table.map_version = map.version;
  table.no_forward = map.no_forward;
  for (std::uint32_t a = 0U; a < tiles; ++a) {
    table.clear[a] = 0U;
    for (std::uint32_t b = 0U; b < tiles; ++b) {
      work.int_ops += map.cols + map.rows;
      if (path_clear(map, a, b)) {
        table.clear[a] |= bit_of(b);
      }
    }
  }
  for (std::uint32_t d = 0U; d < kRouteMaxTiles; ++d) {
    table.to[d] = (d < tiles) ? route_to(table, d, work) : Route{};
  }
  return RouteError::kOk;
}

RouteError route_next_hop(const RouteTable& table, bsp::TileId dest, bsp::TileId& next) noexcept {
  next = bsp::kNoTile;
  if (dest >= table.tiles || dest >= kRouteMaxTiles) {
    return RouteError::kBadTile;
  }
  const Route& r = table.to[dest];
  const bsp::TileId hop = (r.via_count == 0U) ? dest : static_cast<bsp::TileId>(r.via[0]);
  // The table lives in the tile's RAM: an upset intermediate off the grid is no route.
  if (r.status != RouteError::kOk || hop >= table.tiles) {
    return RouteError::kUnreachable;
  }
  next = hop;
  return RouteError::kOk;
}

RoutePath route_path(const FaultMap& map, const RouteTable& table, bsp::TileId dest) noexcept {
  RoutePath p{};
  if (dest >= table.tiles || dest >= kRouteMaxTiles || table.self >= table.tiles ||
      table.to[dest].status != RouteError::kOk) {
    return p;
  }
  const Route& r = table.to[dest];
  std::array<bsp::TileId, kRouteMaxVias + 2U> stop{};
  std::uint32_t n = 0U;
  stop[n++] = table.self;
  for (std::uint32_t v = 0U; v < r.via_count && v < kRouteMaxVias; ++v) {
    stop[n++] = r.via[v];
  }
  stop[n++] = dest;
  for (std::uint32_t k = 1U; k < n; ++k) {
    p.tiles |= path_tiles(map, stop[k - 1U], stop[k]);
    const LinkSet l = path_links(map, stop[k - 1U], stop[k]);
    p.links.w[0] |= l.w[0];
    p.links.w[1] |= l.w[1];
  }
  return p;
}

}  // namespace udn
