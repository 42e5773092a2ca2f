/**
 * @file geometry_test.cpp
 * @brief Pose geometry (projection, map-plane homography, lifted points) against the camera device's
 *        pinhole model, the terrain-following warp against direct projection, and template relighting.
 */
#include "bsp_tile64/emu/devices/camera.hpp"
#include "bsp_tile64/emu/rng.hpp"
#include "trn/vision/frame.hpp"
#include "trn/vision/ortho.hpp"
#include "trn/vision/pose_geometry.hpp"

#include <gtest/gtest.h>

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cmath>
#include <cstdint>
#include <vector>

namespace {

namespace tv = trn::vision;

constexpr double kPi = 3.14159265358979323846;
constexpr double kDeg = kPi / 180.0;

/** Body attitude from heading, pitch, roll (deg): body FRD, map ENU (as the trajectory defines it). */
Eigen::Quaterniond attitude(double yaw_deg, double pitch_deg, double roll_deg) {
  Eigen::Matrix3d ned_to_enu;
  ned_to_enu << 0, 1, 0, 1, 0, 0, 0, 0, -1;
  return Eigen::Quaterniond(ned_to_enu) * Eigen::AngleAxisd(yaw_deg * kDeg, Eigen::Vector3d::UnitZ()) *
         Eigen::AngleAxisd(pitch_deg * kDeg, Eigen::Vector3d::UnitY()) *
         Eigen::AngleAxisd(roll_deg * kDeg, Eigen::Vector3d::UnitX());
}

tv::PoseGeometry pose_of(const bsp::CameraModel& cam, const bsp::CameraPose& p) {
  const double r[3] = {p.r_m.x(), p.r_m.y(), p.r_m.z()};
  const double q[4] = {p.q_mb.w(), p.q_mb.x(), p.q_mb.y(), p.q_mb.z()};
  tv::PoseGeometry g;
  bsp::Work work;
  EXPECT_TRUE(tv::make_pose(r, q, cam, g, work));
  return g;
}

/** A camera tilted 20 deg about body y, 640 x 480, 70 deg: nothing symmetric to hide a transposition. */
bsp::CameraModel tilted_camera() {
  bsp::CameraModel m = bsp::make_camera(640, 480, 70.0);
  m.fy_px *= 1.01;
  m.cx_px += 3.25;
  m.cy_px -= 1.5;
  const Eigen::Matrix3d r_bc = Eigen::AngleAxisd(20.0 * kDeg, Eigen::Vector3d::UnitY()).toRotationMatrix();
  for (int i = 0; i < 9; ++i) {
    m.r_bc[i] = r_bc(i / 3, i % 3);
  }
  return m;
}

TEST(PoseGeometry, ProjectionEqualsTheCameraDeviceForRandomPosesAndPoints) {
  constexpr std::uint64_t kSeed = 7101;
  bsp::Rng rng(kSeed, bsp::StreamId::kTest);
  const bsp::CameraModel m = tilted_camera();
  int in_front = 0;
  for (int k = 0; k < 1000; ++k) {
    // One draw per statement (or in a braced list): a call's argument order is unspecified.
    const Eigen::Vector3d r{rng.uniform(-500, 500), rng.uniform(-500, 500), rng.uniform(500, 4000)};
    const double yaw = rng.uniform(-180, 180);
    const double pitch = rng.uniform(-20, 20);
    const double roll = rng.uniform(-20, 20);
    const bsp::CameraPose pose{r, attitude(yaw, pitch, roll)};
    const Eigen::Vector3d p{rng.uniform(-3000, 3000), rng.uniform(-3000, 3000), rng.uniform(-200, 200)};
    const double pm[3] = {p.x(), p.y(), p.z()};
    const bsp::PixelPoint ref = bsp::project(m, pose, p);
    double u = 0.0;
    double v = 0.0;
    double z = 0.0;
    bsp::Work work;
    const bool ok = tv::project_point(m, pose_of(m, pose), pm, u, v, &z, work);
    ASSERT_EQ(ok, ref.in_front && z > 1e-3) << "seed " << kSeed << " draw " << k;
    if (ok) {
      ++in_front;
      ASSERT_NEAR(u, ref.u_px, 1e-7) << "seed " << kSeed << " draw " << k;
      ASSERT_NEAR(v, ref.v_px, 1e-7) << "seed " << kSeed << " draw " << k;
      // The pixel's ray points back at the point.
      double w[3];
      tv::pixel_ray(m, u, v, w, work);
      const Eigen::Vector3d pc = bsp::camera_to_map(m, pose).transpose() * (p - pose.r_m);
      ASSERT_NEAR(std::hypot(std::hypot(w[0], w[1]), w[2]), 1.0, 1e-12);
      ASSERT_NEAR(w[0] * pc.z() - w[2] * pc.x(), 0.0, 1e-9 * pc.norm());
      ASSERT_NEAR(w[1] * pc.z() - w[2] * pc.y(), 0.0, 1e-9 * pc.norm());
      ASSERT_GT(work.flops, 0U);
    }
  }
  EXPECT_GT(in_front, 300) << "seed " << kSeed;
}

TEST(PoseGeometry, PlaneHomographyMapsGridPixelsWhereTheCameraProjectsTheirPoints) {
  constexpr std::uint64_t kSeed = 7102;
  bsp::Rng rng(kSeed, bsp::StreamId::kTest);
  const bsp::CameraModel m = tilted_camera();
  for (int k = 0; k < 200; ++k) {
    // One draw per statement (or in a braced list): a call's argument order is unspecified.
    const Eigen::Vector3d r{rng.uniform(-500, 500), rng.uniform(-500, 500), rng.uniform(1000, 4000)};
    const double yaw = rng.uniform(-180, 180);
    const double pitch = rng.uniform(-10, 10);
    const double roll = rng.uniform(-10, 10);
    const bsp::CameraPose pose{r, attitude(yaw, pitch, roll)};
    tv::PlaneGrid grid;
    grid.origin_m[0] = rng.uniform(-800, 800);
    grid.origin_m[1] = rng.uniform(-800, 800);
    grid.origin_m[2] = rng.uniform(-100, 100);
    grid.m_per_px = rng.uniform(2.0, 12.0);
    const tv::PoseGeometry g = pose_of(m, pose);
    bsp::Work work;
    const trn::vision::Homography h = tv::plane_homography(m, g, grid, work);
    double lift[3];
    tv::vertical_column(m, g, lift);
    for (int j = 0; j < 5; ++j) {
      const double x = rng.uniform(-20, 80);
      const double y = rng.uniform(-20, 80);
      const double dz = rng.uniform(-60, 60);
      // Grid pixel (x, y): east with x, south with y, at the plane's height (+ dz when lifted).
      const Eigen::Vector3d p(grid.origin_m[0] + x * grid.m_per_px, grid.origin_m[1] - y * grid.m_per_px,
                              grid.origin_m[2]);
      const bsp::PixelPoint ref = bsp::project(m, pose, p);
      const bsp::PixelPoint ref_up = bsp::project(m, pose, p + Eigen::Vector3d(0, 0, dz));
      double u = 0.0;
      double v = 0.0;
      ASSERT_EQ(tv::apply_homography(h, x, y, u, v), ref.in_front) << "seed " << kSeed << " draw " << k;
      if (ref.in_front) {
        ASSERT_NEAR(u, ref.u_px, 1e-6) << "seed " << kSeed << " draw " << k;
        ASSERT_NEAR(v, ref.v_px, 1e-6) << "seed " << kSeed << " draw " << k;
      }
      ASSERT_EQ(tv::apply_lifted(h, lift, dz, x, y, u, v), ref_up.in_front) << "seed " << kSeed << " draw " << k;
      if (ref_up.in_front) {
        ASSERT_NEAR(u, ref_up.u_px, 1e-6) << "seed " << kSeed << " draw " << k;
        ASSERT_NEAR(v, ref_up.v_px, 1e-6) << "seed " << kSeed << " draw " << k;
      }
      // Scale: the largest stretch of a small step, by finite differences.
      if (ref.in_front) {
        const double s = tv::homography_scale(h, x, y, work);
        double best = 0.0;
        for (int a = 0; a < 360; a += 5) {
          const double e = 1e-4;
          double u1 = 0.0;
          double v1 = 0.0;
          double u0 = 0.0;
          double v0 = 0.0;
          tv::apply_homography(h, x + e * std::cos(a * kDeg), y + e * std::sin(a * kDeg), u1, v1);
          tv::apply_homography(h, x - e * std::cos(a * kDeg), y - e * std::sin(a * kDeg), u0, v0);
          best = std::max(best, std::hypot(u1 - u0, v1 - v0) / (2 * e));
        }
        ASSERT_NEAR(s, best, 2e-3 * best + 1e-6) << "seed " << kSeed << " draw " << k;
      }
    }
  }
}

TEST(PoseGeometry, BadCamerasAndPosesAreRefused) {
  bsp::CameraModel m = bsp::make_camera(1024, 1024, 90.0);
  EXPECT_TRUE(tv::camera_ok(m));
  bsp::CameraModel bad = m;
  bad.fx_px = 0.0;
  EXPECT_FALSE(tv::camera_ok(bad));
  bad = m;
  bad.width_px = 0;
  EXPECT_FALSE(tv::camera_ok(bad));
  bad = m;
  bad.r_bc[0] = 2.0;  // not a rotation
  EXPECT_FALSE(tv::camera_ok(bad));
  bad = m;
  bad.cy_px = std::nan("");
  EXPECT_FALSE(tv::camera_ok(bad));
  const double p[3] = {0, 0, 1000};
  const double q0[4] = {0, 0, 0, 0};
  const double qn[4] = {std::nan(""), 0, 0, 1};
  const double qs[4] = {0, 0, 0, 3};  // not unit: normalised, accepted
  tv::PoseGeometry g;
  bsp::Work work;
  EXPECT_FALSE(tv::make_pose(p, q0, m, g, work));
  EXPECT_FALSE(tv::make_pose(p, qn, m, g, work));
  EXPECT_TRUE(tv::make_pose(p, qs, m, g, work));
  // q = (0, 0, 0, 1): 180 deg about z; camera = body.
  EXPECT_NEAR(g.r_mc[0], -1.0, 1e-12);
  EXPECT_NEAR(g.r_mc[4], -1.0, 1e-12);
  EXPECT_NEAR(g.r_mc[8], 1.0, 1e-12);
}

TEST(Ortho, TerrainWarpSamplesWhereTheCameraSeesEachLiftedPixel) {
  // Source: a frame whose value encodes its column (so a sample tells where it was taken).
  const bsp::CameraModel m = tilted_camera();
  std::vector<std::uint8_t> src(640U * 480U);
  for (std::size_t y = 0; y < 480; ++y)
    for (std::size_t x = 0; x < 640; ++x) src[y * 640 + x] = static_cast<std::uint8_t>((x * 255) / 639);
  const tv::ConstImageU8 sv{src.data(), 640, 480, 640};
  const bsp::CameraPose pose{{10.0, -20.0, 2500.0}, attitude(35, 2, -3)};
  const tv::PoseGeometry g = pose_of(m, pose);
  tv::PlaneGrid grid;
  grid.origin_m[0] = -300.0;
  grid.origin_m[1] = 200.0;
  grid.origin_m[2] = 15.0;
  grid.m_per_px = 6.0;
  bsp::Work work;
  const trn::vision::Homography h = tv::plane_homography(m, g, grid, work);
  double lift[3];
  tv::vertical_column(m, g, lift);
  constexpr std::int32_t kSide = 40;
  std::vector<std::int16_t> heights(kSide * kSide);
  bsp::Rng rng(7103, bsp::StreamId::kTest);
  for (auto& e : heights) e = static_cast<std::int16_t>(rng.uniform(-800, 1200));  // -80..120 m
  tv::GridHeights gh{heights.data(), kSide, 0.1, grid.origin_m[2]};
  std::vector<std::uint8_t> dst(kSide * kSide);
  std::int32_t outside = -1;
  ASSERT_EQ(tv::warp_terrain(sv, h, lift, gh, 1, tv::ImageU8{dst.data(), kSide, kSide, kSide}, 0, outside, work),
            tv::Status::kOk);
  EXPECT_EQ(outside, 0);
  for (std::int32_t y = 0; y < kSide; ++y) {
    for (std::int32_t x = 0; x < kSide; ++x) {
      const Eigen::Vector3d p(grid.origin_m[0] + x * 6.0, grid.origin_m[1] - y * 6.0,
                              heights[static_cast<std::size_t>(y * kSide + x)] * 0.1);
      const bsp::PixelPoint ref = bsp::project(m, pose, p);
      std::uint8_t want = 0;
      ASSERT_TRUE(tv::sample_bilinear(sv, ref.u_px, ref.v_px, want));
      ASSERT_NEAR(dst[static_cast<std::size_t>(y * kSide + x)], want, 1) << x << "," << y;
    }
  }
  // Sub-sampling averages over the pixel's footprint: on a linear ramp the mean is the centre value.
  std::vector<std::uint8_t> dst3(kSide * kSide);
  ASSERT_EQ(tv::warp_terrain(sv, h, lift, gh, 3, tv::ImageU8{dst3.data(), kSide, kSide, kSide}, 0, outside, work),
            tv::Status::kOk);
  for (std::size_t i = 0; i < dst.size(); ++i) ASSERT_NEAR(dst3[i], dst[i], 1) << i;
  // Bad inputs.
  EXPECT_EQ(tv::warp_terrain(sv, h, lift, gh, 0, tv::ImageU8{dst.data(), kSide, kSide, kSide}, 0, outside, work),
            tv::Status::kBadInput);
  EXPECT_EQ(tv::warp_terrain(sv, h, lift, tv::GridHeights{}, 1, tv::ImageU8{dst.data(), kSide, kSide, kSide}, 0,
                             outside, work),
            tv::Status::kBadInput);
}

TEST(Relight, MapShadingUnderOneSunIsTurnedIntoShadingUnderAnother) {
  // A map of a tilted plane plus a bump, constant albedo 0.5, shaded by the same Lambert law as the world.
  constexpr std::int32_t kN = 64;
  std::vector<std::int16_t> elev(kN * kN);
  std::vector<std::uint8_t> img(kN * kN);
  std::vector<std::uint8_t> want(kN * kN);
  double sun_map[3];
  double sun_new[3];
  tv::sun_direction(250.0, 50.0, sun_map);
  tv::sun_direction(135.0, 35.0, sun_new);
  EXPECT_NEAR(sun_new[0], std::sin(135 * kDeg) * std::cos(35 * kDeg), 1e-12);  // east
  EXPECT_NEAR(sun_new[1], std::cos(135 * kDeg) * std::cos(35 * kDeg), 1e-12);  // north
  const double s = 6.0;
  auto height = [](double x, double y) { return 0.15 * x - 0.1 * y + 20.0 * std::exp(-((x - 190) * (x - 190) + (y - 200) * (y - 200)) / 3000.0); };
  for (std::int32_t r = 0; r < kN; ++r)
    for (std::int32_t c = 0; c < kN; ++c)
      elev[static_cast<std::size_t>(r * kN + c)] = static_cast<std::int16_t>(std::lround(height(c * s, -r * s) * 10.0));
  auto shade = [&](std::int32_t c, std::int32_t r, const double* sun) {
    const double gx = (elev[static_cast<std::size_t>(r * kN + c + 1)] - elev[static_cast<std::size_t>(r * kN + c - 1)]) * 0.1 / (2 * s);
    const double gy = (elev[static_cast<std::size_t>((r - 1) * kN + c)] - elev[static_cast<std::size_t>((r + 1) * kN + c)]) * 0.1 / (2 * s);
    return std::max(0.0, (-gx * sun[0] - gy * sun[1] + sun[2]) / std::sqrt(gx * gx + gy * gy + 1));
  };
  for (std::int32_t r = 1; r < kN - 1; ++r)
    for (std::int32_t c = 1; c < kN - 1; ++c) {
      img[static_cast<std::size_t>(r * kN + c)] = static_cast<std::uint8_t>(std::lround(250.0 * shade(c, r, sun_map)));
      want[static_cast<std::size_t>(r * kN + c)] = static_cast<std::uint8_t>(std::lround(250.0 * shade(c, r, sun_new)));
    }
  tv::MapView map;
  map.image = tv::ConstImageU8{img.data(), kN, kN, kN};
  map.elevation = elev.data();
  map.elevation_scale_m = 0.1;
  map.geo = tv::MapGeometry{s, 0.0, 0.0};
  for (int k = 0; k < 3; ++k) map.sun_m[k] = sun_map[k];
  std::vector<std::uint8_t> out(40 * 40);
  bsp::Work work;
  ASSERT_EQ(tv::relight_region(map, 12, 12, sun_new, tv::ImageU8{out.data(), 40, 40, 40}, work), tv::Status::kOk);
  double max_err = 0.0;
  for (std::int32_t r = 0; r < 40; ++r)
    for (std::int32_t c = 0; c < 40; ++c)
      max_err = std::max(max_err, std::fabs(static_cast<double>(out[static_cast<std::size_t>(r * 40 + c)]) -
                                            want[static_cast<std::size_t>((r + 12) * kN + c + 12)]));
  EXPECT_LE(max_err, 2.0);  // two roundings of DN
  EXPECT_GT(work.flops, 0U);
  // Refused: unknown map sun, a region outside the map, no elevation.
  tv::MapView no_sun = map;
  no_sun.sun_m[0] = no_sun.sun_m[1] = no_sun.sun_m[2] = 0.0;
  EXPECT_EQ(tv::relight_region(no_sun, 12, 12, sun_new, tv::ImageU8{out.data(), 40, 40, 40}, work),
            tv::Status::kBadInput);
  EXPECT_EQ(tv::relight_region(map, 30, 12, sun_new, tv::ImageU8{out.data(), 40, 40, 40}, work),
            tv::Status::kBadInput);
  tv::MapView no_elev = map;
  no_elev.elevation = nullptr;
  EXPECT_EQ(tv::relight_region(no_elev, 12, 12, sun_new, tv::ImageU8{out.data(), 40, 40, 40}, work),
            tv::Status::kBadInput);
}

}  // namespace
