/**
 * @file fdir_fixture.hpp
 * @brief Runs a test body as a task on tile 0 of a fresh board with the flight event log carved.
 */
#pragma once

#include "bsp_tile64/emu/board.hpp"
#include "bsp_tile64/api/memory.hpp"
#include "fdir/event_log.hpp"
#include "kernel/kernel.hpp"

#include <gtest/gtest.h>

#include <cstdint>
#include <vector>

namespace fdir_test {

inline constexpr bsp::Cycles kTick = bsp::kTile64.cycles_per_ms();

/** The body the task runs once (a plain function: it runs on the tile's stack). */
inline void (*g_body)() = nullptr;
/** Set when the body has returned: a body that blocks or hangs never sets it. */
inline bool g_body_returned = false;

inline void body_task(void* /*arg*/) {
  if (g_body != nullptr) {
    g_body();
  }
  g_body_returned = true;
  for (;;) {
    k::sleep(1000);
  }
}

inline constexpr k::TaskSpec kBodyTable[] = {
    {"body", &body_task, nullptr, 1, 0, 0, 32U * 1024U, k::Policy::kPreemptive},
};

/**
 * Boots tile 0 alone, carves the event log, runs @p body on the tile for @p ticks emulated ticks, and
 * fails the test unless the body returned within them: assertions that sit inside a body that never ran
 * to its end would otherwise pass unseen.
 */
inline void run_on_tile0(void (*body)(), std::uint32_t ticks = 10U) {
  g_body = body;
  g_body_returned = false;
  bsp::BoardConfig cfg = bsp::default_config(bsp::kTile64);
  cfg.powered_at_start = 1U;
  cfg.monitor_tile = bsp::kNoTile;
  cfg.boot[0] = &k::boot_entry;
  k::set_task_table(0, kBodyTable, kTick);
  ASSERT_EQ(bsp::region_reset(bsp::Region{bsp::Region::kDdr}), bsp::MemError::kOk);
  ASSERT_EQ(bsp::board_init(cfg), bsp::BoardError::kOk);
  ASSERT_EQ(fdir::event_log_init(), fdir::LogError::kOk);
  (void)bsp::run_for(ticks * kTick);
  EXPECT_TRUE(g_body_returned) << "the test's body did not run to its end within " << ticks << " ticks on tile 0";
}

/** The events tile @p tile still holds, oldest first. */
inline std::vector<fdir::Event> events_of(bsp::TileId tile) {
  std::vector<fdir::Event> out;
  const std::uint64_t n = fdir::event_log_written(tile);
  for (std::uint64_t i = 0; i < n; ++i) {
    fdir::Event e{};
    if (fdir::event_log_read(tile, i, &e)) {
      out.push_back(e);
    }
  }
  return out;
}

}  // namespace fdir_test
