/**
 * @file ncc_bench.cpp
 * @brief Hand-coded NCC against a naive reference and OpenCV matchTemplate (TM_CCOEFF_NORMED).
 *
 * Same inputs for all: the fine work (a 21x21 template over a 49x49
 * window, 29x29 surface) and the coarse work (a 64x64 template over a 256x256
 * decimated map, 193x193 surface). Each variant produces the whole surface;
 * OpenCV runs single-threaded for a like-for-like comparison. The coarse work
 * runs twice by hand: spatial dot products (Hand) and the exact integer
 * transform (Transform), then the whole checked correlate() both ways
 * (Checked_Spatial, Checked_Transform: what coarse_match runs after decimation).
 * At the end the binary prints time ratios (above 1 means the hand-coded
 * version is faster), the TILE64 cycles the cost model charges for each coarse
 * variant, and whether the transform surface equals the spatial one bit for bit.
 */
#include "bsp_tile64/emu/cost_model.hpp"
#include "bsp_tile64/emu/profile.hpp"
#include "bsp_tile64/emu/rng.hpp"
#include "trn/vision/correlator.hpp"
#include "trn/vision/integral.hpp"
#include "trn/vision/ncc.hpp"
#include "trn/vision/transform_dots.hpp"

#include <benchmark/benchmark.h>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <map>
#include <string>
#include <vector>

namespace {

namespace tv = trn::vision;

struct Case {
  std::int32_t tw, win;
  std::vector<std::uint8_t> t, w;
};

/** Smooth-ish random bytes (sum of 4 uniforms) so NCC values are not all near 0. */
std::vector<std::uint8_t> make_data(std::int32_t n, std::uint64_t seed) {
  bsp::Rng rng(seed, bsp::StreamId::kTest, 77);
  std::vector<std::uint8_t> v(static_cast<std::size_t>(n));
  for (auto& x : v) x = static_cast<std::uint8_t>((rng.below(64) + rng.below(64) + rng.below(64) + rng.below(64)));
  return v;
}

Case make_case(std::int32_t tw, std::int32_t win) {
  return Case{tw, win, make_data(tw * tw, 1), make_data(win * win, 2)};
}

const Case& fine_case() {
  static const Case c = make_case(21, 49);
  return c;
}
const Case& coarse_case() {
  static const Case c = make_case(64, 256);
  return c;
}

/** Byte (x, y) of a row-major buffer of width w. */
std::uint8_t px(const std::vector<std::uint8_t>& v, std::int32_t x, std::int32_t y, std::int32_t w) {
  return v[static_cast<std::size_t>(y) * static_cast<std::size_t>(w) + static_cast<std::size_t>(x)];
}

/** Direct-formula reference: window mean and sums recomputed at every position, double precision. */
void naive_surface(const Case& c, std::vector<double>& out) {
  const std::int32_t s = c.win - c.tw + 1;
  const double n = static_cast<double>(c.tw) * c.tw;
  double mt = 0;
  for (auto v : c.t) mt += v;
  mt /= n;
  for (std::int32_t oy = 0; oy < s; ++oy)
    for (std::int32_t ox = 0; ox < s; ++ox) {
      double mw = 0;
      for (std::int32_t y = 0; y < c.tw; ++y)
        for (std::int32_t x = 0; x < c.tw; ++x) mw += px(c.w, ox + x, oy + y, c.win);
      mw /= n;
      double num = 0, dt = 0, dw = 0;
      for (std::int32_t y = 0; y < c.tw; ++y)
        for (std::int32_t x = 0; x < c.tw; ++x) {
          const double a = px(c.t, x, y, c.tw) - mt;
          const double b = px(c.w, ox + x, oy + y, c.win) - mw;
          num += a * b;
          dt += a * a;
          dw += b * b;
        }
      out[static_cast<std::size_t>(oy) * static_cast<std::size_t>(s) + static_cast<std::size_t>(ox)] = dw > 0 ? num / std::sqrt(dt * dw) : 0.0;
    }
}

void run_hand(benchmark::State& state, const Case& c) {
  static tv::FixedIntegral<256, 256> integral;
  // The flight's fine workspace gives its correlations room for the 16-bit copies (CorrelatorWorkspace).
  static std::vector<std::int16_t> wide(static_cast<std::size_t>(tv::ncc_wide_entries(256)));
  const std::int32_t s = c.win - c.tw + 1;
  std::vector<float> surf(static_cast<std::size_t>(s * s));
  const tv::ConstImageU8 t{c.t.data(), c.tw, c.tw, c.tw};
  const tv::ConstImageU8 w{c.w.data(), c.win, c.win, c.win};
  for (auto _ : state) {
    bsp::Work work;
    tv::TemplateStats st;
    std::int32_t flat = 0;
    if (tv::template_stats(t, st, work) != tv::Status::kOk || integral.build(w, work) != tv::Status::kOk ||
        tv::ncc_surface(t, st, w, integral.ref(), {surf.data(), s, s, s}, {}, flat, work, nullptr,
                        {wide.data(), static_cast<std::int64_t>(wide.size())}) != tv::Status::kOk) {
      state.SkipWithError("hand-coded NCC failed");
      break;
    }
    benchmark::DoNotOptimize(surf.data());
    state.counters["int_macs"] = static_cast<double>(work.int_macs);
  }
}

/** The surface by the transform: statistics, integral, all dot products at once, scores. */
bool transform_surface(const Case& c, std::vector<float>& surf, bsp::Work& work) {
  static tv::FixedIntegral<256, 256> integral;
  static tv::TransformWorkspace<256> planes;
  const std::int32_t s = c.win - c.tw + 1;
  const tv::ConstImageU8 t{c.t.data(), c.tw, c.tw, c.tw};
  const tv::ConstImageU8 w{c.w.data(), c.win, c.win, c.win};
  tv::TemplateStats st;
  tv::ImageView<const std::uint32_t> dots;
  std::int32_t flat = 0;
  return tv::template_stats(t, st, work) == tv::Status::kOk && integral.build(w, work) == tv::Status::kOk &&
         tv::transform_dots(t, w, planes.buffers(), dots, work) == tv::Status::kOk &&
         tv::ncc_surface_from_dots(st, integral.ref(), dots, {surf.data(), s, s, s}, {}, flat, work) ==
             tv::Status::kOk;
}

void run_transform(benchmark::State& state, const Case& c) {
  const std::int32_t s = c.win - c.tw + 1;
  std::vector<float> surf(static_cast<std::size_t>(s * s));
  for (auto _ : state) {
    bsp::Work work;
    if (!transform_surface(c, surf, work)) {
      state.SkipWithError("transform NCC failed");
      break;
    }
    benchmark::DoNotOptimize(surf.data());
    state.counters["int_macs"] = static_cast<double>(work.int_macs);
  }
}

/** The whole checked correlation (checksum, digest, peak and its neighbourhood again) by @p method. */
tv::Status run_checked(const Case& c, tv::CorrelationMethod method, tv::MatchResult& out, bsp::Work& work) {
  static tv::CorrelatorWorkspace<256> corr;
  static tv::TransformWorkspace<256> planes;
  tv::CorrelatorBuffers buf = corr.buffers();
  buf.transform = planes.buffers();
  const tv::QualityParams q{0.5F, 0.8F, 4, 1, tv::Subpixel::kParaboloid};  // the coarse stage's
  return tv::correlate({c.t.data(), c.tw, c.tw, c.tw}, {c.w.data(), c.win, c.win, c.win}, q, buf, out, work,
                       tv::CorrelationTaps{}, method);
}

void run_checked_bench(benchmark::State& state, const Case& c, tv::CorrelationMethod method) {
  for (auto _ : state) {
    tv::MatchResult r;
    bsp::Work work;
    if (run_checked(c, method, r, work) != tv::Status::kOk) {
      state.SkipWithError("checked correlation failed");
      break;
    }
    benchmark::DoNotOptimize(r.peak.score);
  }
}

void run_naive(benchmark::State& state, const Case& c) {
  const std::int32_t s = c.win - c.tw + 1;
  std::vector<double> surf(static_cast<std::size_t>(s * s));
  for (auto _ : state) {
    naive_surface(c, surf);
    benchmark::DoNotOptimize(surf.data());
  }
}

void run_opencv(benchmark::State& state, const Case& c) {
  cv::setNumThreads(1);
  cv::Mat t(c.tw, c.tw, CV_8UC1);
  cv::Mat w(c.win, c.win, CV_8UC1);
  std::memcpy(t.data, c.t.data(), c.t.size());
  std::memcpy(w.data, c.w.data(), c.w.size());
  cv::Mat out;
  for (auto _ : state) {
    cv::matchTemplate(w, t, out, cv::TM_CCOEFF_NORMED);
    benchmark::DoNotOptimize(out.data);
  }
}

void BM_Fine_Hand(benchmark::State& s) { run_hand(s, fine_case()); }
void BM_Fine_Naive(benchmark::State& s) { run_naive(s, fine_case()); }
void BM_Fine_OpenCV(benchmark::State& s) { run_opencv(s, fine_case()); }
void BM_Coarse_Hand(benchmark::State& s) { run_hand(s, coarse_case()); }
void BM_Coarse_Naive(benchmark::State& s) { run_naive(s, coarse_case()); }
void BM_Coarse_OpenCV(benchmark::State& s) { run_opencv(s, coarse_case()); }
void BM_Coarse_Transform(benchmark::State& s) { run_transform(s, coarse_case()); }
void BM_Coarse_Checked_Spatial(benchmark::State& s) {
  run_checked_bench(s, coarse_case(), tv::CorrelationMethod::kSpatial);
}
void BM_Coarse_Checked_Transform(benchmark::State& s) {
  run_checked_bench(s, coarse_case(), tv::CorrelationMethod::kTransform);
}

BENCHMARK(BM_Fine_Hand)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_Fine_Naive)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_Fine_OpenCV)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_Coarse_Hand)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Coarse_Naive)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Coarse_OpenCV)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Coarse_Transform)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Coarse_Checked_Spatial)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Coarse_Checked_Transform)->Unit(benchmark::kMillisecond);

/** Console output as usual, plus the CPU time of each run kept for the ratios. */
class RatioReporter : public benchmark::ConsoleReporter {
 public:
  void ReportRuns(const std::vector<Run>& runs) override {
    for (const Run& r : runs) {
      // With --benchmark_repetitions the ratios use the medians; single runs are used as they are.
      const bool aggregate = r.run_type == Run::RT_Aggregate;
      if (aggregate && r.aggregate_name != "median") continue;
      if (!aggregate && r.repetitions > 1) continue;
      cpu_ns_[r.run_name.function_name] = r.GetAdjustedCPUTime() * unit_ns(r.time_unit);
    }
    ConsoleReporter::ReportRuns(runs);
  }
  void print_ratios() const {
    for (const char* stage : {"Fine", "Coarse"}) {
      const std::string p = std::string("BM_") + stage + "_";
      const auto hand = cpu_ns_.find(p + "Hand");
      const auto naive = cpu_ns_.find(p + "Naive");
      const auto cv = cpu_ns_.find(p + "OpenCV");
      if (hand == cpu_ns_.end() || naive == cpu_ns_.end() || cv == cpu_ns_.end()) continue;
      std::printf("ratio %-6s: OpenCV/hand %.2f, naive/hand %.1f (hand %.1f us, OpenCV %.1f us, naive %.1f us)\n",
                  stage, cv->second / hand->second, naive->second / hand->second, hand->second / 1e3,
                  cv->second / 1e3, naive->second / 1e3);
    }
    const auto spatial = cpu_ns_.find("BM_Coarse_Hand");
    const auto transform = cpu_ns_.find("BM_Coarse_Transform");
    const auto cv = cpu_ns_.find("BM_Coarse_OpenCV");
    if (spatial != cpu_ns_.end() && transform != cpu_ns_.end() && cv != cpu_ns_.end()) {
      std::printf("ratio Coarse: transform/OpenCV %.2f, spatial/transform %.1f (transform %.2f ms, OpenCV %.2f ms)\n",
                  transform->second / cv->second, spatial->second / transform->second, transform->second / 1e6,
                  cv->second / 1e6);
    }
    const auto cs = cpu_ns_.find("BM_Coarse_Checked_Spatial");
    const auto ct = cpu_ns_.find("BM_Coarse_Checked_Transform");
    if (cs != cpu_ns_.end() && ct != cpu_ns_.end()) {
      std::printf("ratio Coarse checked correlate(): spatial/transform %.1f (spatial %.2f ms, transform %.2f ms)\n",
                  cs->second / ct->second, cs->second / 1e6, ct->second / 1e6);
    }
  }

 private:
  static double unit_ns(benchmark::TimeUnit u) {
    switch (u) {
      case benchmark::kSecond: return 1e9;
      case benchmark::kMillisecond: return 1e6;
      case benchmark::kMicrosecond: return 1e3;
      default: return 1.0;
    }
  }
  std::map<std::string, double> cpu_ns_;
};

/** Largest |hand - OpenCV| over the surface of @p c: the benchmark compares equal work. */
double max_diff_vs_opencv(const Case& c) {
  static tv::FixedIntegral<256, 256> integral;
  const std::int32_t s = c.win - c.tw + 1;
  std::vector<float> surf(static_cast<std::size_t>(s) * static_cast<std::size_t>(s));
  const tv::ConstImageU8 t{c.t.data(), c.tw, c.tw, c.tw};
  const tv::ConstImageU8 w{c.w.data(), c.win, c.win, c.win};
  bsp::Work work;
  tv::TemplateStats st;
  std::int32_t flat = 0;
  if (tv::template_stats(t, st, work) != tv::Status::kOk || integral.build(w, work) != tv::Status::kOk ||
      tv::ncc_surface(t, st, w, integral.ref(), {surf.data(), s, s, s}, {}, flat, work) != tv::Status::kOk) {
    return -1.0;
  }
  cv::Mat tm(c.tw, c.tw, CV_8UC1);
  cv::Mat wm(c.win, c.win, CV_8UC1);
  std::memcpy(tm.data, c.t.data(), c.t.size());
  std::memcpy(wm.data, c.w.data(), c.w.size());
  cv::Mat out;
  cv::matchTemplate(wm, tm, out, cv::TM_CCOEFF_NORMED);
  double worst = 0.0;
  for (std::int32_t y = 0; y < s; ++y)
    for (std::int32_t x = 0; x < s; ++x)
      worst = std::max(worst, std::fabs(static_cast<double>(out.at<float>(y, x)) -
                                        surf[static_cast<std::size_t>(y) * static_cast<std::size_t>(s) +
                                             static_cast<std::size_t>(x)]));
  return worst;
}

/** Emulated TILE64 cycles of the coarse variants, and whether both paths agree bit for bit. */
void print_coarse_cycles() {
  const Case& c = coarse_case();
  const std::int32_t s = c.win - c.tw + 1;
  std::vector<float> hand(static_cast<std::size_t>(s) * static_cast<std::size_t>(s));
  std::vector<float> trans(hand.size());
  bsp::Work wh;
  bsp::Work wt;
  {
    static tv::FixedIntegral<256, 256> integral;
    const tv::ConstImageU8 t{c.t.data(), c.tw, c.tw, c.tw};
    const tv::ConstImageU8 w{c.w.data(), c.win, c.win, c.win};
    tv::TemplateStats st;
    std::int32_t flat = 0;
    if (tv::template_stats(t, st, wh) != tv::Status::kOk || integral.build(w, wh) != tv::Status::kOk ||
        tv::ncc_surface(t, st, w, integral.ref(), {hand.data(), s, s, s}, {}, flat, wh) != tv::Status::kOk) {
      std::printf("coarse cycles: spatial surface failed\n");
      return;
    }
  }
  if (!transform_surface(c, trans, wt)) {
    std::printf("coarse cycles: transform surface failed\n");
    return;
  }
  const bool same = std::memcmp(hand.data(), trans.data(), hand.size() * sizeof(float)) == 0;
  tv::MatchResult rs;
  tv::MatchResult rt;
  bsp::Work cs;
  bsp::Work ct;
  if (run_checked(c, tv::CorrelationMethod::kSpatial, rs, cs) != tv::Status::kOk ||
      run_checked(c, tv::CorrelationMethod::kTransform, rt, ct) != tv::Status::kOk) {
    std::printf("coarse cycles: checked correlation failed\n");
    return;
  }
  const auto cyc = [](const bsp::Work& w) { return static_cast<double>(bsp::cost_of(bsp::kTile64, w)) / 1e6; };
  std::printf("TILE64 cycles, coarse 64 on 256: surface spatial %.1f M, transform %.1f M (%.1fx); "
              "checked correlate() spatial %.1f M, transform %.1f M (%.1fx)\n",
              cyc(wh), cyc(wt), cyc(wh) / cyc(wt), cyc(cs), cyc(ct), cyc(cs) / cyc(ct));
  std::printf("transform surface == spatial surface bit for bit: %s; checked peaks (%d, %d) and (%d, %d)\n",
              same ? "yes" : "NO", rs.peak.ix, rs.peak.iy, rt.peak.ix, rt.peak.iy);
}

}  // namespace

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  RatioReporter reporter;
  benchmark::RunSpecifiedBenchmarks(&reporter);
  reporter.print_ratios();
  std::printf("max |hand - OpenCV| over the surface: fine %.2e, coarse %.2e\n", max_diff_vs_opencv(fine_case()),
              max_diff_vs_opencv(coarse_case()));
  print_coarse_cycles();
  benchmark::Shutdown();
  return 0;
}
