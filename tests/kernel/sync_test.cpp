/**
 * @file sync_test.cpp
 * @brief Queues, semaphores and event flags block and time out at the right tick; pools
 *        report exhaustion; all without allocating after init.
 */
#include "tests/kernel/kernel_fixture.hpp"
#include "tests/support/heap_probe.hpp"

namespace {

using ktest::kBoot;
using ktest::kStack;
using ktest::kTick;
using ktest::token;
using ktest::tokens;

k::Queue<std::uint32_t, 2> g_queue;
k::Semaphore g_sem{0, 4};
k::EventFlags g_flags;
k::Ticks g_timeout_tick = 0;
k::Status g_status = k::Status::kOk;
std::uint32_t g_got = 0;

void receiver_times_out(void*) {
  std::uint32_t v = 0;
  g_status = g_queue.receive(v, k::Timeout{5});
  g_timeout_tick = k::now_ticks();
  token(g_status == k::Status::kTimeout ? 'T' : '?');
}

TEST(Queue, ReceiveOnAnEmptyQueueTimesOutAtTheRightTick) {
  static constexpr k::TaskSpec kTable[] = {
      {"rx", &receiver_times_out, nullptr, 2, 0, 0, kStack, k::Policy::kPreemptive},
  };
  ktest::run_table(kTable, 10 * kTick);
  EXPECT_EQ(tokens(), "T");
  EXPECT_EQ(g_timeout_tick, 5U);
}

void consumer(void*) {
  for (int i = 0; i < 3; ++i) {
    std::uint32_t v = 0;
    if (g_queue.receive(v, k::kForever) == k::Status::kOk) {
      token(static_cast<char>('0' + v));
    }
  }
}

void producer(void*) {
  k::sleep(3);
  token('s');
  for (std::uint32_t v = 1; v <= 3; ++v) {
    EXPECT_EQ(g_queue.send(v, k::kForever), k::Status::kOk);
  }
  token('e');
}

TEST(Queue, MoreUrgentReceiverTakesEachItemAsItIsSent) {
  static constexpr k::TaskSpec kTable[] = {
      {"rx", &consumer, nullptr, 1, 0, 0, kStack, k::Policy::kPreemptive},
      {"tx", &producer, nullptr, 3, 0, 0, kStack, k::Policy::kPreemptive},
  };
  ktest::run_table(kTable, 10 * kTick);
  EXPECT_EQ(tokens(), "s123e");
}

TEST(Queue, FullQueueBlocksTheSenderUntilTheReceiverDrains) {
  // Producer more urgent: fills 2 slots and blocks on the third. The receive
  // that frees a slot readies the more urgent sender, which preempts the
  // receiver inside receive(): the sender finishes before '1' is printed.
  static constexpr k::TaskSpec kTable[] = {
      {"tx", &producer, nullptr, 1, 0, 0, kStack, k::Policy::kPreemptive},
      {"rx", &consumer, nullptr, 3, 0, 0, kStack, k::Policy::kPreemptive},
  };
  ktest::run_table(kTable, 10 * kTick);
  EXPECT_EQ(tokens(), "se123");
}

void sem_waiter(void*) {
  g_status = g_sem.take(k::Timeout{4});
  g_timeout_tick = k::now_ticks();
  token(g_status == k::Status::kTimeout ? 'T' : 'G');
  g_status = g_sem.take(k::Timeout{10});
  token(g_status == k::Status::kOk ? 'G' : 'T');
  EXPECT_EQ(k::now_ticks(), 7U);
  EXPECT_EQ(g_sem.take(k::kNoWait), k::Status::kWouldBlock);
}

void sem_giver(void*) {
  k::sleep(7);
  token('g');
  EXPECT_EQ(g_sem.give(), k::Status::kOk);
  token('d');
}

TEST(Semaphore, TakeTimesOutAtTheRightTickAndAGiveWakesTheWaiter) {
  static constexpr k::TaskSpec kTable[] = {
      {"wait", &sem_waiter, nullptr, 1, 0, 0, kStack, k::Policy::kPreemptive},
      {"give", &sem_giver, nullptr, 3, 0, 0, kStack, k::Policy::kPreemptive},
  };
  ktest::run_table(kTable, 12 * kTick);
  EXPECT_EQ(tokens(), "TgGd");
  EXPECT_EQ(g_timeout_tick, 4U);
  EXPECT_EQ(g_sem.count(), 0U);
}

TEST(Semaphore, GiveAtTheMaximumIsRefused) {
  k::Semaphore s{3, 3};
  EXPECT_EQ(s.give(), k::Status::kExhausted);
  EXPECT_EQ(s.count(), 3U);
}

void flag_waiter(void*) {
  g_status = g_flags.wait(0x3U, k::WaitMode::kAll, true, k::Timeout{20}, &g_got);
  g_timeout_tick = k::now_ticks();
  token(g_status == k::Status::kOk ? 'W' : 'T');
}

void flag_setter(void*) {
  k::sleep(2);
  g_flags.set(0x1U);
  token('1');
  k::sleep(2);
  g_flags.set(0x2U);
  token('2');
}

TEST(EventFlags, WaitAllWakesOnlyWhenEveryBitIsSetAndClears) {
  static constexpr k::TaskSpec kTable[] = {
      {"wait", &flag_waiter, nullptr, 1, 0, 0, kStack, k::Policy::kPreemptive},
      {"set", &flag_setter, nullptr, 3, 0, 0, kStack, k::Policy::kPreemptive},
  };
  ktest::run_table(kTable, 10 * kTick);
  EXPECT_EQ(tokens(), "1W2");
  EXPECT_EQ(g_timeout_tick, 4U);
  EXPECT_EQ(g_got & 0x3U, 0x3U);
  EXPECT_EQ(g_flags.value(), 0U) << "the waited bits were cleared";
}

TEST(Pool, AllocatesEveryBlockThenReportsExhaustionAndRefusesBadReleases) {
  k::Pool<std::uint64_t, 4> pool;
  void* blocks[4] = {};
  for (void*& b : blocks) {
    ASSERT_EQ(pool.allocate(&b), k::Status::kOk);
    ASSERT_NE(b, nullptr);
  }
  void* extra = &extra;
  EXPECT_EQ(pool.allocate(&extra), k::Status::kExhausted);
  EXPECT_EQ(extra, nullptr);
  EXPECT_EQ(pool.free_count(), 0U);
  std::uint64_t foreign = 0;
  EXPECT_EQ(pool.release(&foreign), k::Status::kBadArg);
  EXPECT_EQ(pool.release(blocks[2]), k::Status::kOk);
  EXPECT_EQ(pool.release(blocks[2]), k::Status::kBadArg) << "double release";
  void* again = nullptr;
  EXPECT_EQ(pool.allocate(&again), k::Status::kOk);
  EXPECT_EQ(again, blocks[2]) << "LIFO reuse of the freed block";
}

TEST(KernelHeap, ARunOfTheKernelAllocatesNothingAfterInit) {
  static constexpr k::TaskSpec kTable[] = {
      {"rx", &consumer, nullptr, 1, 0, 0, kStack, k::Policy::kPreemptive},
      {"tx", &producer, nullptr, 3, 0, 0, kStack, k::Policy::kPreemptive},
      {"wait", &sem_waiter, nullptr, 2, 0, 0, kStack, k::Policy::kPreemptive},
      {"give", &sem_giver, nullptr, 4, 0, 0, kStack, k::Policy::kPreemptive},
  };
  tokens().reserve(4096);
  const std::uint64_t n = test_support::count_allocs([] { ktest::run_table(kTable, 20 * kTick); });
  EXPECT_EQ(n, 0U);
  EXPECT_EQ(tokens().size(), 9U);
}

}  // namespace

namespace {

k::Semaphore g_irq_sem{0, 1};
bsp::Cycles g_irq_woke_at = 0;
bsp::Cycles g_irq_due = 0;

void device_isr(bsp::TileId /*tile*/) { EXPECT_EQ(g_irq_sem.give_from_isr(), k::Status::kOk); }

void device_waiter(void*) {
  ASSERT_EQ(k::set_isr(bsp::Irq::kDevice, &device_isr), k::Status::kOk);
  g_irq_due = bsp::now() + 2 * ktest::kTick + ktest::kTick / 3;  // between ticks
  ASSERT_EQ(bsp::schedule_event(g_irq_due, 0, bsp::Irq::kDevice, nullptr, 0), bsp::BoardError::kOk);
  ASSERT_EQ(g_irq_sem.take(k::kForever), k::Status::kOk);
  g_irq_woke_at = bsp::now();
  token('I');
}

void background(void*) {
  token('b');
  bsp::consume(5 * ktest::kTick);
  token('B');
}

TEST(Interrupts, DeviceInterruptGivesFromIsrAndPreemptsChargedWorkAtItsCycle) {
  static constexpr k::TaskSpec kTable[] = {
      {"dev", &device_waiter, nullptr, 1, 0, 0, ktest::kStack, k::Policy::kPreemptive},
      {"bg", &background, nullptr, 6, 0, 0, ktest::kStack, k::Policy::kPreemptive},
  };
  ktest::run_table(kTable, 10 * ktest::kTick);
  EXPECT_EQ(tokens(), "bIB");
  EXPECT_EQ(g_irq_woke_at, g_irq_due);
}

}  // namespace
