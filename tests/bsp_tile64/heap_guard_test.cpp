/**
 * @file heap_guard_test.cpp
 * @brief The heap seal: allocations before the seal are free, after it they are counted
 *        (tests) or fatal (images).
 */
#include "bsp_tile64/emu/host/heap_guard.hpp"
#include "tests/support/heap_probe.hpp"

#include <gtest/gtest.h>

#include <cstdlib>
#include <memory>
#include <vector>

namespace {

TEST(HeapGuard, AllocationBeforeTheSealIsNotCounted) {
  auto before = std::make_unique<int>(7);  // made before the seal
  const std::uint64_t n = test_support::count_allocs([&] { *before = 8; });
  EXPECT_EQ(n, 0U);
  EXPECT_EQ(*before, 8);
}

TEST(HeapGuard, OperatorNewAfterTheSealIsCounted) {
  const std::uint64_t n = test_support::count_allocs([] {
    std::vector<int> v;
    v.reserve(100);
    v.push_back(1);
    test_support::escape(v.data());
    auto p = std::make_unique<double>(1.0);
    test_support::escape(p.get());
  });
  EXPECT_EQ(n, 2U);
}

TEST(HeapGuard, MallocAfterTheSealIsCountedWhereTheGuardOwnsMalloc) {
  const std::uint64_t n = test_support::count_allocs([] {
    void* p = std::malloc(64);
    test_support::escape(p);
    std::free(p);
  });
  EXPECT_EQ(n, bsp::heap::counts_malloc() ? 1U : 0U);
}

TEST(HeapGuard, TotalCountKeepsGrowingAndSealStateIsReported) {
  const std::uint64_t t0 = bsp::heap::allocs_total();
  auto p = std::make_unique<int>(1);
  test_support::escape(p.get());  // else Clang may elide the new/delete pair (C++14 allows it)
  EXPECT_GT(bsp::heap::allocs_total(), t0);
  EXPECT_FALSE(bsp::heap::is_sealed());
  bsp::heap::seal(bsp::heap::SealMode::kCount);
  EXPECT_TRUE(bsp::heap::is_sealed());
  bsp::heap::unseal();
  EXPECT_FALSE(bsp::heap::is_sealed());
}

TEST(HeapGuardDeathTest, AllocationAfterAFatalSealStopsTheProcessNamingTheCount) {
  GTEST_FLAG_SET(death_test_style, "threadsafe");
  EXPECT_EXIT(
      {
        bsp::heap::seal(bsp::heap::SealMode::kFatal);
        auto p = std::make_unique<long>(3);
        test_support::escape(p.get());
      },
      ::testing::ExitedWithCode(bsp::heap::kSealViolationExit), "allocation #1 after the seal");
}

}  // namespace
