/**
 * @file device_bus_test.cpp
 * @brief The devices deliver through the I/O tile's FIFOs at exact cycles: IMU samples every
 *        10 ms, frames at capture time plus readout, each with Irq::kDevice, read by a kernel task.
 */
#include "bsp_tile64/emu/board.hpp"
#include "bsp_tile64/emu/devices/device_bus.hpp"
#include "bsp_tile64/world/terrain.hpp"
#include "bsp_tile64/world/trajectory.hpp"
#include "kernel/kernel.hpp"

#include <gtest/gtest.h>

#include <array>
#include <cstring>

namespace {

constexpr bsp::TileId kIo = 3;
constexpr bsp::Cycles kHz = bsp::kTile64.clock_hz;

struct Seen {
  std::array<bsp::ImuSample, 256> imu{};
  std::array<bsp::Cycles, 256> imu_cycle{};
  std::uint32_t imu_count = 0;
  std::array<bsp::FrameRecord, 4> frame{};
  std::array<bsp::Cycles, 4> frame_cycle{};
  std::uint32_t frame_count = 0;
};
Seen g_seen;
k::Semaphore g_ready{0, 1000};

void device_isr(bsp::TileId /*tile*/) { (void)g_ready.give_from_isr(); }

void io_driver(void*) {
  if (k::set_isr(bsp::Irq::kDevice, &device_isr) != k::Status::kOk) {
    return;
  }
  for (;;) {
    (void)g_ready.take(k::kForever);
    bsp::ImuSample s{};
    while (bsp::imu_read(&s) && g_seen.imu_count < g_seen.imu.size()) {
      g_seen.imu_cycle[g_seen.imu_count] = bsp::now();
      g_seen.imu[g_seen.imu_count++] = s;
    }
    bsp::FrameRecord f{};
    while (bsp::frame_read(&f) && g_seen.frame_count < g_seen.frame.size()) {
      g_seen.frame_cycle[g_seen.frame_count] = bsp::now();
      g_seen.frame[g_seen.frame_count++] = f;
    }
  }
}

constexpr k::TaskSpec kIoTable[] = {
    {"io", &io_driver, nullptr, 1, 0, 0, 32U * 1024U, k::Policy::kPreemptive},
};

/** The cross-strap's second attachment. */
constexpr bsp::TileId kBackup = 5;
bsp::DeviceSelect g_select{};

/** A driver on the backup: takes the devices over, then reads like the prime's. */
void backup_driver(void* arg) {
  g_select = bsp::devices_select();
  io_driver(arg);
}

constexpr k::TaskSpec kBackupTable[] = {
    {"io", &backup_driver, nullptr, 1, 0, 0, 32U * 1024U, k::Policy::kPreemptive},
};

class DeviceBus : public ::testing::Test {
 protected:
  void SetUp() override {
    // Other suites of this binary build terrains of other seeds: rebuild only when needed.
    static bool built = false;
    if (!built || bsp::world::terrain_config().seed != 5U) {
      bsp::world::TerrainConfig tc;
      tc.seed = 5;
      tc.size_px = 1024;
      tc.m_per_px = 8.0;
      ASSERT_EQ(bsp::world::terrain_build(tc), bsp::world::WorldError::kOk);
      built = true;
    }
    ASSERT_EQ(traj_.init(bsp::world::TrajectoryConfig{}), bsp::world::WorldError::kOk);
    ASSERT_EQ(imu_.init(&traj_, bsp::ImuErrorConfig{}, 11), bsp::ImuError::kOk);
    bsp::CameraConfig cc;
    cc.width_px = 64;
    cc.height_px = 64;
    ASSERT_EQ(cam_.init(&traj_, cc, 12), bsp::CameraError::kOk);
    bsp::BoardConfig cfg = bsp::default_config(bsp::kTile64);
    cfg.powered_at_start = 1ULL << kIo;
    cfg.monitor_tile = bsp::kNoTile;
    cfg.boot[kIo] = &k::boot_entry;
    cfg.boot[kBackup] = &k::boot_entry;
    k::set_task_table(kIo, kIoTable, bsp::kTile64.cycles_per_ms());
    k::set_task_table(kBackup, kBackupTable, bsp::kTile64.cycles_per_ms());
    g_select = bsp::DeviceSelect{};
    ASSERT_EQ(bsp::board_init(cfg), bsp::BoardError::kOk);
    g_seen = Seen{};
  }
  bsp::world::Trajectory traj_;
  bsp::ImuModel imu_;
  bsp::CameraDevice cam_;
};

TEST_F(DeviceBus, ImuSamplesArriveEveryTenMillisecondsAtTheirExactCycle) {
  bsp::DeviceBusConfig bus;
  bus.io_tile = kIo;
  bus.imu = &imu_;
  ASSERT_EQ(bsp::attach_devices(bus), bsp::DeviceBusError::kOk);
  (void)bsp::run_for(kHz / 2U + kHz / 1000U);  // 0.501 s: samples 0..49
  ASSERT_EQ(g_seen.imu_count, 50U);
  // The same model, same seed, sampled directly: the FIFO passed every bit through.
  bsp::ImuModel ref;
  ASSERT_EQ(ref.init(&traj_, bsp::ImuErrorConfig{}, 11), bsp::ImuError::kOk);
  for (std::uint32_t i = 0; i < g_seen.imu_count; ++i) {
    EXPECT_EQ(g_seen.imu[i].seq, i);
    EXPECT_EQ(g_seen.imu_cycle[i], (i + 1U) * (kHz / 100U)) << "sample " << i;
    const bsp::ImuSample r = ref.sample(i);
    EXPECT_EQ(std::memcmp(&r, &g_seen.imu[i], sizeof r), 0) << "sample " << i;
  }
  const bsp::DeviceStats st = bsp::device_stats();
  EXPECT_EQ(st.imu_delivered, 50U);
  EXPECT_EQ(st.imu_dropped, 0U);
  EXPECT_EQ(bsp::io_tile(), kIo);
}

TEST_F(DeviceBus, FramesAreReadyAfterTheirReadoutDelay) {
  bsp::DeviceBusConfig bus;
  bus.io_tile = kIo;
  bus.camera = &cam_;
  bus.first_frame_s = 1.0;
  bus.frame_readout_s = 0.02;
  ASSERT_EQ(bsp::attach_devices(bus), bsp::DeviceBusError::kOk);
  (void)bsp::run_for(2U * kHz + kHz / 10U);  // 2.1 s: frames at 1.0 and 2.0 s
  ASSERT_EQ(g_seen.frame_count, 2U);
  for (std::uint32_t i = 0; i < 2U; ++i) {
    EXPECT_EQ(g_seen.frame[i].seq, i);
    EXPECT_DOUBLE_EQ(g_seen.frame[i].t_s, 1.0 + i);
    EXPECT_EQ(g_seen.frame[i].status, 0U);
    EXPECT_EQ(g_seen.frame[i].width_px, 64U);
    EXPECT_EQ(g_seen.frame_cycle[i], static_cast<bsp::Cycles>((1.02 + i) * static_cast<double>(kHz) + 0.5));
    EXPECT_NE(g_seen.frame[i].pixels, nullptr);
  }
}

TEST_F(DeviceBus, AFullFifoDropsAndCountsInsteadOfOverwriting) {
  // Nobody reads: power the I/O tile off so its driver never runs.
  ASSERT_EQ(bsp::power_off(kIo), bsp::BoardError::kOk);
  bsp::DeviceBusConfig bus;
  bus.io_tile = kIo;
  bus.imu = &imu_;
  ASSERT_EQ(bsp::attach_devices(bus), bsp::DeviceBusError::kOk);
  (void)bsp::run_for(kHz / 2U + kHz / 1000U);
  const bsp::DeviceStats st = bsp::device_stats();
  EXPECT_EQ(st.imu_delivered, bsp::kImuFifoDepth);
  EXPECT_EQ(st.imu_dropped, 50U - bsp::kImuFifoDepth);
  bsp::ImuSample s{};
  ASSERT_TRUE(bsp::imu_read(&s));
  EXPECT_EQ(s.seq, 0U) << "the oldest samples are kept";
}

TEST_F(DeviceBus, TheCrossStrapSelectMovesTheDevicesToTheBackupAndCountsWhatWasLeft) {
  // The prime dies before its driver reads anything: its IMU FIFO fills and then drops.
  ASSERT_EQ(bsp::power_off(kIo), bsp::BoardError::kOk);
  bsp::DeviceBusConfig bus;
  bus.io_tile = kIo;
  bus.backup_tile = kBackup;
  bus.imu = &imu_;
  ASSERT_EQ(bsp::attach_devices(bus), bsp::DeviceBusError::kOk);
  EXPECT_EQ(bsp::io_tile(), kIo) << "the prime is selected at attach";
  EXPECT_EQ(bsp::devices_select().result, bsp::SelectResult::kNotWired) << "the host is no attachment";
  (void)bsp::run_for(kHz / 2U + kHz / 1000U);  // samples 0..49: 32 held by the prime, 18 dropped
  ASSERT_EQ(g_seen.imu_count, 0U);
  // The backup starts: its driver sets the select to its own tile.
  ASSERT_EQ(bsp::power_on(kBackup), bsp::BoardError::kOk);
  (void)bsp::run_for(kHz / 2U);  // to 1.001 s
  EXPECT_EQ(g_select.result, bsp::SelectResult::kSelected);
  EXPECT_EQ(g_select.from, kIo);
  EXPECT_EQ(g_select.imu_stranded, bsp::kImuFifoDepth);
  EXPECT_EQ(bsp::io_tile(), kBackup);
  const bsp::DeviceStats st = bsp::device_stats();
  EXPECT_EQ(st.selects, 1U);
  EXPECT_EQ(st.imu_stranded, bsp::kImuFifoDepth);
  EXPECT_EQ(st.imu_dropped, 50U - bsp::kImuFifoDepth);
  // Every sample from the select on reached the backup, in order, none twice.
  ASSERT_GT(g_seen.imu_count, 40U);
  for (std::uint32_t i = 1; i < g_seen.imu_count; ++i) {
    EXPECT_EQ(g_seen.imu[i].seq, g_seen.imu[0].seq + i);
  }
  EXPECT_EQ(g_seen.imu[g_seen.imu_count - 1U].seq, 99U);
  EXPECT_EQ(st.imu_delivered, bsp::kImuFifoDepth + g_seen.imu_count);
}

TEST_F(DeviceBus, BadConfigurationIsRefused) {
  bsp::DeviceBusConfig bus;
  bus.io_tile = 200;
  EXPECT_EQ(bsp::attach_devices(bus), bsp::DeviceBusError::kBadConfig);
  bus.io_tile = kIo;
  bus.backup_tile = kIo;  // the backup is another tile
  EXPECT_EQ(bsp::attach_devices(bus), bsp::DeviceBusError::kBadConfig);
  bus.backup_tile = 200;
  EXPECT_EQ(bsp::attach_devices(bus), bsp::DeviceBusError::kBadConfig);
  bus.backup_tile = bsp::kNoTile;
  bus.io_tile = kIo;
  bus.camera = &cam_;
  bus.frame_readout_s = 1.5;  // longer than the frame period
  EXPECT_EQ(bsp::attach_devices(bus), bsp::DeviceBusError::kBadConfig);
}

}  // namespace
