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
  tiny.cell_px = 4;
  tiny.min_separation_px = 4;
  tiny.cell_inset_px = 1;
  EXPECT_EQ(tv::select_landmarks(map.view(), {}, {}, tiny, table, work), tv::Status::kTooLarge);
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

// The coordinator selects in steps and takes the filter's solutions between them: any step size gives the
// table select_landmarks() gives, bit for bit, and the same counted work; bad steps are refused.
TEST(Landmarks, SelectionInStepsGivesTheSameTableAndWork) {
  const std::uint64_t seed = 83;
  const Image map = vision_test::smooth_texture(700, 520, 2, seed);
  const tv::MapGeometry geo{6.0, 100.0, 900.0};
  static tv::LandmarkTable whole;
  static tv::LandmarkTable stepped;
  bsp::Work w_whole;
  ASSERT_EQ(tv::select_landmarks(map.view(), {}, geo, tv::SelectParams{}, whole, w_whole), tv::Status::kOk);
  ASSERT_GT(whole.count, 20U) << "seed " << seed;
  for (const std::int32_t per_step : {1, 7, 16, 1000}) {
    tv::SelectProgress progress{};
    bsp::Work w_steps;
    std::uint32_t calls = 0;
    while (!progress.done && calls < 10000U) {
      ASSERT_EQ(tv::select_landmarks_step(map.view(), {}, geo, tv::SelectParams{}, stepped, progress, per_step, w_steps),
                tv::Status::kOk);
      ++calls;
    }
    ASSERT_TRUE(progress.done) << per_step;
    EXPECT_EQ(calls, static_cast<std::uint32_t>((progress.next_cell + per_step - 1) / per_step)) << per_step;
    ASSERT_EQ(stepped.count, whole.count) << per_step;
    for (std::uint32_t i = 0; i < whole.count; ++i) {
      EXPECT_EQ(stepped.items[i].col_px, whole.items[i].col_px) << per_step << " " << i;
      EXPECT_EQ(stepped.items[i].row_px, whole.items[i].row_px) << per_step << " " << i;
      EXPECT_EQ(stepped.items[i].corner, whole.items[i].corner) << per_step << " " << i;
      EXPECT_EQ(stepped.items[i].p_m[0], whole.items[i].p_m[0]) << per_step << " " << i;
      EXPECT_EQ(stepped.items[i].p_m[1], whole.items[i].p_m[1]) << per_step << " " << i;
    }
    EXPECT_EQ(w_steps.int_macs, w_whole.int_macs) << per_step;
    EXPECT_EQ(w_steps.int_ops, w_whole.int_ops) << per_step;
  }
  tv::SelectProgress bad{};
  bsp::Work w;
  EXPECT_EQ(tv::select_landmarks_step(map.view(), {}, geo, tv::SelectParams{}, stepped, bad, 0, w), tv::Status::kBadInput);
  bad.next_cell = 1 << 20;
  EXPECT_EQ(tv::select_landmarks_step(map.view(), {}, geo, tv::SelectParams{}, stepped, bad, 16, w), tv::Status::kBadInput);
}

}  // namespace
