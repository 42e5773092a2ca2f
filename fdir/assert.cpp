/**
 * @file assert.cpp
 * @brief Failed flight checks: event and recovery request.
 */
#include "fdir/assert.hpp"

#include "bsp_tile64/api/memory.hpp"
#include "fdir/event_log.hpp"

#include <array>

namespace fdir {
namespace {

/** Per tile: failed checks not yet taken care of (a hardware-style status register, read by the health layer). */
std::array<std::uint32_t, bsp::kMaxTiles> g_requests{};

}  // namespace

void assert_failed(std::uint32_t id, std::uint32_t line) noexcept {
  report(EventId::kAssertFailed, id, line);
  const bsp::TileId t = bsp::current_tile();
  if (t < bsp::kMaxTiles) {
    ++g_requests[t];
  }
}

std::uint32_t recovery_requested(bsp::TileId tile) noexcept { return tile < bsp::kMaxTiles ? g_requests[tile] : 0U; }

void recovery_clear(bsp::TileId tile) noexcept {
  if (tile < bsp::kMaxTiles) {
    g_requests[tile] = 0U;
  }
}

}  // namespace fdir
