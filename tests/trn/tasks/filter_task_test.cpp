/**
 * @file filter_task_test.cpp
 * @brief The filter task on its own tile at 100 Hz, fed by the I/O tile over the UDN: follows
 *        the truth, meets every deadline inside 10 ms of emulated time, allocates nothing,
 *        and repeats bit for bit.
 */
#include "bsp_tile64/emu/board.hpp"
#include "bsp_tile64/api/memory.hpp"
#include "bsp_tile64/emu/devices/device_bus.hpp"
#include "bsp_tile64/emu/trace.hpp"
#include "bsp_tile64/emu/udn_net.hpp"
#include "bsp_tile64/world/trajectory.hpp"
#include "kernel/kernel.hpp"
#include "tests/support/heap_probe.hpp"
#include "tests/support/flight_record.hpp"
#include "trn/tasks/filter/filter_task.hpp"
#include "trn/tasks/io/io_task.hpp"
#include "trn/tasks/messages.hpp"
#include "trn/tasks/tile_map.hpp"

#include <gtest/gtest.h>

#include <cstring>

namespace {

/** The filter task's counters on @p tile, as the host reads them: its record in the tile's RAM. */
trn::tasks::FilterTaskStats filter_stats(bsp::TileId tile) {
  return test_support::flight_record(tile, trn::tasks::kFilterTaskStatsRecord);
}

/** The latest solution @p tile's filter delivered, as the host reads it: its record in the tile's RAM. False before the first. */
bool latest_output(bsp::TileId tile, trn::filter::NavOutput& o) {
  const trn::tasks::FilterOutput out = test_support::flight_record(tile, trn::tasks::kFilterOutputRecord);
  o = out.latest;
  return out.delivered;
}


constexpr bsp::TileId kIoTile = 9;
constexpr bsp::TileId kFilterTile = 18;
constexpr bsp::Cycles kHz = bsp::kTile64.clock_hz;

class FilterTask : public ::testing::Test {
 protected:
  void boot(bool imu_errors) {
    ASSERT_EQ(traj_.init(bsp::world::TrajectoryConfig{}), bsp::world::WorldError::kOk);
    bsp::ImuErrorConfig ic;
    ic.enabled = imu_errors;
    ASSERT_EQ(imu_.init(&traj_, ic, 21), bsp::ImuError::kOk);
    const bsp::world::TruthState t0 = traj_.at(0.0);
    trn::tasks::ImageConfig image{};
    image.io.filter_tile = kFilterTile;
    image.filter.initial.t_s = 0.0;
    image.filter.initial.x.p_m = t0.r_m;
    image.filter.initial.x.v_mps = t0.v_mps;
    image.filter.initial.x.q_mb = t0.q_mb;
    image.filter.initial.sigma_p_m = trn::filter::Vec3::Constant(1.0);
    image.filter.initial.sigma_v_mps = trn::filter::Vec3::Constant(0.01);
    ASSERT_EQ(trn::tasks::configure_image(image), trn::tasks::ImageError::kOk);
    bsp::BoardConfig cfg = bsp::default_config(bsp::kTile64);
    cfg.powered_at_start = (1ULL << kIoTile) | (1ULL << kFilterTile);
    cfg.monitor_tile = bsp::kNoTile;
    cfg.boot[kIoTile] = &k::boot_entry;
    cfg.boot[kFilterTile] = &k::boot_entry;
    k::set_task_table(kIoTile, trn::tasks::kIoRole, bsp::kTile64.cycles_per_ms());
    k::set_task_table(kFilterTile, trn::tasks::kFilterRole, bsp::kTile64.cycles_per_ms());
    // A fresh shared DDR: no checkpoint or IMU record of an earlier test to resume from.
    ASSERT_EQ(bsp::region_reset(bsp::Region{bsp::Region::kDdr}), bsp::MemError::kOk);
    ASSERT_EQ(bsp::board_init(cfg), bsp::BoardError::kOk);
    ASSERT_EQ(bsp::udn_net_init(bsp::NetConfig{}), bsp::NetError::kOk);
    bsp::DeviceBusConfig bus;
    bus.io_tile = kIoTile;
    bus.imu = &imu_;
    ASSERT_EQ(bsp::attach_devices(bus), bsp::DeviceBusError::kOk);
  }

  double position_error_m(const trn::filter::NavOutput& o) const {
    const bsp::world::TruthState t = traj_.at(o.t_s);
    const Eigen::Vector3d p(o.p_m[0], o.p_m[1], o.p_m[2]);
    return (p - t.r_m).norm();
  }

  bsp::world::Trajectory traj_;
  bsp::ImuModel imu_;
};

TEST_F(FilterTask, FollowsTheTruthAtOneHundredHertzWithinEveryDeadline) {
  boot(false);
  (void)bsp::run_for(5U * kHz);
  const trn::tasks::FilterTaskStats st = filter_stats(kFilterTile);
  EXPECT_GE(st.jobs, 495U);
  EXPECT_GE(st.imu_used, 495U) << "every sample forwarded and integrated";
  EXPECT_EQ(st.imu_rejected, 0U);
  EXPECT_EQ(st.filter_errors, 0U);
  EXPECT_EQ(test_support::flight_record(kIoTile, trn::tasks::kIoTaskStatsRecord).send_failures, 0U);
  // One period's work on the soft-float TILE64 fits well inside 10 ms.
  EXPECT_GT(st.max_job_cycles, 0U);
  EXPECT_LT(st.max_job_cycles, 10U * bsp::kTile64.cycles_per_ms() / 2U);
  k::TaskStats ks{};
  ASSERT_EQ(k::task_stats(kFilterTile, k::find_task(kFilterTile, "filter"), &ks), k::Status::kOk);
  EXPECT_EQ(ks.deadline_misses, 0U);
  EXPECT_EQ(ks.overruns, 0U);
  trn::filter::NavOutput o{};
  ASSERT_TRUE(latest_output(kFilterTile, o));
  EXPECT_NEAR(o.t_s, 5.0, 0.0201);
  EXPECT_LT(position_error_m(o), 0.05) << "a perfect IMU integrates back to the truth";
  std::printf("filter task: %u jobs, %u samples, max job %.3f ms, last %.3f ms, error %.4f m\n", st.jobs,
              st.imu_used, static_cast<double>(st.max_job_cycles) / 7.0e5,
              static_cast<double>(st.last_job_cycles) / 7.0e5, position_error_m(o));
}

TEST_F(FilterTask, WithLn200ErrorsTheDriftStaysInsideThreeSigma) {
  boot(true);
  (void)bsp::run_for(10U * kHz);
  trn::filter::NavOutput o{};
  ASSERT_TRUE(latest_output(kFilterTile, o));
  const double sigma = std::sqrt(o.var_diag[0] + o.var_diag[1] + o.var_diag[2]);
  EXPECT_LT(position_error_m(o), 3.0 * sigma) << "sigma " << sigma;
  EXPECT_GT(position_error_m(o), 0.0);
}

TEST_F(FilterTask, RunAllocatesNothingAndRepeatsBitForBit) {
  boot(true);
  const std::uint64_t allocs = test_support::count_allocs([] { (void)bsp::run_for(2U * kHz); });
  EXPECT_EQ(allocs, 0U);
  trn::filter::NavOutput first{};
  ASSERT_TRUE(latest_output(kFilterTile, first));
  const std::uint64_t hash = bsp::trace_hash();
  boot(true);
  (void)bsp::run_for(2U * kHz);
  trn::filter::NavOutput second{};
  ASSERT_TRUE(latest_output(kFilterTile, second));
  EXPECT_EQ(bsp::trace_hash(), hash);
  EXPECT_EQ(std::memcmp(&first, &second, sizeof first), 0);
}

TEST(Messages, ImuSampleSurvivesPackingBitForBit) {
  bsp::ImuSample s{};
  s.seq = 77;
  s.status = 0;
  s.t_s = 0.78;
  s.dtheta_rad[1] = -1.0e-7;
  s.dv_mps[2] = 0.0371234567;
  std::array<std::uint32_t, trn::tasks::kImuWords> w{};
  (void)fdir::msg::encode(trn::tasks::kImuMsg, s, w);
  const bsp::ImuSample r = fdir::msg::read(trn::tasks::kImuMsg, w);
  EXPECT_EQ(std::memcmp(&r, &s, sizeof s), 0);
}

}  // namespace
