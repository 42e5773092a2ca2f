/**
 * @file camera_test.cpp
 * @brief The camera model: pinhole projection, renderer geometry (calibration targets, depth against exact
 *        ray intersections), noise, blur, determinism, DDR ring, frames rendered ahead on a host thread.
 */
#include "bsp_tile64/emu/devices/camera.hpp"
#include "bsp_tile64/emu/devices/imu.hpp"
#include "bsp_tile64/emu/host/frame_ahead.hpp"
#include "bsp_tile64/api/memory.hpp"
#include "tests/support/heap_probe.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
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
    // One draw per statement (or in a braced list): a call's argument order is unspecified.
    const Eigen::Vector3d r{rng.uniform(-500, 500), rng.uniform(-500, 500), rng.uniform(500, 4000)};
    const double yaw = rng.uniform(-180, 180);
    const double pitch = rng.uniform(-20, 20);
    const double roll = rng.uniform(-20, 20);
    const bsp::CameraPose pose{r, attitude(yaw, pitch, roll)};
    const Eigen::Vector3d p{rng.uniform(-3000, 3000), rng.uniform(-3000, 3000), rng.uniform(-200, 200)};
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

/** Map-frame direction of the ray through pixel (u, v), scaled so its camera z is 1 (its parameter is the depth). */
Eigen::Vector3d ray_direction(const bsp::CameraModel& m, const bsp::CameraPose& pose, double u, double v) {
  return bsp::camera_to_map(m, pose) * Eigen::Vector3d((u - m.cx_px) / m.fx_px, (v - m.cy_px) / m.fy_px, 1.0);
}

/** Highest sample of the built terrain, metres. */
double terrain_top_m() {
  const bsp::world::TerrainConfig& c = bsp::world::terrain_config();
  const bsp::world::detail::Cell* cells = bsp::world::detail::cell_data();
  float top = cells[0].height_m;
  for (std::size_t i = 0; i < std::size_t{c.size_px} * c.size_px; ++i) {
    top = std::max(top, cells[i].height_m);
  }
  return static_cast<double>(top);
}

/**
 * Reference for the renderer's depth: the first crossing of the ray r + t d with the bilinear
 * terrain, by a march from the height @p top_m down in steps of 1/50 of a cell, then bisection.
 * -1 where the ray leaves the grid (or never descends) first.
 */
double exact_first_hit(const Eigen::Vector3d& r, const Eigen::Vector3d& d, double top_m) {
  const double half = bsp::world::terrain_half_extent_m();
  const double step = bsp::world::terrain_config().m_per_px / 50.0 / std::max(std::hypot(d.x(), d.y()), 1e-6);
  auto above = [&](double t, bool* inside) {
    const Eigen::Vector3d p = r + t * d;
    *inside = std::fabs(p.x()) <= half && std::fabs(p.y()) <= half;
    return p.z() - bsp::world::terrain_height_m(p.x(), p.y());
  };
  if (d.z() >= 0.0) {
    return -1.0;
  }
  bool inside = true;
  double t0 = std::max(0.0, (top_m + 0.01 - r.z()) / d.z());
  for (double t1 = t0 + step;; t0 = t1, t1 += step) {
    if (above(t1, &inside) <= 0.0) {
      for (int i = 0; i < 60; ++i) {
        const double mid = 0.5 * (t0 + t1);
        bool in_mid = true;
        (above(mid, &in_mid) > 0.0 ? t0 : t1) = mid;
      }
      return inside ? 0.5 * (t0 + t1) : -1.0;
    }
    if (!inside) {
      return -1.0;
    }
  }
}

/** Depth errors of a rendered frame against exact_first_hit() on every @p stride-th pixel (and the last row and column). */
struct DepthCheck {
  std::size_t rays = 0;
  std::size_t over_1cm = 0;
  std::size_t misses_disagree = 0;
  double mean_m = 0.0;
  double max_m = 0.0;
};

DepthCheck check_depth(const bsp::CameraModel& m, const bsp::CameraPose& pose, const std::vector<float>& depth,
                       std::uint32_t stride) {
  const double top = terrain_top_m();
  DepthCheck c;
  auto visit = [&](std::uint32_t u, std::uint32_t v) {
    const double ref = exact_first_hit(pose.r_m, ray_direction(m, pose, u, v), top);
    const double got = depth[std::size_t{v} * m.width_px + u];
    ++c.rays;
    if ((ref < 0.0) != (got < 0.0)) {
      ++c.misses_disagree;
      return;
    }
    if (ref >= 0.0) {
      const double e = std::fabs(got - ref);
      c.mean_m += e;
      c.max_m = std::max(c.max_m, e);
      c.over_1cm += e > 0.01 ? 1U : 0U;
    }
  };
  for (std::uint32_t v = 0; v < m.height_px; v += stride) {
    for (std::uint32_t u = 0; u < m.width_px; u += stride) {
      visit(u, v);
    }
    visit(m.width_px - 1U, v);
  }
  for (std::uint32_t u = 0; u < m.width_px; u += stride) {
    visit(u, m.height_px - 1U);
  }
  c.mean_m /= static_cast<double>(c.rays);
  return c;
}

TEST_F(CameraRender, DepthOfEveryRayIsTheExactFirstHitOnTheBilinearTerrain) {
  // Headings 0 and 90 deg make the renderer walk the image by columns and by rows; an odd-sized
  // frame leaves partial lane groups and strips; the tilted and the low poses see steep slopes
  // obliquely; the narrow camera at 20 km works at the far end of float precision.
  struct Case {
    bsp::CameraModel model;
    bsp::CameraPose pose;
  };
  const Case cases[] = {
      {model_, {{0.0, 0.0, 2500.0}, attitude(0.0, 0.0, 0.0)}},
      {model_, {{300.0, -200.0, 2500.0}, attitude(90.0, 0.0, 0.0)}},
      {bsp::make_camera(1001, 767, 70.0), {{-500.0, 400.0, 1800.0}, attitude(37.0, 3.0, -2.0)}},
      {model_, {{150.0, -80.0, 1500.0}, attitude(128.0, 15.0, -10.0)}},
      {model_, {{-1000.0, 700.0, 600.0}, attitude(250.0, -4.0, 6.0)}},
      {bsp::make_camera(512, 512, 10.0), {{200.0, 100.0, 20000.0}, attitude(60.0, 1.0, 0.5)}},
  };
  for (const Case& k : cases) {
    std::vector<std::uint8_t> frame(std::size_t{k.model.width_px} * k.model.height_px);
    std::vector<float> depth(frame.size(), 0.0F);
    bsp::RenderOptions opt;
    opt.depth_m = depth.data();
    ASSERT_EQ(bsp::render(k.model, k.pose, opt, frame.data(), nullptr), bsp::CameraError::kOk);
    const DepthCheck c = check_depth(k.model, k.pose, depth, 7);
    std::printf("%ux%u at %.0f m: %zu rays, depth error mean %.2e m, max %.2e m, %zu over 1 cm\n", k.model.width_px,
                k.model.height_px, k.pose.r_m.z(), c.rays, c.mean_m, c.max_m, c.over_1cm);
    EXPECT_EQ(c.misses_disagree, 0U);
    // The lanes solve in float: about 1e-7 of the depth, plus the convergence tolerance.
    EXPECT_LT(c.mean_m, 1e-3 + 1e-7 * k.pose.r_m.z());
    // A ray that clips a bump just before its hit may see past it (about one pixel in a million on the
    // descent): allow one such ray in ten thousand.
    EXPECT_LE(c.over_1cm * 10000U, c.rays);
  }
}

TEST_F(CameraRender, RaysLeavingTheGridOrLookingUpAreBlackWithNoDepth) {
  // Near the west edge of the 8.2 km grid, pitched up 60 deg: some rays hit, some leave the grid, some look up.
  const bsp::CameraPose pose{{-3200.0, 0.0, 800.0}, attitude(-90.0, 60.0, 0.0)};
  std::vector<float> depth(frame_.size(), 0.0F);
  bsp::RenderOptions opt;
  opt.depth_m = depth.data();
  ASSERT_EQ(bsp::render(model_, pose, opt, frame_.data(), nullptr), bsp::CameraError::kOk);
  std::size_t hits = 0;
  std::size_t misses = 0;
  for (std::size_t i = 0; i < frame_.size(); ++i) {
    if (depth[i] > 0.0F) {
      ++hits;
    } else {
      ASSERT_EQ(depth[i], -1.0F) << "pixel " << i;
      ASSERT_EQ(frame_[i], 0U) << "pixel " << i;
      ++misses;
    }
  }
  std::printf("edge view: %zu hits, %zu misses\n", hits, misses);
  EXPECT_GT(hits, frame_.size() / 10U);
  EXPECT_GT(misses, frame_.size() / 10U);
  const DepthCheck c = check_depth(model_, pose, depth, 16);
  EXPECT_EQ(c.misses_disagree, 0U);
  EXPECT_LE(c.over_1cm * 10000U, c.rays);
}

TEST_F(CameraRender, BlurIsTheThreeByThreeBinomialKernelOfTheSharpFrame) {
  const bsp::CameraPose pose{{0.0, 0.0, 1200.0}, attitude(20.0, 0.0, 0.0)};
  std::vector<std::uint8_t> blurred(frame_.size());
  bsp::Rng a(7, bsp::StreamId::kSensor, bsp::kCameraStreamIndex);
  bsp::Rng b(7, bsp::StreamId::kSensor, bsp::kCameraStreamIndex);
  ASSERT_EQ(bsp::render(model_, pose, bsp::RenderOptions{600.0, 3.0, false}, frame_.data(), &a), bsp::CameraError::kOk);
  ASSERT_EQ(bsp::render(model_, pose, bsp::RenderOptions{600.0, 3.0, true}, blurred.data(), &b), bsp::CameraError::kOk);
  const long w = 1024;
  auto at = [&](long x, long y) {
    return static_cast<std::uint32_t>(frame_[static_cast<std::size_t>(std::clamp(y, 0L, w - 1) * w + std::clamp(x, 0L, w - 1))]);
  };
  for (long y = 0; y < w; ++y) {
    for (long x = 0; x < w; ++x) {
      const std::uint32_t acc = at(x - 1, y - 1) + 2U * at(x, y - 1) + at(x + 1, y - 1) + 2U * at(x - 1, y) +
                                4U * at(x, y) + 2U * at(x + 1, y) + at(x - 1, y + 1) + 2U * at(x, y + 1) +
                                at(x + 1, y + 1);
      ASSERT_EQ(blurred[static_cast<std::size_t>(y * w + x)], (acc + 8U) / 16U) << "pixel " << x << "," << y;
    }
  }
}

TEST_F(CameraRender, SamePoseAndSeedGiveTheSameBitsWhateverRanBefore) {
  const bsp::CameraPose pose{{120.0, 40.0, 3000.0}, attitude(75.0, 2.0, -3.0)};
  const bsp::RenderOptions opt{600.0, 2.0, false};
  std::vector<std::uint8_t> again(frame_.size());
  std::vector<float> depth_a(frame_.size());
  std::vector<float> depth_b(frame_.size());
  bsp::Rng a(11, bsp::StreamId::kSensor, bsp::kCameraStreamIndex);
  bsp::Rng b(11, bsp::StreamId::kSensor, bsp::kCameraStreamIndex);
  bsp::RenderOptions with_depth = opt;
  with_depth.depth_m = depth_a.data();
  ASSERT_EQ(bsp::render(model_, pose, with_depth, frame_.data(), &a), bsp::CameraError::kOk);
  // Another frame in between (other pose, other line order) leaves nothing behind that the next one reads.
  std::vector<std::uint8_t> other(frame_.size());
  ASSERT_EQ(bsp::render(model_, {{-700.0, 900.0, 1100.0}, attitude(0.0, 10.0, 5.0)}, opt, other.data(), nullptr),
            bsp::CameraError::kOk);
  with_depth.depth_m = depth_b.data();
  ASSERT_EQ(bsp::render(model_, pose, with_depth, again.data(), &b), bsp::CameraError::kOk);
  EXPECT_EQ(frame_, again);
  EXPECT_EQ(0, std::memcmp(depth_a.data(), depth_b.data(), depth_a.size() * sizeof(float)));
}

TEST_F(CameraRender, FourAndEightLaneRenderersGiveTheSameBits) {
  // The lane width follows the host (8 with AVX2); the lanes run the same float operations, so a
  // replay on another host gives the same frames. Row and column line orders, with noise and depth.
  const bsp::CameraPose poses[] = {{{0.0, 0.0, 3000.0}, attitude(10.0, 1.0, 2.0)},
                                   {{-400.0, 250.0, 900.0}, attitude(95.0, -6.0, 4.0)}};
  // Without the 8-lane renderer on this host the comparison would be of 4 lanes with 4 lanes.
#if defined(__x86_64__)
  ASSERT_EQ(bsp::detail::render_lanes(), 8U) << "this x86-64 host has no AVX2: the 8-lane renderer cannot be compared";
#endif
  std::printf("host renderer lanes: %u\n", bsp::detail::render_lanes());
  for (const bsp::CameraPose& pose : poses) {
    std::vector<std::uint8_t> narrow(frame_.size());
    std::vector<float> depth_wide(frame_.size());
    std::vector<float> depth_narrow(frame_.size());
    bsp::Rng a(13, bsp::StreamId::kSensor, bsp::kCameraStreamIndex);
    bsp::Rng b(13, bsp::StreamId::kSensor, bsp::kCameraStreamIndex);
    bsp::RenderOptions opt{600.0, 2.0, false};
    opt.depth_m = depth_wide.data();
    ASSERT_EQ(bsp::render(model_, pose, opt, frame_.data(), &a), bsp::CameraError::kOk);
    bsp::detail::cap_render_lanes(4);
    EXPECT_EQ(bsp::detail::render_lanes(), 4U);
    opt.depth_m = depth_narrow.data();
    const bsp::CameraError err = bsp::render(model_, pose, opt, narrow.data(), &b);
    bsp::detail::cap_render_lanes(0);
    ASSERT_EQ(err, bsp::CameraError::kOk);
    EXPECT_EQ(frame_, narrow);
    EXPECT_EQ(0, std::memcmp(depth_wide.data(), depth_narrow.data(), depth_wide.size() * sizeof(float)));
  }
}

/** The frames a fresh camera (blurred, noisy, seed 4) captures at @p times; prepare() before each at @p announced. */
std::vector<std::vector<std::uint8_t>> capture_series(const bsp::world::Trajectory& traj,
                                                      const std::vector<double>& times,
                                                      const std::vector<double>& announced) {
  bsp::CameraConfig cc;
  cc.blur = true;
  bsp::CameraDevice cam;
  EXPECT_EQ(cam.init(&traj, cc, 4), bsp::CameraError::kOk);
  std::vector<std::vector<std::uint8_t>> out;
  for (std::size_t k = 0; k < times.size(); ++k) {
    if (k < announced.size()) {
      cam.prepare(announced[k]);
    }
    const bsp::FrameInfo f = cam.capture(times[k]);
    EXPECT_EQ(f.error, bsp::CameraError::kOk);
    EXPECT_EQ(f.seq, k);
    out.emplace_back(f.pixels, f.pixels + std::size_t{cc.width_px} * cc.height_px);
  }
  return out;
}

TEST_F(CameraRender, FramesRenderedAheadOnAHostThreadAreTheCapturesBytesAndNoise) {
  bsp::world::Trajectory traj;
  ASSERT_EQ(traj.init(bsp::world::TrajectoryConfig{}), bsp::world::WorldError::kOk);
  const std::vector<double> times = {1.0, 2.0, 3.0, 4.0};
  bsp::frame_ahead::stop();
  const auto at_capture = capture_series(traj, times, times);  // no worker: prepare() does nothing
  ASSERT_TRUE(bsp::frame_ahead::start(std::size_t{1024U} * 1024U));
  // The third frame is announced at the wrong time: it is rendered at its capture instead, and
  // the fourth, rendered ahead again, must start from the noise state the third left.
  const auto ahead = capture_series(traj, times, {1.0, 2.0, 2.5, 4.0});
  const bsp::frame_ahead::Stats st = bsp::frame_ahead::stats();
  EXPECT_EQ(st.taken, 3U);
  EXPECT_EQ(st.missed, 1U);
  ASSERT_EQ(ahead.size(), at_capture.size());
  for (std::size_t k = 0; k < ahead.size(); ++k) {
    EXPECT_TRUE(ahead[k] == at_capture[k]) << "frame " << k;
  }
  // With the worker running, announcing and capturing still never touch the heap.
  bsp::CameraDevice cam;
  ASSERT_EQ(cam.init(&traj, bsp::CameraConfig{}, 1), bsp::CameraError::kOk);
  bsp::CameraError err = bsp::CameraError::kNotReady;
  const std::uint64_t allocs = test_support::count_allocs([&] {
    cam.prepare(20.0);
    err = cam.capture(20.0).error;
  });
  EXPECT_EQ(err, bsp::CameraError::kOk);
  EXPECT_EQ(allocs, 0U);
  EXPECT_EQ(bsp::frame_ahead::stats().taken, 4U);
  bsp::frame_ahead::stop();
  EXPECT_FALSE(bsp::frame_ahead::running());
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
