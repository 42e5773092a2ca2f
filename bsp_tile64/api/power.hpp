/**
 * @file power.hpp
 * @brief Power control of the tiles, as a supervisor tile commands it: switch on, switch off,
 *        reset. The board interface fault management uses to retire tiles and wake spares.
 */
#pragma once

#include "bsp_tile64/api/port.hpp"

#include <cstdint>

namespace bsp {

enum class BoardError : std::uint8_t {
  kOk,
  kBadConfig,  ///< see board_init()
  kBadTile,    ///< tile id outside the profile's grid
  kFull,       ///< a fixed-capacity table is full
  kBadState,   ///< operation not allowed in the tile's current state
};

/**
 * Power control. From the host (outside a run) the change is immediate; from a
 * tile it is applied at the next barrier. Switching on a tile that is off boots
 * it after the board's boot delay; switching off discards its contexts, timer
 * and watchdog (its switch still routes); reset discards its contexts, empties
 * its RAM region and boots it again after the boot delay. [host|task]
 */
BoardError power_on(TileId tile) noexcept;
BoardError power_off(TileId tile) noexcept;
BoardError reset_tile(TileId tile) noexcept;

}  // namespace bsp
