/**
 * @file endpoint_messages.cpp
 * @brief Word layouts of the endpoint's messages (suspect and transit reports, fault map,
 *        role move, parked set): pack, and unpack with every field checked.
 */
#include "udn/endpoint.hpp"

#include "bsp_tile64/api/udn_hw.hpp"

namespace udn {

static_assert(kRouteMaxTiles <= 64U, "tile sets are 64-bit masks");

namespace {

bool is_tile(std::uint32_t t) noexcept { return t < kRouteMaxTiles; }

std::uint64_t join64(std::uint32_t lo, std::uint32_t hi) noexcept {
  return static_cast<std::uint64_t>(lo) | (static_cast<std::uint64_t>(hi) << 32U);
}

/** Tiles of a cols x rows grid as a bit mask (cols * rows <= kRouteMaxTiles). */
std::uint64_t grid_mask(std::uint32_t tiles) noexcept {
  return tiles >= 64U ? ~std::uint64_t{0} : (std::uint64_t{1} << tiles) - 1U;
}

}  // namespace

void pack_suspect(const SuspectReport& r, std::span<std::uint32_t, kSuspectWords> w) noexcept {
  w[0] = kMsgSuspect;
  w[1] = r.reporter;
  w[2] = r.suspect;
}

bool unpack_suspect(std::span<const std::uint32_t> w, SuspectReport& out) noexcept {
  if (!is_message(w, kMsgSuspect, kSuspectWords) || !is_tile(w[1]) || !is_tile(w[2]) || w[1] == w[2]) {
    return false;
  }
  out = SuspectReport{w[1], w[2]};
  return true;
}

void pack_transit(const TransitReport& r, std::span<std::uint32_t, kTransitWords> w) noexcept {
  w[0] = kMsgTransit;
  w[1] = r.prober;
  w[2] = r.target;
  w[3] = r.lost ? 1U : 0U;
}

bool unpack_transit(std::span<const std::uint32_t> w, TransitReport& out) noexcept {
  if (!is_message(w, kMsgTransit, kTransitWords) || !is_tile(w[1]) || !is_tile(w[2]) || w[3] > 1U) {
    return false;
  }
  out = TransitReport{w[1], w[2], w[3] == 1U};
  return true;
}

void pack_fault_map(const FaultMap& map, std::span<std::uint32_t, kFaultMapWords> w) noexcept {
  w[0] = kMsgFaultMap;
  w[1] = map.version;
  w[2] = map.cols;
  w[3] = map.rows;
  w[4] = static_cast<std::uint32_t>(map.failed_tiles);
  w[5] = static_cast<std::uint32_t>(map.failed_tiles >> 32U);
  w[6] = static_cast<std::uint32_t>(map.no_forward);
  w[7] = static_cast<std::uint32_t>(map.no_forward >> 32U);
  for (std::uint32_t i = 0; i < kRouteMaxTiles / 4U; ++i) {
    std::uint32_t word = 0U;
    for (std::uint32_t k = 0; k < 4U; ++k) {
      word |= static_cast<std::uint32_t>(map.failed_links[4U * i + k]) << (8U * k);
    }
    w[8U + i] = word;
  }
}

bool unpack_fault_map(std::span<const std::uint32_t> w, FaultMap& map) noexcept {
  if (!is_message(w, kMsgFaultMap, kFaultMapWords) || w[2] == 0U || w[3] == 0U ||
      w[2] > kRouteMaxTiles || w[3] > kRouteMaxTiles || w[2] * w[3] > kRouteMaxTiles) {
    return false;
  }
  // Every tile the map names is on its grid, and a tile's failed links are its kUdnDirs links.
  const std::uint32_t tiles = w[2] * w[3];
  const std::uint64_t off_grid = ~grid_mask(tiles);
  if ((join64(w[4], w[5]) & off_grid) != 0U || (join64(w[6], w[7]) & off_grid) != 0U) {
    return false;
  }
  constexpr std::uint32_t kDirBits = (1U << bsp::kUdnDirs) - 1U;
  for (std::uint32_t t = 0; t < kRouteMaxTiles; ++t) {
    const std::uint32_t links = (w[8U + t / 4U] >> (8U * (t % 4U))) & 0xFFU;
    if ((links & ~kDirBits) != 0U || (t >= tiles && links != 0U)) {
      return false;
    }
  }
  map = FaultMap{};
  map.version = w[1];
  map.cols = w[2];
  map.rows = w[3];
  map.failed_tiles = join64(w[4], w[5]);
  map.no_forward = join64(w[6], w[7]);
  for (std::uint32_t t = 0; t < kRouteMaxTiles; ++t) {
    map.failed_links[t] = static_cast<std::uint8_t>(w[8U + t / 4U] >> (8U * (t % 4U)));
  }
  return true;
}

void pack_role_move(const RoleMove& m, std::span<std::uint32_t, kRoleMoveWords> w) noexcept {
  w[0] = kMsgRoleMove;
  w[1] = m.slot;
  w[2] = m.tile;
  w[3] = m.version;
}

bool unpack_role_move(std::span<const std::uint32_t> w, RoleMove& out) noexcept {
  if (!is_message(w, kMsgRoleMove, kRoleMoveWords) || w[1] >= kRoleSlots || !is_tile(w[2]) || w[3] == 0U) {
    return false;
  }
  out = RoleMove{w[1], w[2], w[3]};
  return true;
}

void pack_parked(const ParkedSet& p, std::span<std::uint32_t, kParkedWords> w) noexcept {
  w[0] = kMsgParked;
  w[1] = static_cast<std::uint32_t>(p.tiles);
  w[2] = static_cast<std::uint32_t>(p.tiles >> 32U);
  w[3] = p.serial;
}

bool unpack_parked(std::span<const std::uint32_t> w, ParkedSet& out) noexcept {
  if (!is_message(w, kMsgParked, kParkedWords) || w[3] == 0U) {
    return false;
  }
  out = ParkedSet{join64(w[1], w[2]), w[3]};
  return true;
}

}  // namespace udn
