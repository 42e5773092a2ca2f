/**
 * @file event_log.cpp
 * @brief Per-tile event rings in shared DDR.
 */
#include "fdir/event_log.hpp"

#include "bsp_tile64/api/memory.hpp"

#include <array>
#include <new>

namespace fdir {
namespace {

struct Ring {
  std::uint64_t written;
  std::array<Event, kRingEvents> ev;
};

/** The carve in DDR, one ring per tile of the profile; nullptr before init. */
Ring* g_rings = nullptr;
bsp::TileId g_tiles = 0U;

/** True while the rings are still the DDR carve made by init (a board re-init drops every carve). */
bool rings_live() noexcept {
  if (g_rings == nullptr) {
    return false;
  }
  const bsp::Region ddr{bsp::Region::kDdr};
  const std::byte* base = bsp::region_span(ddr).data();
  for (const bsp::CarveRecord& c : bsp::region_carves(ddr)) {
    if (static_cast<const void*>(base + c.offset) == static_cast<const void*>(g_rings)) {
      return true;
    }
  }
  return false;
}

}  // namespace

LogError event_log_init() noexcept {
  const bsp::TileId tiles = bsp::tile_count();
  if (tiles == 0U || tiles > bsp::kMaxTiles) {
    return LogError::kBadTile;
  }
  bsp::MemError err = bsp::MemError::kOk;
  auto* rings = bsp::carve_array<Ring>(bsp::Region{bsp::Region::kDdr}, tiles, "fdir_events", &err);
  if (err != bsp::MemError::kOk || rings == nullptr) {
    return LogError::kNoRoom;
  }
  for (bsp::TileId t = 0; t < tiles; ++t) {
    ::new (&rings[t]) Ring{};
  }
  g_rings = rings;
  g_tiles = tiles;
  return LogError::kOk;
}

void report(const EventInfo& info, std::uint32_t subject, std::uint32_t cause, std::uint32_t a,
            std::uint32_t b) noexcept {
  const bsp::TileId tile = bsp::current_tile();
  bsp::trace(static_cast<std::uint16_t>(bsp::kTraceFdirBase + (static_cast<std::uint16_t>(info.id) & 0x0FFFU)),
             (static_cast<std::uint64_t>(subject) << 32U) | cause, (static_cast<std::uint64_t>(a) << 32U) | b);
  if (tile >= g_tiles || !rings_live()) {
    return;  // no log carved (unit tests of a layer): the trace still has it
  }
  Ring& r = g_rings[tile];
  r.ev[r.written % kRingEvents] = Event{bsp::now(), info.id, info.severity, info.steps, tile, subject, cause, a, b};
  ++r.written;
}

void report(EventId id, std::uint32_t subject, std::uint32_t cause, std::uint32_t a, std::uint32_t b) noexcept {
  const EventInfo* info = event_info(id);
  if (info == nullptr) {  // a programming error reported as one, with the bad id kept
    report_unknown(id, subject, a, b);
    return;
  }
  report(*info, subject, cause, a, b);
}

void report_unknown(EventId id, std::uint32_t subject, std::uint32_t a, std::uint32_t b) noexcept {
  const EventInfo* info = event_info(EventId::kAssertFailed);
  if (info != nullptr) {
    report(*info, subject, static_cast<std::uint32_t>(id), a, b);
  }
}

std::uint64_t event_log_written(bsp::TileId tile) noexcept {
  return (tile < g_tiles && rings_live()) ? g_rings[tile].written : 0U;
}

bool event_log_read(bsp::TileId tile, std::uint64_t index, Event* out) noexcept {
  if (out == nullptr || tile >= g_tiles || !rings_live()) {
    return false;
  }
  const Ring& r = g_rings[tile];
  if (index >= r.written || r.written - index > kRingEvents) {
    return false;
  }
  *out = r.ev[index % kRingEvents];
  return true;
}

}  // namespace fdir
