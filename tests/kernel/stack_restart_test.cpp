/**
 * @file stack_restart_test.cpp
 * @brief Stack painting shows real use, an overflow is detected and reported, and a tile
 *        restarts from its task table after a reset.
 */
#include "bsp_tile64/api/memory.hpp"
#include "tests/kernel/kernel_fixture.hpp"

#include <cstring>

namespace {

using ktest::kStack;
using ktest::kTick;
using ktest::token;
using ktest::tokens;

[[gnu::noinline]] void use_stack(std::size_t bytes) {
  volatile unsigned char buf[8192];
  for (std::size_t i = 0; i < bytes && i < sizeof buf; ++i) {
    buf[i] = static_cast<unsigned char>(i);
  }
}

void deep(void*) {
  use_stack(8192);
  token('d');
}
void shallow(void*) { token('s'); }

TEST(Stack, HighWaterMarkShowsRealUse) {
  static constexpr k::TaskSpec kTable[] = {
      {"deep", &deep, nullptr, 1, 0, 0, kStack, k::Policy::kPreemptive},
      {"shallow", &shallow, nullptr, 2, 0, 0, kStack, k::Policy::kPreemptive},
  };
  ktest::run_table(kTable, 3 * kTick);
  EXPECT_EQ(tokens(), "ds");
  const k::TaskStats d = ktest::stats_of("deep");
  const k::TaskStats s = ktest::stats_of("shallow");
  EXPECT_GE(d.stack_high_water, 8192U);
  EXPECT_LT(d.stack_high_water, kStack);
  EXPECT_GT(s.stack_high_water, 0U);
  EXPECT_LT(s.stack_high_water, 4096U);
}

bsp::TileId g_fault_tile = bsp::kNoTile;
k::TaskId g_fault_task = k::kNoTask;

void on_fault(bsp::TileId tile, k::TaskId task) {
  g_fault_tile = tile;
  g_fault_task = task;
}

/** Finds a task's stack in tile 0's RAM through the carve records (named after the task). */
std::byte* stack_of(const char* name) {
  const auto base = bsp::region_span(bsp::Region{0}).data();
  for (const bsp::CarveRecord& c : bsp::region_carves(bsp::Region{0})) {
    if (std::strcmp(c.what, name) == 0) {
      return base + c.offset;
    }
  }
  return nullptr;
}

void overflower(void*) {
  token('o');
  // What a runaway frame does: it writes over the bottom of the stack.
  std::byte* bottom = stack_of("over");
  if (bottom != nullptr) {
    std::memset(bottom, 0, 16);
  }
  k::yield();
  token('X');  // must never run again
}

void bystander(void*) {
  for (int i = 0; i < 3; ++i) {
    token('b');
    k::yield();
  }
}

TEST(Stack, OverflowIsDetectedAtTheSwitchAndTheTaskStopped) {
  static constexpr k::TaskSpec kTable[] = {
      {"over", &overflower, nullptr, 4, 0, 0, kStack, k::Policy::kPreemptive},
      {"by", &bystander, nullptr, 4, 0, 0, kStack, k::Policy::kPreemptive},
  };
  k::set_fault_hook(&on_fault);
  ktest::run_table(kTable, 5 * kTick);
  k::set_fault_hook(nullptr);
  EXPECT_EQ(tokens(), "obbb");
  EXPECT_EQ(k::stack_faults(0), 1U);
  EXPECT_EQ(g_fault_tile, 0U);
  EXPECT_EQ(g_fault_task, k::find_task(0, "over"));
  EXPECT_EQ(ktest::stats_of("over").state, 4U) << "kFaulted";
}

void once(void*) { token('r'); }

TEST(Restart, ResetTileRebootsTheKernelFromItsTable) {
  static constexpr k::TaskSpec kTable[] = {
      {"once", &once, nullptr, 2, 0, 0, kStack, k::Policy::kPreemptive},
  };
  ktest::run_table(kTable, 3 * kTick);
  EXPECT_EQ(tokens(), "r");
  ASSERT_EQ(bsp::reset_tile(0), bsp::BoardError::kOk);
  (void)bsp::run_for(4 * kTick);
  EXPECT_EQ(tokens(), "rr");
  EXPECT_EQ(bsp::tile_stats(0).boots, 2U);
  EXPECT_EQ(k::task_count(0), 2U);
}

}  // namespace
