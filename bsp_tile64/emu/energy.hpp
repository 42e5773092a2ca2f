/**
 * @file energy.hpp
 * @brief The board's energy meter: a power model per tile state and the exact cycles each tile spent in each.
 *
 * A tile draws power by its PowerState (board.hpp). The board charges every
 * cycle a tile's clock advances to exactly one state, where the clock
 * advances (tile_runtime.cpp, board.cpp), so for every tile
 *   off + booting + idle + active == tile_time(tile)
 * holds at every cycle, in integers. Joules are computed only when asked, as a
 * double from those integers in a fixed order: the meter is deterministic and
 * it only observes (it changes nothing the tiles see, nor the trace hash).
 *
 * Which state a cycle is charged to (docs/BOARD.md, "Power and energy"):
 * - active: cycles charged by consume() (the core executes), and the cycles of
 *   a stopped tile (hang fault, returned context, failed boot) still marked
 *   kActive: a hung core keeps its clock running;
 * - idle: cycles spent waiting in wait_for_interrupt(), and a stopped or
 *   program-less tile marked kIdle;
 * - booting: from a power-on or reset to the boot entry (the boot delay);
 * - off: switched off (the core draws nothing; its switch still routes).
 *
 * ASSUMPTIONS of the power model (the only published anchor: the TILE64 draws
 * 170-300 mW per tile at 600 MHz - 1 GHz, about 11-19 W for 64 tiles; the
 * Maestro's power is not published). Each is a named constant below:
 * 1. A whole tile (core, caches, switch) running at clock f draws the anchor
 *    band interpolated linearly in f between (600 MHz, 170 mW) and
 *    (1 GHz, 300 mW); outside the band, proportional to f from the nearer end
 *    (dynamic power at a fixed supply). TILE64 at 700 MHz: 202.5 mW.
 * 2. The switch (router, links, their clock) of a tile draws 10 mW in every
 *    state, off included: a switched-off tile's switch still routes the mesh.
 *    It is part of the 202.5 mW, not added to it.
 * 3. An idle core (clock-gated in wait_for_interrupt, caches kept and leaking)
 *    draws 1/4 of its active power.
 * 4. A booting core draws its active power (the boot ROM and cache clearing run).
 * 5. A switched-off core draws nothing.
 * Network traffic, DDR and I/O are not metered: their energy is not in these
 * figures (only the switches' static share is).
 */
#pragma once

#include "bsp_tile64/emu/board.hpp"
#include "bsp_tile64/api/port.hpp"
#include "bsp_tile64/emu/profile.hpp"

#include <cstdint>

namespace bsp {

// ------------------------------------------------------------------ model constants (the assumptions)

/** Anchor, low end: a TILE64 tile draws 170 mW at 600 MHz (published band, docs/BOARD.md). */
inline constexpr std::uint64_t kAnchorLowHz = 600'000'000U;
inline constexpr std::uint64_t kAnchorLowUw = 170'000U;
/** Anchor, high end: 300 mW at 1 GHz. */
inline constexpr std::uint64_t kAnchorHighHz = 1'000'000'000U;
inline constexpr std::uint64_t kAnchorHighUw = 300'000U;
/** ASSUMPTION 2: a tile's switch draws this in every state (5 % of a 700 MHz tile). */
inline constexpr std::uint64_t kSwitchUw = 10'000U;
/** ASSUMPTION 3: an idle core draws kIdleNum / kIdleDen of its active power. */
inline constexpr std::uint64_t kIdleNum = 1U;
inline constexpr std::uint64_t kIdleDen = 4U;

/** What one tile draws in each state, microwatts, at the clock of a chip profile. */
struct PowerModel {
  std::uint64_t clock_hz;          ///< the clock the figures hold for (the profile's)
  std::uint64_t tile_active_uw;    ///< a whole running tile: core, caches and switch (assumption 1)
  std::uint64_t switch_uw;         ///< the switch alone, drawn in every state (assumption 2)
  std::uint64_t core_active_uw;    ///< the core and caches while executing (tile_active_uw - switch_uw)
  std::uint64_t core_idle_uw;      ///< the core in wait_for_interrupt (assumption 3)
  std::uint64_t core_booting_uw;   ///< the core during its boot delay (assumption 4)
  std::uint64_t core_off_uw;       ///< the core switched off (assumption 5: 0)
};

/** Assumption 1: a whole running tile at @p clock_hz, microwatts (0 for a 0 Hz clock). */
constexpr std::uint64_t tile_active_uw_at(std::uint64_t clock_hz) noexcept {
  // Every product below stays under 2^64 for clocks up to 6e13 Hz (3e5 uW * 6e13).
  if (clock_hz < kAnchorLowHz) {
    return kAnchorLowUw * clock_hz / kAnchorLowHz;
  }
  if (clock_hz > kAnchorHighHz) {
    return kAnchorHighUw * clock_hz / kAnchorHighHz;
  }
  return kAnchorLowUw + (kAnchorHighUw - kAnchorLowUw) * (clock_hz - kAnchorLowHz) / (kAnchorHighHz - kAnchorLowHz);
}

/** The power model of a chip profile (its clock), from the constants above. */
constexpr PowerModel power_model_for(const ChipProfile& profile) noexcept {
  const std::uint64_t tile = tile_active_uw_at(profile.clock_hz);
  const std::uint64_t sw = tile > kSwitchUw ? kSwitchUw : tile;
  const std::uint64_t core = tile - sw;
  return PowerModel{profile.clock_hz, tile, sw, core, core * kIdleNum / kIdleDen, core, 0U};
}

static_assert(power_model_for(kTile64).tile_active_uw == 202'500U, "TILE64 at 700 MHz: 202.5 mW per tile");
static_assert(power_model_for(kTile64).core_idle_uw == 48'125U, "idle core: a quarter of 192.5 mW");
static_assert(64U * power_model_for(kTile64).tile_active_uw >= 11'000'000U &&
                  64U * power_model_for(kTile64).tile_active_uw <= 19'000'000U,
              "a fully active TILE64 stays inside the published 11-19 W");

/** Microwatts one tile draws in @p state under @p model: its core's share plus its switch. */
constexpr std::uint64_t tile_uw(const PowerModel& model, PowerState state) noexcept {
  switch (state) {
    case PowerState::kOff:
      return model.core_off_uw + model.switch_uw;
    case PowerState::kBooting:
      return model.core_booting_uw + model.switch_uw;
    case PowerState::kIdle:
      return model.core_idle_uw + model.switch_uw;
    case PowerState::kActive:
      break;
  }
  return model.core_active_uw + model.switch_uw;
}

/** The power model of the board's configured profile. [host] */
[[nodiscard]] PowerModel power_model() noexcept;

// ------------------------------------------------------------------ the meter

/** Cycles one tile spent in each power state (their sum is the tile's time). */
struct StateCycles {
  Cycles off;
  Cycles booting;
  Cycles idle;
  Cycles active;

  [[nodiscard]] constexpr Cycles total() const noexcept { return off + booting + idle + active; }
};

/**
 * Joules of @p cycles under @p model: sum over the states of cycles * power / clock,
 * summed in the order off, booting, idle, active. 0 for a 0 Hz model.
 */
[[nodiscard]] double energy_j(const StateCycles& cycles, const PowerModel& model) noexcept;

/** One tile's meter: its cycles per state since board_init() and their energy under power_model(). */
struct TileEnergy {
  StateCycles cycles;
  double joules;
};

/** The meter of @p tile (all zero for a bad id). Exact at any time the host reads it. [host] */
[[nodiscard]] TileEnergy tile_energy(TileId tile) noexcept;

/** Joules of every tile of the grid since board_init(), summed in tile order. [host] */
[[nodiscard]] double chip_energy_j() noexcept;

/**
 * What @p tile's core is doing as the meter charges it (kOff for a bad id):
 * kOff or kBooting as power_state() says; for a tile that is on, kActive if
 * its latest cycle executed, kIdle if it waited. power_state() can still say
 * kIdle while a context that an interrupt handler taken in
 * wait_for_interrupt() switched to runs (docs/BOARD.md); this says kActive.
 * What the outputs show as a tile's power state. [host]
 */
[[nodiscard]] PowerState metered_state(TileId tile) noexcept;

/** "off", "booting", "idle", "active". */
[[nodiscard]] const char* power_state_name(PowerState state) noexcept;

}  // namespace bsp
