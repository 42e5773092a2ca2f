/**
 * @file world_bench.cpp
 * @brief Host time of the world on the emulation's path: terrain build, shading, map product, one camera frame.
 *
 * Full-size world (4096 x 4096 samples at 4 m, 16.4 km square). Target: a
 * 1024 x 1024 frame in 20 ms or less, since one is rendered per emulated second.
 */
#include "bsp_tile64/devices/camera.hpp"
#include "bsp_tile64/memory.hpp"
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

/** One 1024x1024 frame from the truth pose at t (altitude from 4200 m at t=0 to 1000 m at ~46 s). */
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
  for (auto _ : state) {
    benchmark::DoNotOptimize(bsp::render(m, {s.r_m, s.q_mb}, opt, frame.data(), &rng));
  }
  state.counters["altitude_m"] = s.r_m.z();
}
BENCHMARK(BM_RenderFrame1024)->Args({0, 0})->Args({25, 0})->Args({45, 0})->Args({0, 1})->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
