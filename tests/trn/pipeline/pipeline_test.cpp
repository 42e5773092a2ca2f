/**
 * @file pipeline_test.cpp
 * @brief The whole TRN pipeline on the emulated chip: I/O tile, vision coordinator, 40 vision
 *        tiles and the filter, on rendered frames of the default descent.
 *
 * One world per suite (building it takes seconds, reading it from the cache
 * of an earlier run less than one); each test boots the chip
 * afresh. These are the acceptance tests of the distributed vision: frames
 * finish inside their deadline on 40 tiles, and with 10 vision tiles removed
 * the frames still finish, with fewer matches at first.
 */
#include "build_dirs.hpp"
#include "trn/events.hpp"

#include "bsp_tile64/emu/board.hpp"
#include "fdir/event_log.hpp"
#include "tests/support/flight_record.hpp"
#include "tools/common/mission/mission.hpp"
#include "trn/tasks/filter/filter_task.hpp"
#include "trn/tasks/vision/landmark_product.hpp"
#include "trn/tasks/tile_map.hpp"
#include "trn/tasks/vision/vision_coord.hpp"
#include "trn/tasks/vision/vision_shared.hpp"

#include <gtest/gtest.h>

#include <array>
#include <cstring>
#include <memory>
#include <string>
#include <vector>

namespace {

/** The filter task's counters on @p tile, as the host reads them: its record in the tile's RAM. */
trn::tasks::FilterTaskStats filter_stats(bsp::TileId tile) {
  return test_support::flight_record(tile, trn::tasks::kFilterTaskStatsRecord);
}

/** The coordinator's counters on @p tile, as the host reads them: its record in the tile's RAM. */
trn::tasks::VisionCoordStats coord_stats(bsp::TileId tile) {
  return test_support::flight_record(tile, trn::tasks::kVisionCoordStatsRecord);
}


using trn::tasks::kCoordinatorTile;
using trn::tasks::kFilterTile;

double cycles_to_s(bsp::Cycles c) { return static_cast<double>(c) / static_cast<double>(bsp::kTile64.clock_hz); }

void fly_s(double s) {
  (void)bsp::run_for(static_cast<bsp::Cycles>(s * static_cast<double>(bsp::kTile64.clock_hz)));
}

class PipelineTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    mission_ = std::make_unique<tools::Mission>();
    tools::MissionSetup setup;
    setup.duration_s = 46.0;
    // A world cache of this program's own (the cache keys a world by the program that built it).
    setup.world_cache = std::string(build_info::kBinDir) + "/test-world-cache-pipeline";
    std::string error;
    ASSERT_TRUE(mission_->build(setup, error)) << error;
  }
  static void TearDownTestSuite() { mission_.reset(); }

  static std::unique_ptr<tools::Mission> mission_;
};

std::unique_ptr<tools::Mission> PipelineTest::mission_;

TEST_F(PipelineTest, FortyVisionTilesConvergeFromThreeKilometres) {
  mission_->set_unpowered(0);
  std::string error;
  ASSERT_TRUE(mission_->boot(error)) << error;
  const tools::NavSample start = [] {
    fly_s(0.05);
    return PipelineTest::mission_->nav();
  }();
  ASSERT_TRUE(start.valid);
  EXPECT_GT(start.position_error_m, 2500.0);  // the scenario's 3 km horizontal error
  fly_s(7.0);
  const trn::tasks::VisionCoordStats c = coord_stats(kCoordinatorTile);
  EXPECT_GT(c.landmarks_selected, 500U);
  EXPECT_GE(c.frames_processed, 5U);
  EXPECT_GE(c.coarse_accepted, 1U);
  EXPECT_EQ(c.units_lost, 0U);
  EXPECT_GE(c.last_frame_matches, 100U) << "planned " << c.planned_total;
  // A fine-only frame (no coarse stage) ends well inside its 0.5 s deadline.
  EXPECT_LT(cycles_to_s(c.last_frame_cycles), 0.25);
  const tools::NavSample end = mission_->nav();
  ASSERT_TRUE(end.valid);
  EXPECT_LT(end.position_error_m, 20.0) << "after " << end.t_s << " s";
  const trn::tasks::FilterTaskStats f = filter_stats(kFilterTile);
  EXPECT_GT(f.matches_applied, 300U);
}

TEST_F(PipelineTest, TenVisionTilesRemovedFramesStillComplete) {
  // Ten vision tiles, scattered, never power up. The coordinator is not told:
  // the probes find them (each has at least two live neighbours to vote) and
  // the health task takes them out of the fault map, after which every other
  // tile still has a route of at most two re-injecting tiles to and from the
  // coordinator (checked for this set; two whole dead columns would cut some
  // tiles off, as the spares around the coordinator run no forwarder).
  constexpr std::array<bsp::TileId, 10> kRemoved{25, 31, 40, 44, 45, 47, 48, 53, 58, 59};
  std::uint64_t off = 0;
  std::uint32_t removed = 0;
  for (const bsp::TileId t : kRemoved) {
    off |= 1ULL << t;
    ++removed;
  }
  ASSERT_EQ(removed, 10U);
  mission_->set_unpowered(off);
  std::string error;
  ASSERT_TRUE(mission_->boot(error)) << error;
  fly_s(0.5);
  // The health task found them: their neighbours' probes get no answer, two agree.
  std::uint32_t voted = 0;
  for (std::uint64_t i = 0; i < fdir::event_log_written(trn::tasks::kSupervisorTile); ++i) {
    fdir::Event e{};
    if (fdir::event_log_read(trn::tasks::kSupervisorTile, i, &e) && e.id == fdir::EventId::kSwitchFailed) {
      EXPECT_NE((off >> e.subject) & 1ULL, 0ULL) << "tile " << e.subject << " voted out but alive";
      ++voted;
    }
  }
  EXPECT_EQ(voted, 10U);
  fly_s(5.5);  // the coordinator's start (selection, relit coarse map) takes the first frames
  const trn::tasks::VisionCoordStats first = coord_stats(kCoordinatorTile);
  ASSERT_GE(first.frames_processed, 3U);
  EXPECT_GE(first.units_lost + first.units_send_failed, 10U);  // the removed tiles' shares, at first
  EXPECT_GT(first.matches_total / first.frames_processed, 50U);
  fly_s(4.0);
  const trn::tasks::VisionCoordStats later = coord_stats(kCoordinatorTile);
  EXPECT_EQ(later.suspect_tiles, 10U);
  // Once isolated they get one probe unit every kProbeEveryFrames frames: only those are lost.
  EXPECT_LE(later.units_lost - first.units_lost, 10U * (4U / trn::tasks::kProbeEveryFrames + 1U));
  EXPECT_GE(later.frames_processed, first.frames_processed + 4U);
  // Their landmarks went to the 30 others: full frames again.
  EXPECT_GE(later.last_frame_matches, 80U);
  mission_->set_unpowered(0);
}

TEST_F(PipelineTest, ACoordinatorThatCannotStartSaysWhy) {
  // 8 px cells on the 6 m layer are more cells than the landmark table holds: the selection refuses.
  trn::vision::SelectParams tiny = trn::tasks::coord_select_params();
  tiny.cell_px = 8;
  tiny.cell_inset_px = 2;
  tiny.min_separation_px = 4;
  tiny.stride_px = 2;
  tiny.dense_cell_px = 0;
  mission_->set_unpowered(0);
  mission_->set_select(tiny);
  mission_->set_ground_landmarks(false);  // the ground could not select with these either: on board
  std::string error;
  ASSERT_TRUE(mission_->boot(error)) << error;
  fly_s(1.5);
  mission_->set_select(trn::tasks::coord_select_params());  // the next tests boot the usual coordinator
  mission_->set_ground_landmarks(true);
  std::uint32_t said = 0;
  for (std::uint64_t i = 0; i < fdir::event_log_written(kCoordinatorTile); ++i) {
    fdir::Event e{};
    if (fdir::event_log_read(kCoordinatorTile, i, &e) && e.id == trn::ev::kVisionSetUpFailed) {
      EXPECT_EQ(e.subject, 4U) << "the landmark selection";
      EXPECT_EQ(e.a, static_cast<std::uint32_t>(trn::vision::Status::kTooLarge));
      ++said;
    }
  }
  EXPECT_EQ(said, 1U);
  EXPECT_EQ(coord_stats(kCoordinatorTile).frames_processed, 0U);
}

/** The coordinator's table (DDR "landmarks"): its records, count and first_tight first. */
std::vector<std::uint8_t> coordinator_table() {
  const std::uint8_t* t = trn::tasks::ddr_find(trn::tasks::kLandmarkCarveName);
  if (t == nullptr) {
    return {};
  }
  const auto* table = reinterpret_cast<const trn::vision::LandmarkTable*>(t);  // NOLINT(cppcoreguidelines-pro-type-reinterpret-cast): carve bytes
  std::vector<std::uint8_t> out(2U * sizeof(std::uint32_t) + table->count * sizeof(trn::vision::Landmark));
  std::memcpy(out.data(), &table->count, sizeof(std::uint32_t));
  std::memcpy(out.data() + sizeof(std::uint32_t), &table->first_tight, sizeof(std::uint32_t));
  std::memcpy(out.data() + 2U * sizeof(std::uint32_t), table->items, table->count * sizeof(trn::vision::Landmark));
  return out;
}

/** The events of @p id the coordinator's tile wrote. */
std::vector<fdir::Event> coordinator_events(fdir::EventId id) {
  std::vector<fdir::Event> out;
  for (std::uint64_t i = 0; i < fdir::event_log_written(kCoordinatorTile); ++i) {
    fdir::Event e{};
    if (fdir::event_log_read(kCoordinatorTile, i, &e) && e.id == id) {
      out.push_back(e);
    }
  }
  return out;
}

// The ground's landmark table is the table the coordinator selects on board, bit for bit (positions
// included), and with it the coordinator is ready for the frame captured at 1 s.
TEST_F(PipelineTest, TheGroundsLandmarkTableIsTheOnboardSelectionAndReadyForTheFirstFrame) {
  mission_->set_unpowered(0);
  std::string error;
  ASSERT_TRUE(mission_->boot(error)) << error;
  fly_s(1.2);
  const trn::tasks::VisionCoordStats ground = coord_stats(kCoordinatorTile);
  EXPECT_EQ(ground.landmarks_from_ground, 1U);
  EXPECT_GT(ground.landmarks_selected, 3000U);
  EXPECT_EQ(ground.frames_before_ready, 0U);
  EXPECT_GE(ground.frames_processed, 1U) << "the frame captured at 1 s";
  EXPECT_TRUE(coordinator_events(trn::ev::kLandmarkProductRefused).empty());
  const std::vector<std::uint8_t> from_ground = coordinator_table();
  mission_->set_ground_landmarks(false);
  ASSERT_TRUE(mission_->boot(error)) << error;
  fly_s(2.5);
  mission_->set_ground_landmarks(true);
  const trn::tasks::VisionCoordStats board = coord_stats(kCoordinatorTile);
  EXPECT_EQ(board.landmarks_from_ground, 0U);
  EXPECT_LT(ground.ready_ms, 300U) << "the table checked, the coarse layer relit";
  EXPECT_GT(board.ready_ms, 1000U) << "the selection on board is most of the start";
  EXPECT_EQ(board.frames_before_ready, 1U) << "selected on board, the start takes the frame at 1 s";
  const std::vector<std::uint8_t> on_board = coordinator_table();
  ASSERT_FALSE(on_board.empty());
  EXPECT_TRUE(from_ground == on_board) << "the same records, bit for bit";
}

// A ground table changed in DDR (one bit of one record) fails its CRC: the coordinator says so
// (landmark_product_refused, cause 5) and selects the landmarks itself; the frames go on.
TEST_F(PipelineTest, AGroundTableChangedInMemoryIsRefusedAndTheCoordinatorSelectsItself) {
  mission_->set_unpowered(0);
  std::string error;
  ASSERT_TRUE(mission_->boot(error)) << error;
  const std::uint8_t* block = trn::tasks::ddr_find(trn::tasks::kLandmarkProductCarveName);
  ASSERT_NE(block, nullptr);
  auto* bytes = const_cast<std::uint8_t*>(block);  // NOLINT(cppcoreguidelines-pro-type-const-cast): the test's upset
  bytes[sizeof(trn::tasks::LandmarkProductHeader) + 1000U * sizeof(trn::vision::Landmark) + 9U] ^= 0x10U;
  fly_s(3.5);
  const std::vector<fdir::Event> refused = coordinator_events(trn::ev::kLandmarkProductRefused);
  ASSERT_EQ(refused.size(), 1U);
  EXPECT_EQ(refused[0].cause, static_cast<std::uint32_t>(trn::tasks::ProductCheck::kBadRecords));
  const trn::tasks::VisionCoordStats c = coord_stats(kCoordinatorTile);
  EXPECT_EQ(c.landmarks_from_ground, 0U);
  EXPECT_GT(c.landmarks_selected, 3000U);
  EXPECT_GE(c.frames_processed, 1U);
  EXPECT_TRUE(coordinator_events(trn::ev::kVisionSetUpFailed).empty());
}

}  // namespace
