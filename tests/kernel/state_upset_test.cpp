/**
 * @file state_upset_test.cpp
 * @brief The kernel's own state in tile RAM takes an upset (issue 54 item 6): each emulated index
 *        or count the scheduler follows is checked at its entry, repaired and traced
 *        (TraceKind::kKernelStateBad), and the tasks go on running.
 *
 * AddressSanitizer cannot see an index that stays inside the tile's RAM, so each case sets the
 * corrupted value itself, between two runs of the board, as an upset lands between two quanta.
 */
#include "tests/kernel/kernel_fixture.hpp"

#include "bsp_tile64/api/memory.hpp"
#include "kernel/detail/tcb.hpp"
#include "kernel/sched.hpp"

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <functional>
#include <string>
#include <utility>
#include <vector>

namespace {

using ktest::kStack;
using ktest::kTick;

void ping(void*) {
  for (;;) {
    ktest::token('p');
    (void)k::wait_period();
  }
}
void pong(void*) {
  for (;;) {
    ktest::token('q');
    (void)k::wait_period();
  }
}

constexpr k::TaskSpec kTable[] = {
    {"ping", &ping, nullptr, 2, 1, 0, kStack, k::Policy::kPreemptive},
    {"pong", &pong, nullptr, 5, 2, 0, kStack, k::Policy::kPreemptive},
};

/** The kernel state carved on tile 0. */
k::detail::KernelState* kernel_state() {
  for (const bsp::CarveRecord& c : bsp::region_carves(bsp::Region{0})) {
    if (c.what != nullptr && std::strcmp(c.what, "kernel state") == 0) {
      EXPECT_EQ(c.layout, &k::detail::kKernelStateLayout) << "the carve declares its layout";
      // NOLINTNEXTLINE(cppcoreguidelines-pro-type-reinterpret-cast): the carve's storage
      return reinterpret_cast<k::detail::KernelState*>(bsp::region_span(bsp::Region{0}).data() + c.offset);
    }
  }
  return nullptr;
}

/** Repairs traced in the tile's kernel ring, as (what, which). */
std::vector<std::pair<std::uint32_t, std::uint32_t>> repairs(const k::detail::KernelState& ks) {
  std::vector<std::pair<std::uint32_t, std::uint32_t>> out;
  const std::uint32_t n = ks.trace_head < k::config::kTraceRing ? ks.trace_head : k::config::kTraceRing;
  for (std::uint32_t i = 0; i < n; ++i) {
    const k::detail::TraceEntry& e = ks.trace_ring[(ks.trace_head - n + i) % k::config::kTraceRing];
    if (e.kind == static_cast<std::uint16_t>(k::TraceKind::kKernelStateBad)) {
      out.emplace_back(e.a, e.b);
    }
  }
  return out;
}

/**
 * Boots the two periodic tasks, runs 10 ticks, applies @p upset, runs 10 more: the kernel must
 * trace the repair @p what and both tasks keep their periods.
 */
void fly_upset(const std::function<void(k::detail::KernelState&)>& upset, std::uint32_t what) {
  ktest::run_table(kTable, 10 * kTick);
  k::detail::KernelState* ks = kernel_state();
  ASSERT_NE(ks, nullptr);
  EXPECT_TRUE(repairs(*ks).empty()) << "a whole state is never repaired";
  upset(*ks);
  ktest::tokens().clear();
  (void)bsp::run_for(10 * kTick);
  const std::string t = ktest::tokens();
  EXPECT_GE(std::count(t.begin(), t.end(), 'p'), 9) << t;
  EXPECT_GE(std::count(t.begin(), t.end(), 'q'), 4) << t;
  bool found = false;
  for (const auto& r : repairs(*ks)) found = found || r.first == what;
  EXPECT_TRUE(found) << "repair " << what << " traced";
  EXPECT_EQ(ks->task_count, 3U);
  EXPECT_EQ(ks->tcbs[0].priority, 2U);
  EXPECT_EQ(ks->tcbs[1].priority, 5U);
}

TEST(KernelState, AnUpsetTaskCountIsTakenFromTheTaskTable) {
  fly_upset([](k::detail::KernelState& ks) { ks.task_count ^= 1U << 9U; }, 1U);
  fly_upset([](k::detail::KernelState& ks) { ks.task_count = 15U; }, 1U);
}

TEST(KernelState, AnUpsetIdleTaskOrTileIsTakenAgain) {
  fly_upset([](k::detail::KernelState& ks) { ks.idle ^= 0x40U; }, 2U);
  fly_upset([](k::detail::KernelState& ks) { ks.tile ^= 0x80U; }, 3U);
}

TEST(KernelState, AnUpsetPriorityIsTakenFromTheTaskTable) {
  // Past the levels (a ready level past the array, a shift past the bitmap) and a wrong level.
  fly_upset([](k::detail::KernelState& ks) { ks.tcbs[1].priority ^= 0x80U; }, 4U);
  fly_upset([](k::detail::KernelState& ks) { ks.tcbs[0].priority ^= 0x08U; }, 4U);
}

TEST(KernelState, AnUpsetTaskIdIsTakenAgain) {
  fly_upset([](k::detail::KernelState& ks) { ks.tcbs[1].id ^= 0x20U; }, 5U);
}

TEST(KernelState, UpsetReadyQueuesAreRebuiltFromTheTasksStates) {
  // The idle task's level (empty while the idle task runs): head or tail past the tasks; a level
  // marked in the bitmap with no task in it.
  constexpr std::uint32_t kIdleLevel = k::config::kNumPriorities - 1U;
  fly_upset([](k::detail::KernelState& ks) { ks.ready[kIdleLevel].head ^= 0x10U; }, 6U);
  fly_upset([](k::detail::KernelState& ks) { ks.ready[kIdleLevel].tail = 0x0EU; }, 6U);
  fly_upset([](k::detail::KernelState& ks) { ks.ready_bitmap ^= 1U << 7U; }, 6U);
}

}  // namespace
