/**
 * @file kernel_fixture.hpp
 * @brief Test harness: boots the kernel on tile 0 of a TILE64 board and records token traces.
 */
#pragma once

#include "bsp_tile64/emu/board.hpp"
#include "bsp_tile64/emu/trace.hpp"
#include "kernel/kernel.hpp"

#include <gtest/gtest.h>

#include <cstdint>
#include <string>

namespace ktest {

inline constexpr bsp::Cycles kTick = bsp::kTile64.cycles_per_ms();
inline constexpr bsp::Cycles kBoot = kTick;  // default boot delay: 1 ms
inline constexpr std::uint32_t kStack = 16U * 1024U;

/** The token trace tasks append to (static: tasks run on tile stacks). */
inline std::string& tokens() {
  static std::string t;
  return t;
}
inline void token(char c) { tokens().push_back(c); }

/** Boots @p table on tile 0 (the only powered tile) and runs the board for @p run_cycles. */
inline void run_table(k::TaskTable table, bsp::Cycles run_cycles, std::uint64_t seed = 1U) {
  tokens().clear();
  tokens().reserve(4096);  // appends inside tasks must not reallocate mid-test
  bsp::BoardConfig cfg = bsp::default_config(bsp::kTile64);
  cfg.powered_at_start = 1U;
  cfg.monitor_tile = bsp::kNoTile;
  cfg.seed = seed;
  cfg.boot[0] = &k::boot_entry;
  k::set_task_table(0, table, kTick);
  ASSERT_EQ(bsp::board_init(cfg), bsp::BoardError::kOk);
  (void)bsp::run_for(run_cycles);
}

inline k::TaskStats stats_of(const char* name) {
  k::TaskStats s{};
  const k::TaskId id = k::find_task(0, name);
  EXPECT_NE(id, k::kNoTask) << name;
  EXPECT_EQ(k::task_stats(0, id, &s), k::Status::kOk);
  return s;
}

}  // namespace ktest
