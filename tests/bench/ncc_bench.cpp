/**
 * @file ncc_bench.cpp
 * @brief Hand-coded NCC against a naive reference and OpenCV matchTemplate (TM_CCOEFF_NORMED).
 *
 * Same inputs for all three: the fine work (a 21x21 template over a 49x49
 * window, 29x29 surface) and the coarse work (a 64x64 template over a 256x256
 * decimated map, 193x193 surface). Each variant produces the whole surface;
 * OpenCV runs single-threaded for a like-for-like comparison. At the end the
 * binary prints time ratios (OpenCV / hand and naive / hand; above 1 means the
 * hand-coded version is faster).
 */
#include "bsp_tile64/rng.hpp"
#include "trn/vision/integral.hpp"
#include "trn/vision/ncc.hpp"

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
  const std::int32_t s = c.win - c.tw + 1;
  std::vector<float> surf(static_cast<std::size_t>(s * s));
  const tv::ConstImageU8 t{c.t.data(), c.tw, c.tw, c.tw};
  const tv::ConstImageU8 w{c.w.data(), c.win, c.win, c.win};
  for (auto _ : state) {
    bsp::Work work;
    tv::TemplateStats st;
    std::int32_t flat = 0;
    if (tv::template_stats(t, st, work) != tv::Status::kOk || integral.build(w, work) != tv::Status::kOk ||
        tv::ncc_surface(t, st, w, integral.ref(), {surf.data(), s, s, s}, {}, flat, work) != tv::Status::kOk) {
      state.SkipWithError("hand-coded NCC failed");
      break;
    }
    benchmark::DoNotOptimize(surf.data());
    state.counters["int_macs"] = static_cast<double>(work.int_macs);
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

BENCHMARK(BM_Fine_Hand)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_Fine_Naive)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_Fine_OpenCV)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_Coarse_Hand)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Coarse_Naive)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Coarse_OpenCV)->Unit(benchmark::kMillisecond);

/** Console output as usual, plus the CPU time of each run kept for the ratios. */
class RatioReporter : public benchmark::ConsoleReporter {
 public:
  void ReportRuns(const std::vector<Run>& runs) override {
    for (const Run& r : runs) {
      cpu_ns_[r.benchmark_name()] = r.GetAdjustedCPUTime() * unit_ns(r.time_unit);
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

}  // namespace

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  RatioReporter reporter;
  benchmark::RunSpecifiedBenchmarks(&reporter);
  reporter.print_ratios();
  std::printf("max |hand - OpenCV| over the surface: fine %.2e, coarse %.2e\n", max_diff_vs_opencv(fine_case()),
              max_diff_vs_opencv(coarse_case()));
  benchmark::Shutdown();
  return 0;
}
