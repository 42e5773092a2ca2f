/**
 * @file landmarks_test.cpp
 * @brief Landmark selection prefers textured corners over flat areas and edges, spreads
 *        over the map, and places each landmark at its map-frame position.
 */
#include "trn/vision/landmarks.hpp"

#include "tests/support/heap_probe.hpp"
#include "tests/trn/vision/synth.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <utility>
#include <vector>

namespace {

namespace tv = trn::vision;
using vision_test::Image;

TEST(Landmarks, CornerStrengthRanksCornerAboveEdgeAboveFlat) {
  Image corner(41, 41, 50);
  Image edge(41, 41, 50);
  const Image flat(41, 41, 50);
  for (std::int32_t y = 0; y < 41; ++y)
    for (std::int32_t x = 0; x < 41; ++x) {
      if (x >= 20 && y >= 20) corner.at(x, y) = 200;
      if (x >= 20) edge.at(x, y) = 200;
    }
  bsp::Work work;
  float c_corner = 0, c_edge = 0, c_flat = 0, sd = 0;
  tv::patch_strength(corner.view(), 20, 20, 21, c_corner, sd, work);
  tv::patch_strength(edge.view(), 20, 20, 21, c_edge, sd, work);
  EXPECT_GT(sd, 50.0F);  // an edge has contrast...
  tv::patch_strength(flat.view(), 20, 20, 21, c_flat, sd, work);
  EXPECT_GT(c_corner, 100.0F);
  EXPECT_NEAR(c_edge, 0.0F, 1e-3F);  // ...but no strength across it
  EXPECT_EQ(c_flat, 0.0F);
  EXPECT_EQ(sd, 0.0F);
  EXPECT_GT(work.int_macs, 0U);
}

TEST(Landmarks, TexturedAreaIsChosenOverFlatAndEdgeOnlyAreas) {
  const std::uint64_t seed = 81;
  Image map = vision_test::smooth_texture(512, 512, 2, seed);
  bsp::Rng rng(seed, bsp::StreamId::kTest, 5);
  for (std::int32_t y = 0; y < 512; ++y)
    for (std::int32_t x = 0; x < 340; ++x) {
      // Flat (sensor noise only) on the left, vertical bars (edges, no corners) in the middle.
      map.at(x, y) = x < 170 ? vision_test::clamp_u8(120.0 + rng.normal(0.0, 1.0))
                             : static_cast<std::uint8_t>((x / 6) % 2 == 0 ? 60 : 190);
    }
  static tv::LandmarkTable table;
  bsp::Work work;
  ASSERT_EQ(tv::select_landmarks(map.view(), {}, tv::MapGeometry{}, tv::SelectParams{}, table, work),
            tv::Status::kOk);
  ASSERT_GT(table.count, 10U) << "seed " << seed;
  for (std::uint32_t i = 0; i < table.count; ++i) {
    EXPECT_GE(table.items[i].col_px, 340 - 10) << "seed " << seed << " landmark " << i;
  }
}

TEST(Landmarks, SpreadOverTheMapOnePerCellAndNeverTooClose) {
  const std::uint64_t seed = 82;
  const Image map = vision_test::smooth_texture(512, 512, 2, seed);
  const tv::SelectParams p;
  static tv::LandmarkTable table;
  bsp::Work work;
  ASSERT_EQ(tv::select_landmarks(map.view(), {}, tv::MapGeometry{}, p, table, work), tv::Status::kOk);
  const std::int32_t cells_per_side = 512 / p.cell_px;
  std::vector<int> per_cell(static_cast<std::size_t>(cells_per_side * cells_per_side), 0);
  for (std::uint32_t i = 0; i < table.count; ++i) {
    const tv::Landmark& a = table.items[i];
    ++per_cell[vision_test::idx(a.col_px / p.cell_px, a.row_px / p.cell_px, cells_per_side)];
    for (std::uint32_t j = i + 1; j < table.count; ++j) {
      const tv::Landmark& b = table.items[j];
      EXPECT_GE(std::hypot(a.col_px - b.col_px, a.row_px - b.row_px), p.min_separation_px) << i << "," << j;
    }
  }
  int occupied = 0;
  for (int n : per_cell) {
    EXPECT_LE(n, 1);
    occupied += n > 0 ? 1 : 0;
  }
  std::printf("landmarks: %u selected, %d of %d cells occupied\n", table.count, occupied,
              cells_per_side * cells_per_side);
  EXPECT_GE(occupied, (cells_per_side * cells_per_side * 9) / 10) << "seed " << seed;
}

TEST(Landmarks, SuppressionKeepsTheSeparationWhenCandidatesMayTouchCellBorders) {
  const std::uint64_t seed = 86;
  const Image map = vision_test::smooth_texture(512, 512, 2, seed);
  tv::SelectParams p;
  p.cell_inset_px = 0;  // winners may sit on a shared border: only the suppression separates them
  static tv::LandmarkTable table;
  bsp::Work work;
  ASSERT_EQ(tv::select_landmarks(map.view(), {}, tv::MapGeometry{}, p, table, work), tv::Status::kOk);
  ASSERT_GT(table.count, 20U);
  for (std::uint32_t i = 0; i < table.count; ++i)
    for (std::uint32_t j = i + 1; j < table.count; ++j) {
      const tv::Landmark& a = table.items[i];
      const tv::Landmark& b = table.items[j];
      EXPECT_GE(std::hypot(a.col_px - b.col_px, a.row_px - b.row_px), p.min_separation_px) << "seed " << seed;
    }
}

TEST(Landmarks, MapPositionsFollowPixelCentreResolutionAndElevation) {
  const std::uint64_t seed = 83;
  const Image map = vision_test::smooth_texture(256, 192, 2, seed);
  std::vector<float> elev(vision_test::idx(0, 192, 256));
  for (std::int32_t y = 0; y < 192; ++y)
    for (std::int32_t x = 0; x < 256; ++x) elev[vision_test::idx(x, y, 256)] = static_cast<float>(1000.0 + 0.5 * x - 0.25 * y);
  const tv::MapGeometry geo{6.0, -768.0, 576.0};
  static tv::LandmarkTable table;
  bsp::Work work;
  ASSERT_EQ(tv::select_landmarks(map.view(), {elev.data(), 256, 192, 256}, geo, tv::SelectParams{}, table, work),
            tv::Status::kOk);
  ASSERT_GT(table.count, 0U);
  for (std::uint32_t i = 0; i < table.count; ++i) {
    const tv::Landmark& l = table.items[i];
    EXPECT_DOUBLE_EQ(l.p_m[0], -768.0 + 6.0 * l.col_px);
    EXPECT_DOUBLE_EQ(l.p_m[1], 576.0 - 6.0 * l.row_px);
    EXPECT_DOUBLE_EQ(l.p_m[2], 1000.0 + 0.5 * l.col_px - 0.25 * l.row_px);
    EXPECT_GE(l.corner, tv::SelectParams{}.min_corner);
    EXPECT_GE(l.stddev, tv::SelectParams{}.min_stddev);
  }
}

TEST(Landmarks, RefusesBadParametersAndTooManyCells) {
  const Image map = vision_test::smooth_texture(512, 512, 2, 84);
  static tv::LandmarkTable table;
  bsp::Work work;
  tv::SelectParams tiny;
  tiny.cell_px = 3;
  tiny.min_separation_px = 3;
  tiny.cell_inset_px = 1;
  EXPECT_EQ(tv::select_landmarks(map.view(), {}, {}, tiny, table, work), tv::Status::kTooLarge);
  tv::SelectParams small;  // 103 x 103 cells fit; with a dense set of 128 x 128 more, the grids do not
  small.cell_px = 5;
  small.min_separation_px = 4;
  small.cell_inset_px = 1;
  EXPECT_EQ(tv::select_landmarks(map.view(), {}, {}, small, table, work), tv::Status::kOk);
  small.dense_cell_px = 4;
  small.dense_cell_inset_px = 1;
  EXPECT_EQ(tv::select_landmarks(map.view(), {}, {}, small, table, work), tv::Status::kTooLarge);
  for (const auto& [cell, inset] : {std::pair{64, 8}, std::pair{24, 8}, std::pair{40, 20}, std::pair{-8, 0}}) {
    tv::SelectParams dense;  // not smaller than the loose cell, below the separation, inset too deep, negative
    dense.dense_cell_px = cell;
    dense.dense_cell_inset_px = inset;
    EXPECT_EQ(tv::select_landmarks(map.view(), {}, {}, dense, table, work), tv::Status::kBadInput) << cell;
  }
  tv::SelectParams even;
  even.patch_px = 20;
  EXPECT_EQ(tv::select_landmarks(map.view(), {}, {}, even, table, work), tv::Status::kBadInput);
  std::vector<float> elev(16);
  EXPECT_EQ(tv::select_landmarks(map.view(), {elev.data(), 4, 4, 4}, {}, {}, table, work), tv::Status::kBadInput);
  EXPECT_EQ(table.count, 0U);
}

TEST(Landmarks, SelectionMakesNoHeapAllocation) {
  const Image map = vision_test::smooth_texture(256, 256, 2, 85);
  static tv::LandmarkTable table;
  bsp::Work work;
  tv::Status st = tv::Status::kBadInput;
  const std::uint64_t allocs = test_support::count_allocs(
      [&] { st = tv::select_landmarks(map.view(), {}, {}, {}, table, work); });
  EXPECT_EQ(st, tv::Status::kOk);
  EXPECT_EQ(allocs, 0U);
}

/** Every field the same, exactly. */
bool same(const tv::Landmark& a, const tv::Landmark& b) {
  return a.col_px == b.col_px && a.row_px == b.row_px && a.p_m[0] == b.p_m[0] && a.p_m[1] == b.p_m[1] &&
         a.p_m[2] == b.p_m[2] && a.corner == b.corner && a.stddev == b.stddev;
}

/** A two-set selection: the default one with a dense set of 40 px cells. */
tv::SelectParams two_sets() {
  tv::SelectParams p;
  p.dense_cell_px = 40;
  p.dense_cell_inset_px = 8;
  return p;
}

// The dense set adds landmarks where the loose set leaves room: the loose set is the one-set table bit for
// bit, the dense landmarks follow it (first_tight), one per dense cell at most, and no two landmarks of the
// whole table are closer than the separation.
TEST(Landmarks, TwoSetsKeepTheLooseSetAndAddDenseLandmarksAwayFromIt) {
  const std::uint64_t seed = 82;
  const Image map = vision_test::smooth_texture(512, 512, 2, seed);
  const tv::MapGeometry geo{6.0, 100.0, 900.0};
  static tv::LandmarkTable one;
  static tv::LandmarkTable two;
  bsp::Work w1;
  bsp::Work w2;
  const tv::SelectParams p = two_sets();
  ASSERT_EQ(tv::select_landmarks(map.view(), {}, geo, tv::SelectParams{}, one, w1), tv::Status::kOk);
  ASSERT_EQ(tv::select_landmarks(map.view(), {}, geo, p, two, w2), tv::Status::kOk);
  EXPECT_EQ(one.first_tight, one.count) << "one set: nothing waits for a tight prior";
  ASSERT_EQ(two.first_tight, one.count);
  for (std::uint32_t i = 0; i < one.count; ++i) {
    ASSERT_TRUE(same(two.items[i], one.items[i])) << i;
  }
  const std::uint32_t dense = two.count - two.first_tight;
  std::printf("two sets: %u loose + %u dense landmarks\n", one.count, dense);
  EXPECT_GT(dense, one.count / 4U) << "seed " << seed;
  const std::int32_t per_side = (512 + p.dense_cell_px - 1) / p.dense_cell_px;
  std::vector<int> per_cell(static_cast<std::size_t>(per_side * per_side), 0);
  for (std::uint32_t i = two.first_tight; i < two.count; ++i) {
    const tv::Landmark& a = two.items[i];
    const std::int32_t in_x = a.col_px % p.dense_cell_px;
    const std::int32_t in_y = a.row_px % p.dense_cell_px;
    EXPECT_TRUE(in_x >= p.dense_cell_inset_px && in_x < p.dense_cell_px - p.dense_cell_inset_px) << i;
    EXPECT_TRUE(in_y >= p.dense_cell_inset_px && in_y < p.dense_cell_px - p.dense_cell_inset_px) << i;
    EXPECT_GE(a.corner, p.min_corner);
    EXPECT_DOUBLE_EQ(a.p_m[0], 100.0 + 6.0 * a.col_px);
    EXPECT_DOUBLE_EQ(a.p_m[1], 900.0 - 6.0 * a.row_px);
    EXPECT_EQ(++per_cell[vision_test::idx(a.col_px / p.dense_cell_px, a.row_px / p.dense_cell_px, per_side)], 1);
    if (i > two.first_tight) {
      const tv::Landmark& b = two.items[i - 1U];
      EXPECT_LT(b.row_px / p.dense_cell_px * per_side + b.col_px / p.dense_cell_px,
                a.row_px / p.dense_cell_px * per_side + a.col_px / p.dense_cell_px) << "cell order";
    }
  }
  for (std::uint32_t i = 0; i < two.count; ++i) {
    for (std::uint32_t j = i + 1; j < two.count; ++j) {
      const tv::Landmark& a = two.items[i];
      const tv::Landmark& b = two.items[j];
      EXPECT_GE(std::hypot(a.col_px - b.col_px, a.row_px - b.row_px), p.min_separation_px) << i << "," << j;
    }
  }
  EXPECT_GT(w2.int_macs, w1.int_macs) << "the dense search is charged";
}

// The coordinator selects in steps and takes the filter's solutions between them: any step size gives the
// table select_landmarks() gives, bit for bit, and the same counted work, with one set or two; bad steps are
// refused.
TEST(Landmarks, SelectionInStepsGivesTheSameTableAndWork) {
  const std::uint64_t seed = 83;
  const Image map = vision_test::smooth_texture(700, 520, 2, seed);
  const tv::MapGeometry geo{6.0, 100.0, 900.0};
  static tv::LandmarkTable whole;
  static tv::LandmarkTable stepped;
  for (const tv::SelectParams& sp : {tv::SelectParams{}, two_sets()}) {
    bsp::Work w_whole;
    ASSERT_EQ(tv::select_landmarks(map.view(), {}, geo, sp, whole, w_whole), tv::Status::kOk);
    ASSERT_GT(whole.count, 20U) << "seed " << seed;
    const std::int32_t loose_cells = ((700 + sp.cell_px - 1) / sp.cell_px) * ((520 + sp.cell_px - 1) / sp.cell_px);
    for (const std::int32_t per_step : {1, 7, 16, 1000}) {
      tv::SelectProgress progress{};
      bsp::Work w_steps;
      std::uint32_t calls = 0;
      while (!progress.done && calls < 10000U) {
        ASSERT_EQ(tv::select_landmarks_step(map.view(), {}, geo, sp, stepped, progress, per_step, w_steps),
                  tv::Status::kOk);
        ++calls;
      }
      ASSERT_TRUE(progress.done) << per_step;
      const std::int32_t dense_cells = progress.next_cell - loose_cells;
      EXPECT_EQ(calls, static_cast<std::uint32_t>((loose_cells + per_step - 1) / per_step +
                                                  (dense_cells + per_step - 1) / per_step))
          << per_step;
      ASSERT_EQ(stepped.count, whole.count) << per_step;
      ASSERT_EQ(stepped.first_tight, whole.first_tight) << per_step;
      for (std::uint32_t i = 0; i < whole.count; ++i) {
        EXPECT_TRUE(same(stepped.items[i], whole.items[i])) << per_step << " " << i;
      }
      EXPECT_EQ(w_steps.int_macs, w_whole.int_macs) << per_step;
      EXPECT_EQ(w_steps.int_ops, w_whole.int_ops) << per_step;
    }
  }
  tv::SelectProgress bad{};
  bsp::Work w;
  EXPECT_EQ(tv::select_landmarks_step(map.view(), {}, geo, tv::SelectParams{}, stepped, bad, 0, w), tv::Status::kBadInput);
  bad.next_cell = 1 << 20;
  EXPECT_EQ(tv::select_landmarks_step(map.view(), {}, geo, tv::SelectParams{}, stepped, bad, 16, w), tv::Status::kBadInput);
}

}  // namespace
