/**
 * @file event_queue_test.cpp
 * @brief The ordered event queue and per-tile lists against a sorted reference; the trace ring and hash.
 */
#include "bsp_tile64/emu/event_queue.hpp"

#include "bsp_tile64/emu/rng.hpp"
#include "bsp_tile64/emu/trace.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cstdint>
#include <vector>

namespace {

bsp::Event random_event(bsp::Rng& rng, std::uint64_t seq) {
  return bsp::Event{rng.below(50U), static_cast<bsp::TileId>(rng.below(4U)), bsp::EventKind::kDevice,
                    bsp::Irq::kDevice, seq, nullptr, 0U};
}

TEST(EventQueue, HeapPopsInCycleTileSequenceOrderLikeASortedReference) {
  constexpr std::uint64_t kSeed = 99U;
  bsp::Rng rng(kSeed, bsp::StreamId::kTest);
  static bsp::EventHeap<512> heap;
  for (int round = 0; round < 20; ++round) {
    heap.clear();
    std::vector<bsp::Event> ref;
    const auto n = static_cast<std::size_t>(rng.below(512U)) + 1U;
    for (std::size_t i = 0; i < n; ++i) {
      const bsp::Event e = random_event(rng, i);
      ASSERT_TRUE(heap.push(e));
      ref.push_back(e);
    }
    std::sort(ref.begin(), ref.end(), bsp::event_before);
    for (const bsp::Event& e : ref) {
      ASSERT_FALSE(heap.empty());
      EXPECT_EQ(heap.top().seq, e.seq) << "seed " << kSeed << " round " << round;
      heap.pop();
    }
    EXPECT_TRUE(heap.empty());
  }
}

TEST(EventQueue, FullHeapAndListRefuseWithoutChange) {
  bsp::EventHeap<4> heap;
  bsp::LocalEvents<3> list;
  bsp::Rng rng(1U, bsp::StreamId::kTest);
  for (std::uint64_t i = 0; i < 4U; ++i) {
    EXPECT_TRUE(heap.push(random_event(rng, i)));
  }
  EXPECT_FALSE(heap.push(random_event(rng, 9U)));
  EXPECT_EQ(heap.size(), 4U);
  for (std::uint64_t i = 0; i < 3U; ++i) {
    EXPECT_TRUE(list.insert(random_event(rng, i)));
  }
  EXPECT_FALSE(list.insert(random_event(rng, 9U)));
  EXPECT_EQ(list.size(), 3U);
}

TEST(EventQueue, LocalListStaysSorted) {
  bsp::Rng rng(5U, bsp::StreamId::kTest);
  bsp::LocalEvents<32> list;
  std::vector<bsp::Event> ref;
  for (std::uint64_t i = 0; i < 32U; ++i) {
    const bsp::Event e = random_event(rng, i);
    ASSERT_TRUE(list.insert(e));
    ref.push_back(e);
  }
  std::sort(ref.begin(), ref.end(), bsp::event_before);
  for (const bsp::Event& e : ref) {
    EXPECT_EQ(list.front().seq, e.seq);
    list.pop_front();
  }
  EXPECT_TRUE(list.empty());
}

TEST(Trace, HashFoldsEveryFieldAndTheRingKeepsTheLatestInOrder) {
  bsp::trace_reset();
  const std::uint64_t h0 = bsp::trace_hash();
  bsp::trace_record(5U, 1U, 0x1001U, 2U, 3U);
  const std::uint64_t expected = bsp::trace_fold(h0, bsp::TraceEvent{5U, 1U, 0x1001U, 2U, 3U});
  EXPECT_EQ(bsp::trace_hash(), expected);
  // Changing any one field changes the hash.
  const std::array<bsp::TraceEvent, 5> variants{{{6U, 1U, 0x1001U, 2U, 3U},
                                                 {5U, 2U, 0x1001U, 2U, 3U},
                                                 {5U, 1U, 0x1002U, 2U, 3U},
                                                 {5U, 1U, 0x1001U, 3U, 3U},
                                                 {5U, 1U, 0x1001U, 2U, 4U}}};
  for (const bsp::TraceEvent& v : variants) {
    EXPECT_NE(bsp::trace_fold(h0, v), expected);
  }
  for (std::uint64_t i = 1; i < 300U; ++i) {
    bsp::trace_record(i, 0U, 1U, i, 0U);
  }
  EXPECT_EQ(bsp::trace_count(), 300U);
  std::array<bsp::TraceEvent, bsp::kTraceRingSize + 10U> out{};
  const std::size_t n = bsp::trace_recent(out);
  ASSERT_EQ(n, bsp::kTraceRingSize);
  EXPECT_EQ(out[0].a, 300U - bsp::kTraceRingSize);
  EXPECT_EQ(out[n - 1U].a, 299U);
}

}  // namespace
