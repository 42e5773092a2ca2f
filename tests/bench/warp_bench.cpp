/**
 * @file warp_bench.cpp
 * @brief The coarse footprint warp: exact per-pixel homography against the grid warp (8 and 16 px).
 *
 * Same work as coarse_frame's footprint: a 256x256 destination resampled from a
 * 1024x1024 frame under a homography of ~2.5 source px per destination px with
 * a mild perspective (w from 1 to 1.008 over the footprint). Host CPU time per
 * variant, then the TILE64 cycles the cost model charges for each and the
 * largest pixel difference of the grid warp from the exact one.
 */
#include "bsp_tile64/emu/cost_model.hpp"
#include "bsp_tile64/emu/profile.hpp"
#include "bsp_tile64/emu/rng.hpp"
#include "trn/vision/warp.hpp"
#include "trn/vision/warp_grid.hpp"

#include <benchmark/benchmark.h>

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <vector>

namespace {

namespace tv = trn::vision;

constexpr std::int32_t kSrc = 1024;
constexpr std::int32_t kDst = 256;
const tv::Homography kH{{2.5, 0.05, 200.0, -0.04, 2.5, 180.0, 2e-5, 1e-5, 1.0}};

/** A frame with detail at every scale: random bytes smoothed by a 2x2 box. */
const std::vector<std::uint8_t>& frame() {
  static const std::vector<std::uint8_t> f = [] {
    bsp::Rng rng(7, bsp::StreamId::kTest);
    const auto n = static_cast<std::size_t>(kSrc) * kSrc;
    std::vector<std::uint8_t> raw(n);
    for (auto& v : raw) v = static_cast<std::uint8_t>(rng.below(256));
    std::vector<std::uint8_t> out(n);
    for (std::int32_t y = 0; y < kSrc; ++y)
      for (std::int32_t x = 0; x < kSrc; ++x) {
        const std::int32_t x1 = std::min(x + 1, kSrc - 1);
        const std::int32_t y1 = std::min(y + 1, kSrc - 1);
        const auto at = [&](std::int32_t xx, std::int32_t yy) {
          return static_cast<std::int32_t>(raw[static_cast<std::size_t>(yy) * kSrc + static_cast<std::size_t>(xx)]);
        };
        out[static_cast<std::size_t>(y) * kSrc + static_cast<std::size_t>(x)] =
            static_cast<std::uint8_t>((at(x, y) + at(x1, y) + at(x, y1) + at(x1, y1) + 2) / 4);
      }
    return out;
  }();
  return f;
}

tv::ConstImageU8 src_view() { return {frame().data(), kSrc, kSrc, kSrc}; }

/** Exact (grid_px 0) or grid warp into @p dst; false on a status other than kOk or any outside pixel. */
bool warp(std::int32_t grid_px, std::vector<std::uint8_t>& dst, bsp::Work& work) {
  dst.resize(static_cast<std::size_t>(kDst) * kDst);
  const tv::ImageU8 d{dst.data(), kDst, kDst, kDst};
  std::int32_t outside = -1;
  const tv::Status st = grid_px == 0 ? tv::warp_homography(src_view(), kH, d, 0, outside, work)
                                     : tv::warp_homography_grid(src_view(), kH, grid_px, d, 0, outside, work);
  return st == tv::Status::kOk && outside == 0;
}

void BM_CoarseWarp(benchmark::State& s) {
  const auto grid_px = static_cast<std::int32_t>(s.range(0));
  std::vector<std::uint8_t> dst;
  for (auto _ : s) {
    bsp::Work work;
    if (!warp(grid_px, dst, work)) {
      s.SkipWithError("warp failed");
      return;
    }
    benchmark::DoNotOptimize(dst.data());
  }
  s.SetLabel(grid_px == 0 ? "exact" : "grid");
}

BENCHMARK(BM_CoarseWarp)->Arg(0)->Arg(8)->Arg(16)->Unit(benchmark::kMicrosecond);

void print_cycles() {
  std::vector<std::uint8_t> exact;
  bsp::Work we;
  if (!warp(0, exact, we)) {
    std::printf("coarse warp cycles: exact warp failed\n");
    return;
  }
  const auto cyc = [](const bsp::Work& w) { return static_cast<double>(bsp::cost_of(bsp::kTile64, w)) / 1e6; };
  std::printf("TILE64 cycles, coarse footprint warp 256x256: exact %.1f M", cyc(we));
  for (std::int32_t g : {8, 16}) {
    std::vector<std::uint8_t> grid;
    bsp::Work wg;
    if (!warp(g, grid, wg)) {
      std::printf("\ncoarse warp cycles: grid warp %d failed\n", g);
      return;
    }
    int worst = 0;
    for (std::size_t i = 0; i < exact.size(); ++i) worst = std::max(worst, std::abs(exact[i] - grid[i]));
    std::printf("; grid %d px %.2f M (%.0fx fewer, pixels within %d DN)", g, cyc(wg), cyc(we) / cyc(wg), worst);
  }
  std::printf("\n");
}

}  // namespace

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  benchmark::RunSpecifiedBenchmarks();
  print_cycles();
  benchmark::Shutdown();
  return 0;
}
