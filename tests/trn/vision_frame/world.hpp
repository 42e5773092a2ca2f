/**
 * @file world.hpp
 * @brief Test helper: a rendered world for the per-frame vision tests (terrain, map product, landmarks, frames).
 *
 * The world is a process-wide singleton, so one World is live at a time:
 * World::use(seed) rebuilds it only when the seed changes (terrain, map
 * product in DDR, descent shading, landmark table), which takes a few seconds
 * with the default 4096^2 terrain. Truth is used here only to render frames
 * and to score the results; the code under test sees the frame, the map
 * product, the camera model and a prior.
 */
#pragma once

#include "build_dirs.hpp"

#include "bsp_tile64/emu/devices/camera.hpp"
#include "bsp_tile64/api/memory.hpp"
#include "bsp_tile64/emu/rng.hpp"
#include "bsp_tile64/world/refmap.hpp"
#include "bsp_tile64/world/terrain.hpp"
#include "bsp_tile64/world/trajectory.hpp"
#include "trn/vision/frame.hpp"
#include "trn/vision/ortho.hpp"
#include "tools/common/mission/world_cache.hpp"

#include <gtest/gtest.h>

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <map>
#include <cstdint>
#include <string>
#include <vector>

namespace frame_test {

namespace tv = trn::vision;

constexpr double kPi = 3.14159265358979323846;
constexpr double kDeg = kPi / 180.0;

/** The world of one seed: map product views, the fine layer's landmarks, the default descent. */
struct World {
  std::uint64_t seed = 0;
  const bsp::MapProductHeader* product = nullptr;
  tv::MapView fine{};
  tv::MapView coarse{};
  tv::MapView coarse_lit{};  ///< the coarse layer relit to the descent sun
  std::vector<std::uint8_t> coarse_relit;
  bsp::world::Trajectory traj;
  bsp::CameraModel cam = bsp::make_camera(1024, 1024, 90.0);
  tv::LandmarkTable* table = nullptr;
  std::map<std::int64_t, std::vector<std::uint8_t>> frames;  ///< rendered frames by altitude

  /** Builds (or keeps) the world of @p s; fails the calling test on any error. */
  static World& use(std::uint64_t s) {
    static World w;
    static tv::LandmarkTable table;
    if (w.seed != s || w.product == nullptr) {
      w = World{};
      w.table = &table;
      w.build(s);
    }
    return w;
  }

  /** Time at which the default descent passes altitude @p z_m (bisection). */
  double time_at_altitude(double z_m) const {
    double lo = 0.0;
    double hi = traj.duration_s();
    for (int k = 0; k < 60; ++k) {
      const double mid = 0.5 * (lo + hi);
      (traj.at(mid).r_m.z() > z_m ? lo : hi) = mid;
    }
    return 0.5 * (lo + hi);
  }

  /** Truth pose of the default descent where it passes altitude @p z_m. */
  bsp::CameraPose truth_at(double z_m, double* t_s = nullptr) const {
    const double t = time_at_altitude(z_m);
    if (t_s != nullptr) {
      *t_s = t;
    }
    const bsp::world::TruthState s = traj.at(t);
    return bsp::CameraPose{s.r_m, s.q_mb};
  }

  /** The frame rendered at altitude @p z_m of the descent (cached: rendering takes ~0.3 s). */
  const std::vector<std::uint8_t>& frame_at(double z_m) {
    const auto key = static_cast<std::int64_t>(std::lround(z_m));
    auto it = frames.find(key);
    if (it == frames.end()) {
      it = frames.emplace(key, render(truth_at(z_m), seed * 1000U + static_cast<std::uint64_t>(key))).first;
    }
    return it->second;
  }

  /** Renders the truth pose @p pose with 2 DN read noise (stream from @p noise_seed). */
  std::vector<std::uint8_t> render(const bsp::CameraPose& pose, std::uint64_t noise_seed) const {
    std::vector<std::uint8_t> f(std::size_t{cam.width_px} * cam.height_px);
    bsp::Rng rng(noise_seed, bsp::StreamId::kSensor, bsp::kCameraStreamIndex);
    bsp::RenderOptions opt;
    opt.exposure_dn = 600.0;
    opt.read_noise_dn = 2.0;
    EXPECT_EQ(bsp::render(cam, pose, opt, f.data(), &rng), bsp::CameraError::kOk);
    return f;
  }

  tv::ConstImageU8 view(const std::vector<std::uint8_t>& f) const {
    return {f.data(), static_cast<std::int32_t>(cam.width_px), static_cast<std::int32_t>(cam.height_px),
            static_cast<std::int32_t>(cam.width_px)};
  }

 private:
  void build(std::uint64_t s) {
    bsp::world::TerrainConfig tc;
    tc.seed = s;
    // Built once, then read from a cache of this program's own (the cache keys a world by the program).
    tools::WorldCache cache(std::string(build_info::kBinDir) + "/test-world-cache-vision-frame");
    std::string why;
    ASSERT_TRUE(cache.terrain(tc, why)) << why;
    ASSERT_EQ(bsp::region_reset(bsp::Region{bsp::Region::kDdr}), bsp::MemError::kOk);
    bsp::world::WorldError err = bsp::world::WorldError::kNotBuilt;
    product = cache.map(tc, bsp::world::MapConfig{}, err);
    ASSERT_EQ(err, bsp::world::WorldError::kOk);
    ASSERT_NE(product, nullptr);
    ASSERT_EQ(bsp::world::terrain_shade(bsp::CameraConfig{}.sun), bsp::world::WorldError::kOk);
    ASSERT_EQ(traj.init(bsp::world::TrajectoryConfig{}), bsp::world::WorldError::kOk);
    ASSERT_EQ(tv::map_view(product, bsp::kMapLayerFine, fine), tv::Status::kOk);
    ASSERT_EQ(tv::map_view(product, bsp::kMapLayerCoarse, coarse), tv::Status::kOk);
    // The descent sun is mission knowledge: the camera's (CameraConfig default).
    const bsp::world::SunAngle sun = bsp::CameraConfig{}.sun;
    tv::sun_direction(sun.azimuth_deg, sun.elevation_deg, fine.descent_sun_m);
    tv::sun_direction(sun.azimuth_deg, sun.elevation_deg, coarse.descent_sun_m);
    // The coarse layer relit to the descent sun (in flight: once at init, into DDR).
    coarse_relit.assign(static_cast<std::size_t>(coarse.image.width) * static_cast<std::size_t>(coarse.image.height), 0);
    bsp::Work relight_work;
    ASSERT_EQ(tv::relight_region(coarse, 0, 0, coarse.descent_sun_m,
                                 tv::ImageU8{coarse_relit.data(), coarse.image.width, coarse.image.height,
                                             coarse.image.width},
                                 relight_work),
              tv::Status::kOk);
    coarse_lit = coarse;
    coarse_lit.image.data = coarse_relit.data();
    for (int k = 0; k < 3; ++k) {
      coarse_lit.sun_m[k] = coarse.descent_sun_m[k];
    }
    // Landmarks on the fine layer, with its elevation in metres.
    std::vector<float> elev(static_cast<std::size_t>(fine.image.width) * static_cast<std::size_t>(fine.image.height));
    for (std::size_t i = 0; i < elev.size(); ++i) {
      elev[i] = static_cast<float>(fine.elevation[i] * fine.elevation_scale_m);
    }
    const tv::ConstImageF32 ev{elev.data(), fine.image.width, fine.image.height, fine.image.width};
    bsp::Work work;
    ASSERT_EQ(tv::select_landmarks(fine.image, ev, fine.geo, tv::SelectParams{}, *table, work), tv::Status::kOk);
    ASSERT_GT(table->count, 500U);
    seed = s;
  }
};

/** Prior built from a truth pose (exact, zero sigmas unless set by the caller). */
inline tv::PosePrior prior_of(const bsp::CameraPose& pose, double t_s) {
  tv::PosePrior p;
  p.t_s = t_s;
  for (int k = 0; k < 3; ++k) {
    p.p_m[k] = pose.r_m[k];
  }
  p.q_mb[0] = pose.q_mb.w();
  p.q_mb[1] = pose.q_mb.x();
  p.q_mb[2] = pose.q_mb.y();
  p.q_mb[3] = pose.q_mb.z();
  return p;
}

/** Value at quantile @p q (0..1) of @p v (nearest rank); 0 for an empty set. */
inline double quantile(std::vector<double> v, double q) {
  if (v.empty()) {
    return 0.0;
  }
  std::sort(v.begin(), v.end());
  const auto i = static_cast<std::size_t>(std::min<double>(static_cast<double>(v.size() - 1),
                                                           std::floor(q * static_cast<double>(v.size()))));
  return v[i];
}

}  // namespace frame_test
