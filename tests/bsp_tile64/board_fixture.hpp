/**
 * @file board_fixture.hpp
 * @brief Shared helpers of the board tests: a small exact-number configuration and trace queries.
 */
#pragma once

#include "bsp_tile64/emu/board.hpp"
#include "bsp_tile64/api/port.hpp"
#include "bsp_tile64/emu/trace.hpp"

#include <gtest/gtest.h>

#include <array>
#include <cstdint>
#include <vector>

namespace board_test {

inline constexpr bsp::Cycles kQuantum = 1000U;
inline constexpr bsp::Cycles kTick = 10000U;
inline constexpr bsp::Cycles kBootDelay = 100U;

/** TILE64 grid with round numbers: quantum 1000, tick 10000, boot delay 100, no tile powered. */
inline bsp::BoardConfig small_config() {
  bsp::BoardConfig c = bsp::default_config(bsp::kTile64);
  c.quantum_cycles = kQuantum;
  c.tick_cycles = kTick;
  c.boot_delay_cycles = kBootDelay;
  c.powered_at_start = 0U;
  c.seed = 42U;
  return c;
}

/** Parks the calling tile for good (interrupts are still taken). */
[[noreturn]] inline void idle_forever() {
  for (;;) {
    bsp::wait_for_interrupt();
  }
}

/** All events of the trace ring of a given kind (and tile, unless kNoTile). */
inline std::vector<bsp::TraceEvent> events_of(bsp::BoardEvent kind, bsp::TileId tile = bsp::kNoTile) {
  std::array<bsp::TraceEvent, bsp::kTraceRingSize> ring{};
  const std::size_t n = bsp::trace_recent(ring);
  std::vector<bsp::TraceEvent> out;
  for (std::size_t i = 0; i < n; ++i) {
    if (ring[i].kind == static_cast<std::uint16_t>(kind) && (tile == bsp::kNoTile || ring[i].tile == tile)) {
      out.push_back(ring[i]);
    }
  }
  return out;
}

}  // namespace board_test
