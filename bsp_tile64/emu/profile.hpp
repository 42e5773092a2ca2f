/**
 * @file profile.hpp
 * @brief Chip profiles (TILE64, Maestro) and their cost tables, as compile-time configuration.
 *
 * A profile is everything the board needs to know about a chip: the grid, the
 * clock and the cost of each kind of counted work. The reasoning behind every
 * number in the cost tables is in docs/COST_MODEL.md; change both together.
 */
#pragma once

#include "bsp_tile64/api/memory.hpp"

#include <array>
#include <cstdint>
#include <string_view>

namespace bsp {

/** Costs are kept in sixteenths of a cycle so a 2-ALU core can charge half a cycle per op. */
inline constexpr std::uint64_t kCostScale = 16U;

/** Cycles per unit of counted work, in 1/kCostScale cycle units. */
struct CostTable {
  std::uint64_t int_op_x16;    ///< integer ALU operation
  std::uint64_t int_mac_x16;   ///< integer multiply-accumulate
  std::uint64_t flop_x16;      ///< floating-point add/mul (soft-float without an FPU)
  std::uint64_t fdiv_x16;      ///< floating-point divide or square root
  std::uint64_t mem_word_x16;  ///< 32-bit word moved beyond the register file
  std::uint64_t hop_x16;       ///< one network hop (router traversal)
};

/** A chip: grid, clock, FPU and cost table. */
struct ChipProfile {
  const char* name;
  std::uint32_t cols;
  std::uint32_t rows;
  std::uint64_t clock_hz;
  bool has_fpu;
  CostTable cost;

  [[nodiscard]] constexpr std::uint32_t tiles() const noexcept { return cols * rows; }
  /** Cycles in @p ms milliseconds at this clock. */
  [[nodiscard]] constexpr std::uint64_t cycles_per_ms(std::uint64_t ms = 1U) const noexcept {
    return clock_hz / 1000U * ms;
  }
};

/** TILE64: 8x8, 700 MHz, 3-issue VLIW with 2 integer ALUs, no FPU. */
inline constexpr ChipProfile kTile64{
    "tile64", 8U, 8U, 700'000'000U, false,
    CostTable{
        kCostScale / 2U,  // 0.5 cycle: two integer ALUs issue per bundle
        kCostScale,       // 1 cycle: pipelined 32-bit multiply (mul-accumulate forms)
        48U * kCostScale, // 48 cycles: IEEE double add/mul in software on a 32-bit integer core
        200U * kCostScale,// 200 cycles: software divide / square root (iterative)
        2U * kCostScale,  // 2 cycles: L1 hit with the L2 (64 KiB) and DDR misses amortized
        kCostScale,       // 1 cycle per hop on the dynamic networks
    }};

/** Maestro: 7x7, 342 MHz, radiation-hardened TILE64 derivative with an FPU per tile. */
inline constexpr ChipProfile kMaestro{
    "maestro", 7U, 7U, 342'000'000U, true,
    CostTable{
        kCostScale / 2U,  // 0.5 cycle: same integer core as TILE64
        kCostScale,       // 1 cycle
        3U * kCostScale,  // 3 cycles: 5.7 GFLOPS / 49 tiles / 342 MHz = 0.34 flop/cycle measured
        20U * kCostScale, // 20 cycles: non-pipelined FPU divide / square root
        2U * kCostScale,  // 2 cycles
        kCostScale,       // 1 cycle per hop
    }};

/** Every chip profile, by name. */
inline constexpr std::array<const ChipProfile*, 2> kProfiles{&kTile64, &kMaestro};

/** The profile named @p name ("tile64", "maestro"); nullptr for none. */
constexpr const ChipProfile* find_profile(std::string_view name) noexcept {
  for (const ChipProfile* p : kProfiles) {
    if (name == p->name) {
      return p;
    }
  }
  return nullptr;
}

static_assert(kTile64.tiles() <= kMaxTiles, "TILE64 grid exceeds the memory map");
static_assert(kMaestro.tiles() <= kMaxTiles, "Maestro grid exceeds the memory map");
static_assert(kMaxTiles <= 64U, "watchdog and fault masks are 64-bit tile masks");
static_assert(kTile64.clock_hz % 1000U == 0U && kMaestro.clock_hz % 1000U == 0U, "whole cycles per ms");

}  // namespace bsp
