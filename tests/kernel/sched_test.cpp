/**
 * @file sched_test.cpp
 * @brief Scheduling by token traces: priorities, FIFO, cooperative yield, preemption at a tick
 *        inside charged work, periodic releases, deadline and overrun accounting.
 */
#include "tests/kernel/kernel_fixture.hpp"

#include <array>

namespace {

using ktest::kBoot;
using ktest::kStack;
using ktest::kTick;
using ktest::token;
using ktest::tokens;

void say_a(void*) { token('A'); }
void say_b(void*) { token('B'); }
void say_c(void*) { token('C'); }

TEST(Sched, MostUrgentPriorityRunsFirst) {
  static constexpr k::TaskSpec kTable[] = {
      {"a", &say_a, nullptr, 3, 0, 0, kStack, k::Policy::kPreemptive},
      {"b", &say_b, nullptr, 1, 0, 0, kStack, k::Policy::kPreemptive},
      {"c", &say_c, nullptr, 2, 0, 0, kStack, k::Policy::kPreemptive},
  };
  static_assert(k::check_table(kTable) == k::TableError::kOk);
  ktest::run_table(kTable, 5 * kTick);
  EXPECT_EQ(tokens(), "BCA");
}

TEST(Sched, EqualPrioritiesRunInTableOrder) {
  static constexpr k::TaskSpec kTable[] = {
      {"a", &say_a, nullptr, 4, 0, 0, kStack, k::Policy::kPreemptive},
      {"b", &say_b, nullptr, 4, 0, 0, kStack, k::Policy::kPreemptive},
      {"c", &say_c, nullptr, 4, 0, 0, kStack, k::Policy::kPreemptive},
  };
  ktest::run_table(kTable, 5 * kTick);
  EXPECT_EQ(tokens(), "ABC");
}

void yield_loop(void* arg) {
  const char c = *static_cast<const char*>(arg);
  for (int i = 0; i < 3; ++i) {
    token(c);
    bsp::consume(1000);
    k::yield();
  }
}

TEST(Sched, CooperativeTasksAlternateOnYield) {
  static const char kX = 'x';
  static const char kY = 'y';
  static constexpr k::TaskSpec kTable[] = {
      {"x", &yield_loop, const_cast<char*>(&kX), 4, 0, 0, kStack, k::Policy::kCooperative},
      {"y", &yield_loop, const_cast<char*>(&kY), 4, 0, 0, kStack, k::Policy::kCooperative},
  };
  ktest::run_table(kTable, 5 * kTick);
  EXPECT_EQ(tokens(), "xyxyxy");
}

bsp::Cycles g_high_ran_at = 0;
bsp::Cycles g_low_started_at = 0;
bsp::Cycles g_low_done_at = 0;

void high_sleeper(void*) {
  k::sleep(2);
  g_high_ran_at = bsp::now();
  token('H');
}

void low_worker(void*) {
  g_low_started_at = bsp::now();
  token('l');
  bsp::consume(3 * kTick + kTick / 2);  // 3.5 ticks of work, crossing ticks 1, 2 and 3
  g_low_done_at = bsp::now();
  token('L');
}

TEST(Sched, TickInsideChargedWorkPreemptsAtItsExactCycle) {
  static constexpr k::TaskSpec kTable[] = {
      {"high", &high_sleeper, nullptr, 1, 0, 0, kStack, k::Policy::kPreemptive},
      {"low", &low_worker, nullptr, 5, 0, 0, kStack, k::Policy::kPreemptive},
  };
  ktest::run_table(kTable, 10 * kTick);
  EXPECT_EQ(tokens(), "lHL");
  EXPECT_EQ(g_low_started_at, kBoot);
  EXPECT_EQ(g_high_ran_at, kBoot + 2 * kTick) << "woken by the tick at its exact cycle";
  // The preempting task charged nothing, so the low task's work ends on time.
  EXPECT_EQ(g_low_done_at, kBoot + 3 * kTick + kTick / 2);
}

TEST(Sched, CooperativeTaskIsNotPreempted) {
  static constexpr k::TaskSpec kTable[] = {
      {"high", &high_sleeper, nullptr, 1, 0, 0, kStack, k::Policy::kPreemptive},
      {"low", &low_worker, nullptr, 5, 0, 0, kStack, k::Policy::kCooperative},
  };
  ktest::run_table(kTable, 10 * kTick);
  EXPECT_EQ(tokens(), "lLH");
  EXPECT_EQ(g_high_ran_at, g_low_done_at) << "the urgent task runs when the cooperative one ends";
}

std::array<k::Ticks, 8> g_release_ticks{};
std::array<bsp::Cycles, 8> g_release_cycles{};

void periodic_recorder(void*) {
  for (std::size_t i = 0; i < g_release_ticks.size(); ++i) {
    g_release_ticks[i] = k::now_ticks();
    g_release_cycles[i] = bsp::now();
    token('p');
    bsp::consume(kTick / 10);
    ASSERT_EQ(k::wait_period(), k::Status::kOk);
  }
}

TEST(Sched, PeriodicTaskIsReleasedAtExactTicks) {
  static constexpr k::TaskSpec kTable[] = {
      {"periodic", &periodic_recorder, nullptr, 2, 3, 3, kStack, k::Policy::kPreemptive},
  };
  ktest::run_table(kTable, kBoot + 12 * kTick + kTick / 2);  // releases at ticks 0, 3, 6, 9, 12
  EXPECT_EQ(tokens(), "ppppp");
  for (std::size_t i = 0; i < 5; ++i) {
    EXPECT_EQ(g_release_ticks[i], 3 * i) << "job " << i;
    EXPECT_EQ(g_release_cycles[i], kBoot + 3 * i * kTick) << "job " << i;
  }
  const k::TaskStats s = ktest::stats_of("periodic");
  EXPECT_EQ(s.jobs, 5U);  // the fifth job (tick 12) ends at 12.1 ticks
  EXPECT_EQ(s.deadline_misses, 0U);
  EXPECT_EQ(s.overruns, 0U);
}

void overloaded(void*) {
  for (int i = 0; i < 100; ++i) {
    token('o');
    bsp::consume(3 * kTick);  // 3 ticks of work every 2-tick period
    ASSERT_EQ(k::wait_period(), k::Status::kOk);
  }
}

TEST(Sched, OverloadedTaskCountsDeadlineMissesAndSkipsReleases) {
  static constexpr k::TaskSpec kTable[] = {
      {"over", &overloaded, nullptr, 2, 2, 2, kStack, k::Policy::kPreemptive},
  };
  // Jobs start at ticks 0, 4, 8, 12, 16 and end 3 ticks later; each misses its
  // deadline (start + 2) and the release at start + 2 is skipped.
  ktest::run_table(kTable, kBoot + 19 * kTick + kTick / 2);
  EXPECT_EQ(tokens(), "ooooo");
  const k::TaskStats s = ktest::stats_of("over");
  EXPECT_EQ(s.jobs, 5U);
  EXPECT_EQ(s.deadline_misses, 5U);
  EXPECT_EQ(s.overruns, 5U);
}

void spin_forever(void*) {
  for (;;) {
    bsp::consume(kTick / 4);
  }
}

TEST(Sched, SameTablesGiveTheSameTraceHash) {
  static constexpr k::TaskSpec kTable[] = {
      {"high", &high_sleeper, nullptr, 1, 0, 0, kStack, k::Policy::kPreemptive},
      {"low", &low_worker, nullptr, 5, 0, 0, kStack, k::Policy::kPreemptive},
      {"spin", &spin_forever, nullptr, 7, 0, 0, kStack, k::Policy::kPreemptive},
      {"periodic", &periodic_recorder, nullptr, 2, 3, 3, kStack, k::Policy::kPreemptive},
  };
  ktest::run_table(kTable, 30 * kTick);
  const std::uint64_t h1 = bsp::trace_hash();
  ktest::run_table(kTable, 30 * kTick);
  EXPECT_EQ(bsp::trace_hash(), h1);
  EXPECT_GT(bsp::trace_count(), 30U);
}

TEST(TaskTable, CompileTimeChecksRejectBadTables) {
  constexpr k::TaskSpec kDup[] = {
      {"a", &say_a, nullptr, 3, 0, 0, kStack, k::Policy::kPreemptive},
      {"a", &say_b, nullptr, 3, 0, 0, kStack, k::Policy::kPreemptive},
  };
  static_assert(k::check_table(kDup) == k::TableError::kDuplicateName);
  constexpr k::TaskSpec kIdlePrio[] = {{"a", &say_a, nullptr, 31, 0, 0, kStack, k::Policy::kPreemptive}};
  static_assert(k::check_table(kIdlePrio) == k::TableError::kBadPriority);
  constexpr k::TaskSpec kSmall[] = {{"a", &say_a, nullptr, 3, 0, 0, 1024, k::Policy::kPreemptive}};
  static_assert(k::check_table(kSmall) == k::TableError::kStackTooSmall);
  constexpr k::TaskSpec kLate[] = {{"a", &say_a, nullptr, 3, 5, 6, kStack, k::Policy::kPreemptive}};
  static_assert(k::check_table(kLate) == k::TableError::kDeadlineAfterPeriod);
  constexpr k::TaskSpec kHuge[] = {{"a", &say_a, nullptr, 3, 0, 0, 512U * 1024U, k::Policy::kPreemptive}};
  static_assert(k::check_table(kHuge) == k::TableError::kOverBudget);
  constexpr k::TaskSpec kNull[] = {{"a", nullptr, nullptr, 3, 0, 0, kStack, k::Policy::kPreemptive}};
  EXPECT_EQ(k::check_table(kNull), k::TableError::kNullEntry) << "checked at run time, by start()";
  EXPECT_EQ(k::start(kNull, kTick), k::Status::kBadArg);
  // The same checks at run time: start() refuses a bad table.
  EXPECT_EQ(k::check_table(kDup), k::TableError::kDuplicateName);
  EXPECT_EQ(k::check_table(k::TaskTable{}), k::TableError::kEmpty);
}

}  // namespace

namespace {

std::array<bsp::Cycles, 4> g_aligned_at{};
k::Status g_bad_phase = k::Status::kOk;

void aligned_recorder(void*) {
  g_bad_phase = k::align_period(10U);  // not below the period
  ASSERT_EQ(k::align_period(4U), k::Status::kOk);
  ASSERT_EQ(k::wait_period(), k::Status::kOk);
  for (bsp::Cycles& at : g_aligned_at) {
    at = bsp::now();
    bsp::consume(kTick / 10);
    ASSERT_EQ(k::wait_period(), k::Status::kOk);
  }
}

// A periodic task that aligns its releases to a phase of the board's time: the tile booted at
// board tick 1, its releases fall at board ticks 4, 14, 24, 34 (not 1 + 10 i), with no miss.
TEST(Sched, AlignPeriodMovesReleasesToAPhaseOfTheBoardsTime) {
  static constexpr k::TaskSpec kTable[] = {
      {"aligned", &aligned_recorder, nullptr, 2, 10, 10, kStack, k::Policy::kPreemptive},
  };
  ktest::run_table(kTable, 36 * kTick);
  EXPECT_EQ(g_bad_phase, k::Status::kBadState);
  for (std::size_t i = 0; i < g_aligned_at.size(); ++i) {
    EXPECT_EQ(g_aligned_at[i], (4U + 10U * i) * kTick) << "release " << i;
  }
  EXPECT_EQ(ktest::stats_of("aligned").deadline_misses, 0U);
}

}  // namespace

namespace {

void check_in_every_tick(void*) {
  for (;;) {
    k::checkin();
    k::sleep(1U);
  }
}

}  // namespace

// The agent's view of a watched task: its budget and last check-in, the same as in the full stats
// (which also scan the stack for its high water), and out of range refused.
TEST(Sched, TaskWatchGivesTheBudgetAndLastCheckinWithoutTheStackScan) {
  static constexpr k::TaskSpec kTable[] = {
      {"w", &check_in_every_tick, nullptr, 1, 0, 0, kStack, k::Policy::kPreemptive, 7U},
  };
  static_assert(k::check_table(kTable) == k::TableError::kOk);
  ktest::run_table(kTable, 20 * kTick);
  const k::TaskId id = k::find_task(0, "w");
  ASSERT_NE(id, k::kNoTask);
  k::TaskWatch w{};
  ASSERT_EQ(k::task_watch(0, id, &w), k::Status::kOk);
  const k::TaskStats s = ktest::stats_of("w");
  EXPECT_EQ(w.watch_ticks, 7U);
  EXPECT_EQ(w.last_checkin, s.last_checkin);
  EXPECT_GE(w.last_checkin, 17U) << "it checks in every tick";
  EXPECT_EQ(k::task_watch(0, static_cast<k::TaskId>(k::task_count(0)), &w), k::Status::kBadArg);
  EXPECT_EQ(k::task_watch(0, id, nullptr), k::Status::kBadArg);
}

namespace {

std::array<k::Ticks, 3> g_sleeper_ticks{};
std::array<bsp::Cycles, 3> g_sleeper_cycles{};
std::array<k::Ticks, 3> g_slow_ticks{};

void sleep_four(void*) {
  for (std::size_t i = 0; i < g_sleeper_ticks.size(); ++i) {
    k::sleep(4U);
    g_sleeper_ticks[i] = k::now_ticks();
    g_sleeper_cycles[i] = bsp::now();
  }
}

void every_ten(void*) {
  for (std::size_t i = 0; i < g_slow_ticks.size(); ++i) {
    g_slow_ticks[i] = k::now_ticks();
    bsp::consume(kTick / 10);
    ASSERT_EQ(k::wait_period(), k::Status::kOk);
  }
}

k::Semaphore g_soft_sem{0, 1};
k::Ticks g_soft_tick = 0;
bsp::Cycles g_soft_due = 0;

void soft_isr(bsp::TileId /*tile*/) { EXPECT_EQ(g_soft_sem.give_from_isr(), k::Status::kOk); }

void soft_waiter(void*) {
  ASSERT_EQ(k::set_isr(bsp::Irq::kSoft, &soft_isr), k::Status::kOk);
  g_soft_due = bsp::now() + 6 * kTick + kTick / 2;  // inside tick 6, nothing due before it
  ASSERT_EQ(bsp::schedule_event(g_soft_due, 0, bsp::Irq::kSoft, nullptr, 0), bsp::BoardError::kOk);
  ASSERT_EQ(g_soft_sem.take(k::kForever), k::Status::kOk);
  g_soft_tick = k::now_ticks();
  token('S');
  k::sleep(3U);  // from tick 6: woken by the timer at tick 9
  g_soft_tick = k::now_ticks();
  token('T');
}

}  // namespace

// Tickless idle: a tile with nothing ready sleeps to the next tick anything is due (a timeout, a
// release) instead of taking every tick. Releases and wake-ups keep their exact ticks and cycles,
// and only the due ticks interrupt it: 3 wake-ups and 2 releases in 25 ticks, 5 timer interrupts.
TEST(Sched, TicklessIdleTakesOnlyTheTicksWithSomethingDue) {
  static constexpr k::TaskSpec kTable[] = {
      {"sleeper", &sleep_four, nullptr, 3, 0, 0, kStack, k::Policy::kPreemptive},
      {"slow", &every_ten, nullptr, 2, 10, 10, kStack, k::Policy::kPreemptive},
  };
  ktest::run_table(kTable, kBoot + 25 * kTick);
  for (std::size_t i = 0; i < g_sleeper_ticks.size(); ++i) {
    EXPECT_EQ(g_sleeper_ticks[i], 4U * (i + 1U)) << "wake-up " << i;
    EXPECT_EQ(g_sleeper_cycles[i], kBoot + 4U * (i + 1U) * kTick) << "wake-up " << i;
    EXPECT_EQ(g_slow_ticks[i], 10U * i) << "release " << i;
  }
  EXPECT_EQ(bsp::tile_stats(0).irqs_taken, 5U) << "ticks 4, 8, 10, 12, 20; the rest slept through";
  EXPECT_EQ(ktest::stats_of("slow").deadline_misses, 0U);
}

// An interrupt in the middle of a tickless sleep brings the kernel's tick count up to the time,
// and the task it wakes ticks again from there.
TEST(Sched, AnInterruptDuringATicklessSleepCatchesTheTicksUp) {
  static constexpr k::TaskSpec kTable[] = {
      {"soft", &soft_waiter, nullptr, 1, 0, 0, kStack, k::Policy::kPreemptive},
  };
  ktest::run_table(kTable, kBoot + 12 * kTick);
  EXPECT_EQ(tokens(), "ST");
  EXPECT_EQ(g_soft_tick, 9U);
  EXPECT_EQ(bsp::tile_stats(0).irqs_taken, 2U) << "the soft interrupt at 6.5 ticks and the timer at tick 9";
}
