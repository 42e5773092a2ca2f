/**
 * @file port_test.cpp
 * @brief The context-switch port and interrupt semantics of port.hpp: switches, preemption, masking, halts.
 */
#include "bsp_tile64/api/port.hpp"

#include "board_fixture.hpp"
#include "bsp_tile64/emu/board.hpp"
#include "bsp_tile64/api/memory.hpp"
#include "bsp_tile64/emu/stack_paint.hpp"
#include "bsp_tile64/emu/trace.hpp"

#include <gtest/gtest.h>

#include <array>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace {

using board_test::idle_forever;
using board_test::small_config;
using bsp::Cycles;
using bsp::TileId;

constexpr std::size_t kStackBytes = std::size_t{64U} * 1024U;
alignas(16) std::array<std::byte, kStackBytes> g_host_stack{};
bsp::Context g_main{};
bsp::Context g_fiber{};
std::string g_tokens;

void fiber_entry(void* arg) {
  g_tokens += *static_cast<const char*>(arg);
  bsp::context_switch(g_fiber, g_main);
  g_tokens += 'C';
  bsp::context_switch(g_fiber, g_main);
  g_tokens += '!';  // never reached: the test does not resume it a third time
}

TEST(Port, ContextSwitchPingPongsBetweenHostAndAFiberOnItsOwnStack) {
  g_tokens.clear();
  bsp::stack_paint(g_host_stack);
  static const char kArg = 'A';
  bsp::context_init(g_fiber, g_host_stack.data(), kStackBytes, fiber_entry, const_cast<char*>(&kArg));  // NOLINT(cppcoreguidelines-pro-type-const-cast): entry takes void*, reads only
  g_tokens += '0';
  bsp::context_switch(g_main, g_fiber);
  g_tokens += 'B';
  bsp::context_switch(g_main, g_fiber);
  g_tokens += 'D';
  EXPECT_EQ(g_tokens, "0ABCD");
  const std::size_t used = bsp::stack_high_water(g_host_stack);
  EXPECT_GT(used, 64U);
  EXPECT_LT(used, kStackBytes);
}

TEST(Port, HostCallsOutsideATileAreHarmless) {
  ASSERT_EQ(bsp::board_init(small_config()), bsp::BoardError::kOk);
  EXPECT_EQ(bsp::current_tile(), bsp::kNoTile);
  bsp::consume(1000U);
  bsp::wait_for_interrupt();
  EXPECT_EQ(bsp::now(), 0U);
  EXPECT_FALSE(bsp::mask_irqs(true));
  std::uint32_t v = 5U;
  EXPECT_FALSE(bsp::publish_filter(1U, &v, sizeof v));
}

// ---------------------------------------------------------------- preemption

std::vector<std::pair<std::string, Cycles>> g_log;
std::array<bsp::Context, 2> g_save{};  // [0]: A (boot context), [1]: B
bsp::Context g_ctx_b{};
constexpr std::size_t kTaskStackBytes = std::size_t{16U} * 1024U;

void task_b(void* /*arg*/) {
  g_log.emplace_back("B start", bsp::now());
  EXPECT_FALSE(bsp::mask_irqs(false)) << "a new context starts with interrupts enabled";
  bsp::consume(300U);
  g_log.emplace_back("B done", bsp::now());
  bsp::context_switch(g_save[1], g_save[0]);
  idle_forever();
}

void preempt_handler(TileId /*tile*/, bsp::Irq irq) {
  g_log.emplace_back(irq == bsp::Irq::kTimer ? "irq" : "other", bsp::now());
  const bool was_masked = bsp::mask_irqs(true);
  g_log.emplace_back(was_masked ? "masked" : "unmasked", bsp::now());
  bsp::timer_start(0U);
  bsp::context_switch(g_save[0], g_ctx_b);  // preempt A: B runs now
  g_log.emplace_back("back in handler", bsp::now());
}

void boot_preempt(TileId tile) {
  bsp::set_irq_handler(tile, preempt_handler);
  const bsp::Carve c = bsp::carve(bsp::Region{tile}, kTaskStackBytes, 16U, "task B stack");
  ASSERT_EQ(c.error, bsp::MemError::kOk);
  bsp::context_init(g_ctx_b, c.ptr, kTaskStackBytes, task_b, nullptr);
  g_log.emplace_back("A start", bsp::now());
  bsp::timer_start(1500U);
  bsp::consume(5000U);
  g_log.emplace_back("A done", bsp::now());
  idle_forever();
}

TEST(Port, InterruptInsideConsumeIsTakenAtItsCycleAndAHandlerSwitchPreempts) {
  g_log.clear();
  bsp::BoardConfig c = small_config();
  c.powered_at_start = 1U;
  c.boot[0] = boot_preempt;
  ASSERT_EQ(bsp::board_init(c), bsp::BoardError::kOk);
  bsp::run_for(10'000U);
  // A charges 1500 cycles (100..1600), is preempted, B charges 300 (1600..1900),
  // then A resumes inside its handler and charges its remaining 3500 (1900..5400).
  const std::vector<std::pair<std::string, Cycles>> expected{
      {"A start", 100U}, {"irq", 1600U},  {"masked", 1600U}, {"B start", 1600U},
      {"B done", 1900U}, {"back in handler", 1900U}, {"A done", 5400U}};
  EXPECT_EQ(g_log, expected);
  EXPECT_EQ(bsp::tile_stats(0).active_cycles, 5300U);
}

// ---------------------------------------------------------------- masking

std::vector<Cycles> g_irq_at;

void count_irq(TileId /*tile*/, bsp::Irq /*irq*/) { g_irq_at.push_back(bsp::now()); }

void boot_masked(TileId tile) {
  bsp::set_irq_handler(tile, count_irq);
  const bool before = bsp::mask_irqs(true);
  EXPECT_FALSE(before);
  bsp::timer_start(200U);  // due at 300, while masked
  bsp::consume(500U);      // 100..600: the interrupt stays pending
  g_irq_at.push_back(1'000'000U + bsp::now());
  static_cast<void>(bsp::mask_irqs(false));  // taken here, at 600
  bsp::timer_start(0U);
  idle_forever();
}

TEST(Port, MaskedInterruptStaysPendingAndIsTakenAtTheUnmask) {
  g_irq_at.clear();
  bsp::BoardConfig c = small_config();
  c.powered_at_start = 1U;
  c.boot[0] = boot_masked;
  ASSERT_EQ(bsp::board_init(c), bsp::BoardError::kOk);
  bsp::run_for(2000U);
  const std::vector<Cycles> expected{1'000'600U, 600U};
  EXPECT_EQ(g_irq_at, expected);
}

// ---------------------------------------------------------------- halts

void boot_returns(TileId /*tile*/) { bsp::consume(10U); }

TEST(Port, ABootEntryThatReturnsStopsTheTileAndIsTraced) {
  bsp::BoardConfig c = small_config();
  c.powered_at_start = 0b100U;
  c.boot[2] = boot_returns;
  ASSERT_EQ(bsp::board_init(c), bsp::BoardError::kOk);
  bsp::run_for(3000U);
  EXPECT_TRUE(bsp::tile_stopped(2));
  const auto halts = board_test::events_of(bsp::BoardEvent::kHalt, 2U);
  ASSERT_EQ(halts.size(), 1U);
  EXPECT_EQ(halts[0].time, 110U);
  EXPECT_EQ(bsp::tile_time(2), 3000U);
}

}  // namespace
