/**
 * @file world_bench.cpp
 * @brief Host time of the world on the emulation's path: terrain build, shading, map product, one camera frame.
 *
 * Full-size world (4096 x 4096 samples at 4 m, 16.4 km square). Target: a
 * 1024 x 1024 frame in 20 ms or less at every altitude of the descent, since
 * one is rendered per emulated second.
 */
#include "bsp_tile64/emu/devices/camera.hpp"
#include "bsp_tile64/api/memory.hpp"
#include "bsp_tile64/world/refmap.hpp"

#include <benchmark/benchmark.h>

#include <cstdint>
#include <vector>

namespace {

void ensure_world() {
  static const bool built = [] {
    return bsp::world::terrain_build(bsp::world::TerrainConfig{}) == bsp::world::WorldError::kOk &&
           bsp::world::terrain_shade(bsp::CameraConfig{}.sun) == bsp::world::WorldError::kOk;
  }();
  if (!built) {
    std::abort();
  }
}

void BM_TerrainBuild4096(benchmark::State& state) {
  for (auto _ : state) {
    benchmark::DoNotOptimize(bsp::world::terrain_build(bsp::world::TerrainConfig{}));
  }
}
BENCHMARK(BM_TerrainBuild4096)->Unit(benchmark::kMillisecond)->Iterations(2);

void BM_TerrainShade4096(benchmark::State& state) {
  ensure_world();
  for (auto _ : state) {
    benchmark::DoNotOptimize(bsp::world::terrain_shade(bsp::CameraConfig{}.sun));
  }
}
BENCHMARK(BM_TerrainShade4096)->Unit(benchmark::kMillisecond)->Iterations(3);

void BM_MapProductBuild(benchmark::State& state) {
  ensure_world();
  for (auto _ : state) {
    state.PauseTiming();
    (void)bsp::region_reset(bsp::Region{bsp::Region::kDdr});
    state.ResumeTiming();
    benchmark::DoNotOptimize(bsp::world::refmap_build(bsp::world::MapConfig{}, nullptr));
  }
}
BENCHMARK(BM_MapProductBuild)->Unit(benchmark::kMillisecond)->Iterations(2);

/**
 * One 1024x1024 frame from the truth pose at t = range(0) s (altitude from 4200 m at t=0 to 1000 m
 * at ~46 s), blur if range(1), rendered with range(2) float lanes (0: the host's choice, 4: forced).
 */
void BM_RenderFrame1024(benchmark::State& state) {
  ensure_world();
  bsp::world::Trajectory traj;
  if (traj.init(bsp::world::TrajectoryConfig{}) != bsp::world::WorldError::kOk) {
    state.SkipWithError("trajectory");
    return;
  }
  const bsp::world::TruthState s = traj.at(static_cast<double>(state.range(0)));
  const bsp::CameraModel m = bsp::make_camera(1024, 1024, 90.0);
  std::vector<std::uint8_t> frame(std::size_t{1024} * 1024);
  bsp::Rng rng(1, bsp::StreamId::kSensor, bsp::kCameraStreamIndex);
  const bsp::RenderOptions opt{600.0, 2.0, state.range(1) != 0};
  bsp::detail::cap_render_lanes(static_cast<std::uint32_t>(state.range(2)));
  for (auto _ : state) {
    benchmark::DoNotOptimize(bsp::render(m, {s.r_m, s.q_mb}, opt, frame.data(), &rng));
  }
  state.counters["altitude_m"] = s.r_m.z();
  state.counters["lanes"] = bsp::detail::render_lanes();
  bsp::detail::cap_render_lanes(0);
}
BENCHMARK(BM_RenderFrame1024)
    ->Args({0, 0, 0})
    ->Args({10, 0, 0})
    ->Args({25, 0, 0})
    ->Args({35, 0, 0})
    ->Args({45, 0, 0})
    ->Args({0, 1, 0})
    ->Args({0, 0, 4})
    ->Args({45, 0, 4})
    ->Unit(benchmark::kMillisecond);

/**
 * One nadir 1024x1024 frame from 4200 m at heading range(0) deg: the footprint's orientation on
 * the grid decides how many cache lines and pages a line of pixels touches (worst near 45 deg).
 */
void BM_RenderFrame1024Heading(benchmark::State& state) {
  ensure_world();
  constexpr double kDeg = 3.14159265358979323846 / 180.0;
  Eigen::Matrix3d ned_to_enu;
  ned_to_enu << 0, 1, 0, 1, 0, 0, 0, 0, -1;
  const Eigen::Quaterniond q =
      Eigen::Quaterniond(ned_to_enu) *
      Eigen::Quaterniond(Eigen::AngleAxisd(static_cast<double>(state.range(0)) * kDeg, Eigen::Vector3d::UnitZ()));
  const bsp::CameraModel m = bsp::make_camera(1024, 1024, 90.0);
  std::vector<std::uint8_t> frame(std::size_t{1024} * 1024);
  bsp::Rng rng(1, bsp::StreamId::kSensor, bsp::kCameraStreamIndex);
  const bsp::RenderOptions opt{600.0, 2.0, false};
  for (auto _ : state) {
    benchmark::DoNotOptimize(bsp::render(m, {Eigen::Vector3d(0.0, 0.0, 4200.0), q}, opt, frame.data(), &rng));
  }
}
BENCHMARK(BM_RenderFrame1024Heading)->Arg(0)->Arg(20)->Arg(45)->Arg(70)->Arg(90)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
