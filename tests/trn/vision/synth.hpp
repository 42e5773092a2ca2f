/**
 * @file synth.hpp
 * @brief Test helper: synthetic images (random textures, band-limited fields, patterns).
 *
 * All randomness comes from bsp::Rng with the caller's seed.
 */
#pragma once

#include "bsp_tile64/emu/rng.hpp"
#include "trn/vision/image.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

namespace vision_test {

/** Row-major index of (x, y) in an image of width w. */
inline std::size_t idx(std::int32_t x, std::int32_t y, std::int32_t w) {
  return static_cast<std::size_t>(y) * static_cast<std::size_t>(w) + static_cast<std::size_t>(x);
}

/** A host-owned 8-bit image. */
struct Image {
  std::int32_t w = 0;
  std::int32_t h = 0;
  std::vector<std::uint8_t> px;

  Image() = default;
  Image(std::int32_t width, std::int32_t height, std::uint8_t fill = 0)
      : w(width), h(height), px(idx(0, height, width), fill) {}
  std::uint8_t& at(std::int32_t x, std::int32_t y) { return px[idx(x, y, w)]; }
  std::uint8_t at(std::int32_t x, std::int32_t y) const { return px[idx(x, y, w)]; }
  trn::vision::ConstImageU8 view() const { return {px.data(), w, h, w}; }
  trn::vision::ImageU8 mview() { return {px.data(), w, h, w}; }
};

inline std::uint8_t clamp_u8(double v) {
  return static_cast<std::uint8_t>(std::clamp(std::lround(v), 0L, 255L));
}

/** Uniform random bytes. */
inline Image random_image(std::int32_t w, std::int32_t h, std::uint64_t seed) {
  bsp::Rng rng(seed, bsp::StreamId::kTest);
  Image im(w, h);
  for (auto& v : im.px) {
    v = static_cast<std::uint8_t>(rng.below(256));
  }
  return im;
}

/** One separable box blur pass of radius r (edges clamped), in place on doubles. */
inline void box_blur(std::vector<double>& f, std::int32_t w, std::int32_t h, std::int32_t r) {
  std::vector<double> tmp(f.size());
  for (std::int32_t y = 0; y < h; ++y) {
    for (std::int32_t x = 0; x < w; ++x) {
      double s = 0;
      for (std::int32_t k = -r; k <= r; ++k) s += f[idx(std::clamp(x + k, 0, w - 1), y, w)];
      tmp[idx(x, y, w)] = s / (2 * r + 1);
    }
  }
  for (std::int32_t y = 0; y < h; ++y) {
    for (std::int32_t x = 0; x < w; ++x) {
      double s = 0;
      for (std::int32_t k = -r; k <= r; ++k) s += tmp[idx(x, std::clamp(y + k, 0, h - 1), w)];
      f[idx(x, y, w)] = s / (2 * r + 1);
    }
  }
}

/** Smooth random texture: white noise blurred twice by a box of radius r, stretched to sd ~40 DN. */
inline Image smooth_texture(std::int32_t w, std::int32_t h, std::int32_t r, std::uint64_t seed) {
  bsp::Rng rng(seed, bsp::StreamId::kTest, 1);
  std::vector<double> f(idx(0, h, w));
  for (auto& v : f) v = rng.normal();
  box_blur(f, w, h, r);
  box_blur(f, w, h, r);
  double mean = 0, sq = 0;
  for (double v : f) { mean += v; sq += v * v; }
  mean /= static_cast<double>(f.size());
  const double sd = std::sqrt(sq / static_cast<double>(f.size()) - mean * mean);
  Image im(w, h);
  for (std::size_t i = 0; i < f.size(); ++i) im.px[i] = clamp_u8(128.0 + 40.0 * (f[i] - mean) / sd);
  return im;
}

/** A band-limited field: a sum of random plane waves, exact at any real (x, y). */
struct WaveField {
  struct Wave { double kx, ky, phase, amp; };
  std::vector<Wave> waves;

  WaveField(std::uint64_t seed, int count, double max_cycles_per_px) {
    bsp::Rng rng(seed, bsp::StreamId::kTest, 2);
    constexpr double kTwoPi = 6.283185307179586;
    for (int i = 0; i < count; ++i) {
      const double f = rng.uniform(0.02, max_cycles_per_px);
      const double dir = rng.uniform(0.0, kTwoPi);
      waves.push_back({kTwoPi * f * std::cos(dir), kTwoPi * f * std::sin(dir), rng.uniform(0.0, kTwoPi),
                       rng.uniform(0.5, 1.0)});
    }
  }
  double operator()(double x, double y) const {
    double s = 0;
    for (const auto& wv : waves) s += wv.amp * std::cos(wv.kx * x + wv.ky * y + wv.phase);
    return s;
  }
  /** w x h samples at (x0 + i, y0 + j), scaled to 128 + gain * field, plus Gaussian noise of sd noise_dn. */
  Image sample(double x0, double y0, std::int32_t w, std::int32_t h, double gain, double noise_dn,
               bsp::Rng& rng) const {
    Image im(w, h);
    for (std::int32_t j = 0; j < h; ++j)
      for (std::int32_t i = 0; i < w; ++i)
        im.at(i, j) = clamp_u8(128.0 + gain * (*this)(x0 + i, y0 + j) + rng.normal(0.0, noise_dn));
    return im;
  }
};

/** Naive double-precision zero-mean NCC at one offset (direct formula); 0 for a flat window. */
inline double naive_ncc_at(const Image& t, const Image& win, std::int32_t ox, std::int32_t oy) {
  const double n = static_cast<double>(t.w) * t.h;
  double mt = 0, mw = 0;
  for (std::int32_t y = 0; y < t.h; ++y)
    for (std::int32_t x = 0; x < t.w; ++x) { mt += t.at(x, y); mw += win.at(ox + x, oy + y); }
  mt /= n;
  mw /= n;
  double num = 0, dt = 0, dw = 0;
  for (std::int32_t y = 0; y < t.h; ++y)
    for (std::int32_t x = 0; x < t.w; ++x) {
      const double a = t.at(x, y) - mt, b = win.at(ox + x, oy + y) - mw;
      num += a * b; dt += a * a; dw += b * b;
    }
  if (dw == 0.0) return 0.0;
  return num / std::sqrt(dt * dw);
}

}  // namespace vision_test
