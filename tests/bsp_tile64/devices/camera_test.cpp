/**
 * @file camera_test.cpp
 * @brief The camera model: pinhole projection, renderer geometry (calibration targets), noise, determinism, DDR ring.
 */
#include "bsp_tile64/devices/camera.hpp"
#include "bsp_tile64/devices/imu.hpp"
#include "bsp_tile64/memory.hpp"
#include "tests/support/heap_probe.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <vector>

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kDeg = kPi / 180.0;

/** A small world for unit tests: 1024 samples at 8 m (8.2 km square), built once per binary. */
bsp::world::TerrainConfig small_terrain(std::uint64_t seed) {
  bsp::world::TerrainConfig c;
  c.seed = seed;
  c.size_px = 1024;
  c.m_per_px = 8.0;
  return c;
}

void use_world(std::uint64_t seed) {
  static std::uint64_t built = 0;
  if (built != seed) {
    ASSERT_EQ(bsp::world::terrain_build(small_terrain(seed)), bsp::world::WorldError::kOk);
    built = seed;
  }
  ASSERT_EQ(bsp::world::terrain_shade(bsp::world::SunAngle{135.0, 35.0}), bsp::world::WorldError::kOk);
}

/** Body attitude from heading, pitch, roll (deg) as the trajectory defines it. */
Eigen::Quaterniond attitude(double yaw_deg, double pitch_deg, double roll_deg) {
  Eigen::Matrix3d ned_to_enu;
  ned_to_enu << 0, 1, 0, 1, 0, 0, 0, 0, -1;
  return Eigen::Quaterniond(ned_to_enu) * Eigen::AngleAxisd(yaw_deg * kDeg, Eigen::Vector3d::UnitZ()) *
         Eigen::AngleAxisd(pitch_deg * kDeg, Eigen::Vector3d::UnitY()) *
         Eigen::AngleAxisd(roll_deg * kDeg, Eigen::Vector3d::UnitX());
}

TEST(CameraProjection, NadirCameraMapsEastToRowsAndNorthToColumnsByHand) {
  // Heading north: body x (columns) points north, body y (rows) east, optical axis down.
  const bsp::CameraModel m = bsp::make_camera(1024, 1024, 90.0);
  const bsp::CameraPose pose{{0.0, 0.0, 1000.0}, attitude(0, 0, 0)};
  const bsp::PixelPoint east = bsp::project(m, pose, {100.0, 0.0, 0.0});
  EXPECT_TRUE(east.in_front);
  EXPECT_NEAR(east.u_px, 511.5, 1e-9);
  EXPECT_NEAR(east.v_px, 511.5 + 512.0 * 0.1, 1e-9);
  const bsp::PixelPoint north = bsp::project(m, pose, {0.0, 200.0, 500.0});
  EXPECT_NEAR(north.u_px, 511.5 + 512.0 * 200.0 / 500.0, 1e-9);
  EXPECT_NEAR(north.v_px, 511.5, 1e-9);
  EXPECT_FALSE(bsp::project(m, pose, {0.0, 0.0, 1200.0}).in_front);
}

TEST(CameraProjection, RandomPosesAndPointsFollowThePinholeEquations) {
  constexpr std::uint64_t kSeed = 20261121;
  bsp::Rng rng(kSeed, bsp::StreamId::kTest);
  bsp::CameraModel m = bsp::make_camera(640, 480, 70.0);
  // A non-trivial mounting: camera tilted 20 deg about body y.
  const Eigen::Matrix3d r_bc = Eigen::AngleAxisd(20.0 * kDeg, Eigen::Vector3d::UnitY()).toRotationMatrix();
  for (int i = 0; i < 9; ++i) {
    m.r_bc[i] = r_bc(i / 3, i % 3);
  }
  for (int k = 0; k < 1000; ++k) {
    const bsp::CameraPose pose{{rng.uniform(-500, 500), rng.uniform(-500, 500), rng.uniform(500, 4000)},
                               attitude(rng.uniform(-180, 180), rng.uniform(-20, 20), rng.uniform(-20, 20))};
    const Eigen::Vector3d p(rng.uniform(-3000, 3000), rng.uniform(-3000, 3000), rng.uniform(-200, 200));
    // Reference: p_C = (R_MB r_bc)^T (p - r), element by element.
    const Eigen::Matrix3d r_mb = pose.q_mb.toRotationMatrix();
    double pc[3] = {0, 0, 0};
    for (int row = 0; row < 3; ++row) {
      for (int j = 0; j < 3; ++j) {
        double r_mc_j_row = 0.0;  // (R_MB r_bc)(j, row)
        for (int l = 0; l < 3; ++l) r_mc_j_row += r_mb(j, l) * r_bc(l, row);
        pc[row] += r_mc_j_row * (p[j] - pose.r_m[j]);
      }
    }
    const bsp::PixelPoint got = bsp::project(m, pose, p);
    ASSERT_EQ(got.in_front, pc[2] > 0.0) << "seed " << kSeed << " draw " << k;
    if (got.in_front) {
      ASSERT_NEAR(got.u_px, m.cx_px + m.fx_px * pc[0] / pc[2], 1e-6) << "seed " << kSeed << " draw " << k;
      ASSERT_NEAR(got.v_px, m.cy_px + m.fy_px * pc[1] / pc[2], 1e-6) << "seed " << kSeed << " draw " << k;
    }
  }
}

class CameraRender : public ::testing::Test {
 protected:
  void SetUp() override {
    use_world(1);
    ASSERT_EQ(bsp::region_reset(bsp::Region{bsp::Region::kDdr}), bsp::MemError::kOk);
  }
  void TearDown() override { EXPECT_EQ(bsp::region_reset(bsp::Region{bsp::Region::kDdr}), bsp::MemError::kOk); }
  std::vector<std::uint8_t> frame_ = std::vector<std::uint8_t>(std::size_t{1024U} * 1024U);
  bsp::CameraModel model_ = bsp::make_camera(1024, 1024, 90.0);
};

/** Weighted centroid of DN above @p floor in a window around (u, v). */
Eigen::Vector2d blob_centroid(const std::vector<std::uint8_t>& f, std::uint32_t w, double u, double v, double floor) {
  double su = 0.0;
  double sv = 0.0;
  double sw = 0.0;
  for (int dv = -15; dv <= 15; ++dv) {
    for (int du = -15; du <= 15; ++du) {
      const long x = std::lround(u) + du;
      const long y = std::lround(v) + dv;
      const double wgt = std::max(0.0, static_cast<double>(f[static_cast<std::size_t>(y * static_cast<long>(w) + x)]) - floor);
      su += wgt * static_cast<double>(x);
      sv += wgt * static_cast<double>(y);
      sw += wgt;
    }
  }
  return sw > 0.0 ? Eigen::Vector2d(su / sw, sv / sw) : Eigen::Vector2d(-1e9, -1e9);
}

TEST_F(CameraRender, CalibrationTargetsAppearWhereTheProjectionSays) {
  // Targets centred on grid nodes (x = (i - 511.5) * 8 m), a 3x3-node disc each, so their
  // bilinear footprint is symmetric about the node: the image centroid is the projected node.
  const bsp::CameraPose pose{{150.0, -80.0, 1500.0}, attitude(40.0, 8.0, -5.0)};
  const int nodes[4][2] = {{560, 500}, {450, 470}, {600, 560}, {470, 580}};
  for (const auto& n : nodes) {
    const double x = (n[0] - 511.5) * 8.0;
    const double y = (n[1] - 511.5) * 8.0;
    ASSERT_EQ(bsp::world::terrain_paint_target(x, y, 12.0, 1.0), bsp::world::WorldError::kOk);
  }
  const bsp::RenderOptions opt{100.0, 0.0, false};
  ASSERT_EQ(bsp::render(model_, pose, opt, frame_.data(), nullptr), bsp::CameraError::kOk);
  for (const auto& n : nodes) {
    const double x = (n[0] - 511.5) * 8.0;
    const double y = (n[1] - 511.5) * 8.0;
    const bsp::PixelPoint p = bsp::project(model_, pose, {x, y, bsp::world::terrain_height_m(x, y)});
    ASSERT_TRUE(p.in_front);
    ASSERT_GT(p.u_px, 20.0);
    ASSERT_LT(p.u_px, 1003.0);
    ASSERT_GT(p.v_px, 20.0);
    ASSERT_LT(p.v_px, 1003.0);
    const Eigen::Vector2d c = blob_centroid(frame_, 1024, p.u_px, p.v_px, 50.0);
    std::printf("target %d,%d: projected (%.2f, %.2f), rendered centroid off by (%.3f, %.3f) px\n", n[0], n[1],
                p.u_px, p.v_px, c.x() - p.u_px, c.y() - p.v_px);
    EXPECT_NEAR(c.x(), p.u_px, 0.1) << "target at node " << n[0] << "," << n[1];
    EXPECT_NEAR(c.y(), p.v_px, 0.1) << "target at node " << n[0] << "," << n[1];
  }
}

TEST_F(CameraRender, NadirFrameIsExposedAndNotEmpty) {
  const bsp::CameraPose pose{{0.0, 0.0, 2500.0}, attitude(30.0, 2.0, 1.0)};
  ASSERT_EQ(bsp::render(model_, pose, bsp::RenderOptions{}, frame_.data(), nullptr), bsp::CameraError::kOk);
  double sum = 0.0;
  double sum2 = 0.0;
  for (const std::uint8_t p : frame_) {
    sum += p;
    sum2 += static_cast<double>(p) * p;
  }
  const double mean = sum / static_cast<double>(frame_.size());
  const double sd = std::sqrt(sum2 / static_cast<double>(frame_.size()) - mean * mean);
  std::printf("nadir frame: mean %.1f DN, sd %.1f DN\n", mean, sd);
  EXPECT_GT(mean, 30.0);
  EXPECT_LT(mean, 200.0);
  EXPECT_GT(sd, 3.0);  // texture: craters and relief
}

TEST_F(CameraRender, ReadNoiseHasItsSigmaAndIsReproducibleFromTheSeed) {
  const bsp::CameraPose pose{{0.0, 0.0, 2500.0}, attitude(0.0, 0.0, 0.0)};
  const bsp::RenderOptions opt{600.0, 4.0, false};
  std::vector<std::uint8_t> again(frame_.size());
  std::vector<std::uint8_t> other(frame_.size());
  bsp::Rng a(3, bsp::StreamId::kSensor, bsp::kCameraStreamIndex);
  bsp::Rng b(3, bsp::StreamId::kSensor, bsp::kCameraStreamIndex);
  bsp::Rng c(4, bsp::StreamId::kSensor, bsp::kCameraStreamIndex);
  ASSERT_EQ(bsp::render(model_, pose, opt, frame_.data(), &a), bsp::CameraError::kOk);
  ASSERT_EQ(bsp::render(model_, pose, opt, again.data(), &b), bsp::CameraError::kOk);
  ASSERT_EQ(bsp::render(model_, pose, opt, other.data(), &c), bsp::CameraError::kOk);
  EXPECT_EQ(frame_, again);
  double sum2 = 0.0;
  std::size_t n = 0;
  for (std::size_t i = 0; i < frame_.size(); ++i) {
    if (frame_[i] > 20U && frame_[i] < 235U && other[i] > 20U && other[i] < 235U) {
      const double d = static_cast<double>(frame_[i]) - static_cast<double>(other[i]);
      sum2 += d * d;
      ++n;
    }
  }
  ASSERT_GT(n, frame_.size() / 2U);
  // Difference of two independent draws: sigma * sqrt(2), plus rounding (1/12 DN^2 each).
  const double sd = std::sqrt(sum2 / static_cast<double>(n));
  EXPECT_NEAR(sd, std::sqrt(2.0 * 16.0 + 2.0 / 12.0), 0.1);
}

TEST_F(CameraRender, BlurSmoothsPixelNoise) {
  // The 3x3 binomial kernel divides the variance of white noise by 64/9 (sigma by ~2.7).
  const bsp::CameraPose pose{{0.0, 0.0, 1200.0}, attitude(0.0, 0.0, 0.0)};
  std::vector<std::uint8_t> blurred(frame_.size());
  bsp::Rng a(5, bsp::StreamId::kSensor, bsp::kCameraStreamIndex);
  bsp::Rng b(5, bsp::StreamId::kSensor, bsp::kCameraStreamIndex);
  ASSERT_EQ(bsp::render(model_, pose, bsp::RenderOptions{600.0, 6.0, false}, frame_.data(), &a),
            bsp::CameraError::kOk);
  ASSERT_EQ(bsp::render(model_, pose, bsp::RenderOptions{600.0, 6.0, true}, blurred.data(), &b),
            bsp::CameraError::kOk);
  auto roughness = [](const std::vector<std::uint8_t>& f) {
    double s = 0.0;
    for (std::size_t i = 1; i < f.size(); ++i) s += std::fabs(static_cast<double>(f[i]) - f[i - 1]);
    return s;
  };
  EXPECT_LT(roughness(blurred), 0.6 * roughness(frame_));
}

TEST_F(CameraRender, AnotherTerrainSeedGivesAnotherFrame) {
  const bsp::CameraPose pose{{0.0, 0.0, 2000.0}, attitude(0.0, 0.0, 0.0)};
  std::vector<std::uint8_t> other(frame_.size());
  ASSERT_EQ(bsp::render(model_, pose, bsp::RenderOptions{}, frame_.data(), nullptr), bsp::CameraError::kOk);
  use_world(2);
  ASSERT_EQ(bsp::render(model_, pose, bsp::RenderOptions{}, other.data(), nullptr), bsp::CameraError::kOk);
  use_world(1);
  std::vector<std::uint8_t> back(frame_.size());
  ASSERT_EQ(bsp::render(model_, pose, bsp::RenderOptions{}, back.data(), nullptr), bsp::CameraError::kOk);
  EXPECT_NE(frame_, other);
  EXPECT_EQ(frame_, back);
}

TEST_F(CameraRender, DeviceCapturesTheTruthPoseIntoItsDdrRing) {
  bsp::world::Trajectory traj;
  bsp::world::TrajectoryConfig tc;
  tc.start_altitude_m = 2500.0;
  ASSERT_EQ(traj.init(tc), bsp::world::WorldError::kOk);
  bsp::CameraConfig cc;
  cc.sun = bsp::world::SunAngle{135.0, 35.0};
  bsp::CameraDevice cam;
  ASSERT_EQ(cam.init(&traj, cc, 9), bsp::CameraError::kOk);
  const std::span<std::byte> ddr = bsp::region_span(bsp::Region{bsp::Region::kDdr});
  const bsp::FrameInfo f0 = cam.capture(1.0);
  const bsp::FrameInfo f1 = cam.capture(2.0);
  const bsp::FrameInfo f2 = cam.capture(3.0);
  ASSERT_EQ(f0.error, bsp::CameraError::kOk);
  ASSERT_EQ(f1.error, bsp::CameraError::kOk);
  EXPECT_EQ(f0.seq, 0U);
  EXPECT_EQ(f2.seq, 2U);
  EXPECT_NE(f0.pixels, f1.pixels);
  EXPECT_EQ(f0.pixels, f2.pixels);  // a ring of two
  const auto* lo = static_cast<const void*>(ddr.data());
  const auto* hi = static_cast<const void*>(ddr.data() + ddr.size());
  EXPECT_GE(static_cast<const void*>(f0.pixels), lo);
  EXPECT_LE(static_cast<const void*>(f1.pixels + frame_.size()), hi);
  // The frame is the render of the truth pose with the device's noise stream.
  const bsp::world::TruthState s = traj.at(3.0);
  bsp::Rng rng(9, bsp::StreamId::kSensor, bsp::kCameraStreamIndex);
  const bsp::RenderOptions opt{cc.exposure_dn, cc.read_noise_dn, cc.blur};
  ASSERT_EQ(bsp::render(cam.model(), {s.r_m, s.q_mb}, opt, frame_.data(), &rng), bsp::CameraError::kOk);
  ASSERT_EQ(bsp::render(cam.model(), {s.r_m, s.q_mb}, opt, frame_.data(), &rng), bsp::CameraError::kOk);
  ASSERT_EQ(bsp::render(cam.model(), {s.r_m, s.q_mb}, opt, frame_.data(), &rng), bsp::CameraError::kOk);
  EXPECT_EQ(std::vector<std::uint8_t>(f2.pixels, f2.pixels + frame_.size()), frame_);
}

TEST_F(CameraRender, CaptureAndImuSamplingNeverTouchTheHeap) {
  bsp::world::Trajectory traj;
  ASSERT_EQ(traj.init(bsp::world::TrajectoryConfig{}), bsp::world::WorldError::kOk);
  bsp::CameraConfig cc;
  cc.blur = true;
  bsp::CameraDevice cam;
  ASSERT_EQ(cam.init(&traj, cc, 1), bsp::CameraError::kOk);
  bsp::ImuModel imu;
  ASSERT_EQ(imu.init(&traj, bsp::ImuErrorConfig{}, 1), bsp::ImuError::kOk);
  bsp::CameraError err = bsp::CameraError::kNotReady;
  std::uint32_t status = 0;
  const std::uint64_t allocs = test_support::count_allocs([&] {
    err = cam.capture(20.0).error;
    for (std::uint32_t k = 0; k < 100; ++k) {
      status |= imu.sample(k).status;
    }
  });
  EXPECT_EQ(err, bsp::CameraError::kOk);
  EXPECT_EQ(status, bsp::kImuStatusOk);
  EXPECT_EQ(allocs, 0U);
}

TEST_F(CameraRender, BadConfigurationsAreRejected) {
  bsp::world::Trajectory traj;
  ASSERT_EQ(traj.init(bsp::world::TrajectoryConfig{}), bsp::world::WorldError::kOk);
  bsp::CameraDevice cam;
  EXPECT_EQ(cam.init(nullptr, bsp::CameraConfig{}, 1), bsp::CameraError::kNoTruth);
  bsp::CameraConfig cc;
  cc.rate_hz = 3.0;
  EXPECT_EQ(cam.init(&traj, cc, 1), bsp::CameraError::kBadConfig);
  cc = bsp::CameraConfig{};
  cc.width_px = bsp::kMaxCameraPx + 1U;
  EXPECT_EQ(cam.init(&traj, cc, 1), bsp::CameraError::kBadConfig);
  EXPECT_EQ(cam.capture(0.0).error, bsp::CameraError::kNotReady);
}

}  // namespace
