/**
 * @file cost_model_test.cpp
 * @brief The cost model: exact cycles per kind of work per profile, rounding, saturation, consume(Work).
 */
#include "bsp_tile64/emu/cost_model.hpp"

#include "board_fixture.hpp"
#include "bsp_tile64/emu/board.hpp"
#include "bsp_tile64/emu/profile.hpp"
#include "bsp_tile64/emu/rng.hpp"

#include <gtest/gtest.h>

#include <cstdint>
#include <limits>

namespace {

using bsp::Cycles;
using bsp::Work;

Work one_of(int kind, std::uint64_t n) {
  Work w{};
  switch (kind) {
    case 0: w.int_ops = n; break;
    case 1: w.int_macs = n; break;
    case 2: w.flops = n; break;
    case 3: w.fdivs = n; break;
    default: w.mem_words = n; break;
  }
  return w;
}

TEST(CostModel, Tile64TableChargesTheDocumentedCycles) {
  const bsp::ChipProfile& p = bsp::kTile64;
  EXPECT_EQ(bsp::cost_of(p, one_of(0, 1000U)), 500U);     // 0.5 cycle per integer op
  EXPECT_EQ(bsp::cost_of(p, one_of(1, 1000U)), 1000U);    // 1 cycle per MAC
  EXPECT_EQ(bsp::cost_of(p, one_of(2, 1000U)), 48'000U);  // soft-float add/mul
  EXPECT_EQ(bsp::cost_of(p, one_of(3, 1000U)), 200'000U); // soft-float div/sqrt
  EXPECT_EQ(bsp::cost_of(p, one_of(4, 1000U)), 2000U);    // memory word
  EXPECT_EQ(bsp::network_cycles(p, 7U, 10U), 17U);        // 7 hops + 10 words of serialization
  EXPECT_FALSE(p.has_fpu);
  EXPECT_EQ(p.tiles(), 64U);
  EXPECT_EQ(p.cycles_per_ms(), 700'000U);
}

TEST(CostModel, MaestroFpuMakesFloatingPointSixteenTimesCheaper) {
  const bsp::ChipProfile& p = bsp::kMaestro;
  EXPECT_EQ(bsp::cost_of(p, one_of(2, 1000U)), 3000U);
  EXPECT_EQ(bsp::cost_of(p, one_of(3, 1000U)), 20'000U);
  EXPECT_EQ(bsp::cost_of(p, one_of(0, 1000U)), 500U);
  EXPECT_TRUE(p.has_fpu);
  EXPECT_EQ(p.tiles(), 49U);
  EXPECT_EQ(bsp::cost_of(bsp::kTile64, one_of(2, 1000U)) / bsp::cost_of(p, one_of(2, 1000U)), 16U);
}

TEST(CostModel, SumMatchesAReferenceAndRoundsUpToWholeCycles) {
  bsp::Rng rng(7U, bsp::StreamId::kTest);
  for (int i = 0; i < 1000; ++i) {
    Work w{};
    w.int_ops = rng.below(1'000'000U);
    w.int_macs = rng.below(1'000'000U);
    w.flops = rng.below(1'000'000U);
    w.fdivs = rng.below(1000U);
    w.mem_words = rng.below(1'000'000U);
    // Reference: exact rational sum in half cycles, rounded up.
    const std::uint64_t half = w.int_ops + 2U * w.int_macs + 96U * w.flops + 400U * w.fdivs + 4U * w.mem_words;
    EXPECT_EQ(bsp::cost_of(bsp::kTile64, w), (half + 1U) / 2U) << "seed 7, draw " << i;
  }
  EXPECT_EQ(bsp::cost_of(bsp::kTile64, one_of(0, 1U)), 1U) << "any work costs at least a cycle";
  EXPECT_EQ(bsp::cost_of(bsp::kTile64, Work{}), 0U);
}

TEST(CostModel, HugeCountsSaturateInsteadOfWrapping) {
  const std::uint64_t kMax = std::numeric_limits<std::uint64_t>::max();
  EXPECT_EQ(bsp::cost_of(bsp::kTile64, one_of(2, kMax / 2U)), kMax / bsp::kCostScale + 1U);
}

Cycles g_after = 0U;

void boot_work(bsp::TileId /*tile*/) {
  Work w{};
  w.flops = 10U;
  w.int_ops = 3U;
  bsp::consume(w);
  g_after = bsp::now();
  board_test::idle_forever();
}

TEST(CostModel, ConsumeWorkAdvancesTheTileByItsCostOnTheBoardProfile) {
  g_after = 0U;
  bsp::BoardConfig c = board_test::small_config();
  c.powered_at_start = 1U;
  c.boot[0] = boot_work;
  ASSERT_EQ(bsp::board_init(c), bsp::BoardError::kOk);
  bsp::run_for(2000U);
  EXPECT_EQ(g_after, 100U + 480U + 2U);  // 10 soft flops + 1.5 cycles of int ops rounded up
  Work w{};
  w.flops = 10U;
  EXPECT_EQ(bsp::cost_of(w), 480U);
}

}  // namespace
