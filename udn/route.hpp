/**
 * @file route.hpp
 * @brief Virtual routing around failed tiles and links: a fault map and per-tile route tables.
 *
 * The hardware routes every packet X-then-Y. A route here is a chain of at
 * most three such legs: direct, or via one or two intermediate tiles that
 * consume the packet and re-inject it (paper Fig. 6). Each leg is a plain
 * X-then-Y path, so the network's deadlock freedom is kept; the intermediate
 * recognises the packet as not its own (decode_packet says kMisdelivered
 * because the protected destination index names another tile) and forwards it
 * with its own table. Every forwarder's remaining route is strictly shorter
 * than the one that sent it there, so forwarding ends (see docs/FT_MESSAGING.md).
 *
 * Failure semantics: a failed tile is avoided as endpoint, intermediate and
 * transit (its switch is not trusted); a failed link is directed (the link
 * leaving a tile in one direction), fault_map_fail_link can fail both ways.
 *
 * Static storage only; all work is bounded by the grid size (at most 64 tiles).
 */
#pragma once

#include "bsp_tile64/api/memory.hpp"
#include "bsp_tile64/api/port.hpp"
#include "bsp_tile64/api/udn_hw.hpp"
#include "bsp_tile64/api/work.hpp"

#include <array>
#include <cstdint>

namespace udn {

inline constexpr std::uint32_t kRouteMaxTiles = 64U;
inline constexpr std::uint32_t kRouteMaxVias = 2U;

enum class RouteError : std::uint8_t {
  kOk,
  kBadGrid,      ///< cols * rows is 0 or above kRouteMaxTiles
  kBadTile,      ///< tile outside the map's grid
  kUnreachable,  ///< no route of at most kRouteMaxVias intermediates avoids the failures
};

/** What is known to be broken. Plain data: copy it to publish a new version. */
struct FaultMap {
  std::uint32_t cols = 0U;
  std::uint32_t rows = 0U;
  std::uint64_t failed_tiles = 0U;                         ///< bit t: tile t (and its switch) failed
  std::array<std::uint8_t, kRouteMaxTiles> failed_links{};  ///< per tile, bit d: link leaving in UdnDir d failed
  /**
   * Bit t: tile t's switch routes, but no software runs there to re-inject a
   * packet (a spare switched off), so it is never chosen as an intermediate.
   */
  std::uint64_t no_forward = 0U;
  std::uint32_t version = 0U;                               ///< incremented by every change
};

/** A fault map is emulated state through and through (bsp::ControlLayout); fault_map_valid() checks its grid. */
inline constexpr std::array kFaultMapFields{
    BSP_CONTROL_STATE(FaultMap, cols),         BSP_CONTROL_STATE(FaultMap, rows),
    BSP_CONTROL_STATE(FaultMap, failed_tiles), BSP_CONTROL_STATE(FaultMap, failed_links),
    BSP_CONTROL_STATE(FaultMap, no_forward),   BSP_CONTROL_STATE(FaultMap, version),
};
inline constexpr bsp::ControlLayout kFaultMapLayout{kFaultMapFields, sizeof(FaultMap), alignof(FaultMap)};
static_assert(bsp::control_layout_ok(kFaultMapLayout), "every member of FaultMap");

/**
 * True if @p map's grid is one fault_map_init() accepts (not empty, at most
 * kRouteMaxTiles tiles). A map in a tile's RAM can take an upset: the route
 * functions treat a map that is not valid as having no tile on its grid.
 */
bool fault_map_valid(const FaultMap& map) noexcept;

/** Empty map for a cols x rows grid. @return kBadGrid for an empty or too large grid. */
RouteError fault_map_init(FaultMap& map, std::uint32_t cols, std::uint32_t rows) noexcept;

/** Marks tile @p t failed. @return kBadTile off the grid. Idempotent (version still moves). */
RouteError fault_map_fail_tile(FaultMap& map, bsp::TileId t) noexcept;

/**
 * Marks the link leaving @p t in @p dir failed, and the opposite direction too
 * when @p both_ways. @return kBadTile if t or its neighbour in dir is off the grid.
 */
RouteError fault_map_fail_link(FaultMap& map, bsp::TileId t, bsp::UdnDir dir, bool both_ways) noexcept;

/** True if the X-then-Y path from @p s to @p d touches no failed tile or link (false off the grid). */
bool path_clear(const FaultMap& map, bsp::TileId s, bsp::TileId d) noexcept;

/** Tiles (bit t) whose switches the X-then-Y path from @p s to @p d passes, both ends included (0 off the grid). */
std::uint64_t path_tiles(const FaultMap& map, bsp::TileId s, bsp::TileId d) noexcept;

/** Mesh hops of the X-then-Y path (Manhattan distance). */
std::uint32_t path_hops(std::uint32_t cols, bsp::TileId s, bsp::TileId d) noexcept;

/**
 * Mesh links as a set, either direction: bit 2t is the link between tile t
 * and its east neighbour, bit 2t + 1 the one to its south neighbour.
 */
struct LinkSet {
  std::array<std::uint64_t, 2> w{};
};

/** LinkSet is emulated state through and through (bsp::ControlLayout). */
inline constexpr std::array kLinkSetFields{BSP_CONTROL_STATE(LinkSet, w)};
inline constexpr bsp::ControlLayout kLinkSetLayout{kLinkSetFields, sizeof(LinkSet), alignof(LinkSet)};
static_assert(bsp::control_layout_ok(kLinkSetLayout), "every member of LinkSet");

/** Links the X-then-Y path from @p s to @p d crosses (empty off the grid). */
LinkSet path_links(const FaultMap& map, bsp::TileId s, bsp::TileId d) noexcept;

/** Links @p map says failed, in either direction. */
LinkSet failed_link_set(const FaultMap& map) noexcept;

/**
 * A second way from @p s to @p d, for copies of a packet sent as well as its
 * route, never instead (a report that must survive one fault on its way): an
 * intermediate m that can forward (not failed, not in the map's no_forward
 * nor @p off), whose two X-then-Y legs are clear in @p map and touch none of
 * the switches in @p avoid_tiles (the route's, its ends left out) and none of
 * the links in @p avoid_links. Fewest hops, then the lowest index. Bounded:
 * one pass over the tiles. [flight: udn/endpoint.cpp; the health tile's
 * verdicts (fdir/transit.cpp) compute the same]
 * @return m, or bsp::kNoTile when there is none.
 */
bsp::TileId route_twin_via(const FaultMap& map, bsp::TileId s, bsp::TileId d, std::uint64_t avoid_tiles,
                           const LinkSet& avoid_links, std::uint64_t off, bsp::Work& work) noexcept;

/** Switches (bit per tile) and links the route of @p t to @p d crosses, leg by leg; 0 and empty if it has none. */
struct RoutePath {
  std::uint64_t tiles = 0U;
  LinkSet links{};
};

/** The route from a table's tile to one destination. */
struct Route {
  RouteError status = RouteError::kUnreachable;
  std::uint8_t hops = 0U;       ///< total mesh hops over all legs
  std::uint8_t via_count = 0U;  ///< 0 direct, 1 or 2 intermediates
  std::array<std::uint8_t, kRouteMaxVias> via{};
};

/** One tile's routes to every tile, built from one version of the fault map. */
struct RouteTable {
  bsp::TileId self = bsp::kNoTile;
  std::uint32_t cols = 0U;
  std::uint32_t tiles = 0U;
  std::uint32_t map_version = 0U;
  std::uint64_t no_forward = 0U;  ///< the map's tiles that cannot be intermediates
  std::array<Route, kRouteMaxTiles> to{};
  /** Scratch of the build: bit b of clear[a] = path_clear(a, b). */
  std::array<std::uint64_t, kRouteMaxTiles> clear{};
};

/**
 * A route table is emulated state through and through (bsp::ControlLayout):
 * route_next_hop refuses a destination or an intermediate off the table's
 * grid, and the messaging node checks the grid before using it (ft_routes_ok).
 */
inline constexpr std::array kRouteFields{BSP_CONTROL_STATE(Route, status), BSP_CONTROL_STATE(Route, hops),
                                         BSP_CONTROL_STATE(Route, via_count), BSP_CONTROL_STATE(Route, via)};
inline constexpr bsp::ControlLayout kRouteLayout{kRouteFields, sizeof(Route), alignof(Route)};
static_assert(bsp::control_layout_ok(kRouteLayout), "every member of Route");
inline constexpr std::array kRouteTableFields{
    BSP_CONTROL_STATE(RouteTable, self),        BSP_CONTROL_STATE(RouteTable, cols),
    BSP_CONTROL_STATE(RouteTable, tiles),       BSP_CONTROL_STATE(RouteTable, map_version),
    BSP_CONTROL_STATE(RouteTable, no_forward),  BSP_CONTROL_NESTED(RouteTable, to, kRouteLayout),
    BSP_CONTROL_STATE(RouteTable, clear),
};
inline constexpr bsp::ControlLayout kRouteTableLayout{kRouteTableFields, sizeof(RouteTable), alignof(RouteTable)};
static_assert(bsp::control_layout_ok(kRouteTableLayout), "every member of RouteTable");

/**
 * Builds @p table for tile @p self: for every destination the route with the
 * fewest total hops; ties go to fewer intermediates, then the lowest first
 * intermediate index, then the lowest second. Bounded: tiles^2 path checks and
 * at most tiles^3 table probes. Charges its work to @p work.
 * @return kBadTile for self off the grid, kBadGrid for a bad map, else kOk
 *         (unreachable destinations are marked in the table, not an error).
 */
RouteError route_table_build(const FaultMap& map, bsp::TileId self, RouteTable& table, bsp::Work& work) noexcept;

/**
 * Where to send a packet for @p dest on its next leg: the first intermediate
 * or the destination itself. @return kUnreachable (next = kNoTile) or kBadTile.
 */
RouteError route_next_hop(const RouteTable& table, bsp::TileId dest, bsp::TileId& next) noexcept;

/** The switches and links of @p table's route to @p dest (the legs through its intermediates). */
RoutePath route_path(const FaultMap& map, const RouteTable& table, bsp::TileId dest) noexcept;

}  // namespace udn
