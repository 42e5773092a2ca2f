/**
 * @file ncc.cpp
 * @brief Integer-arithmetic zero-mean NCC (see ncc.hpp for the formula and bounds).
 */
#include "trn/vision/ncc.hpp"

#include <cmath>

namespace trn::vision {

namespace detail {
namespace {

/** Lanes of the fixed-length inner block: a constant trip count the compiler can vectorise. */
constexpr std::int32_t kBlock = 16;

/** sum(t[i] * w[i]) over @p n bytes. */
std::uint32_t dot_row(const std::uint8_t* t, const std::uint8_t* w, std::int32_t n) noexcept {
  std::uint32_t acc = 0U;
  std::int32_t i = 0;
  for (; i + kBlock <= n; i += kBlock) {
    std::uint32_t part = 0U;
    for (std::int32_t k = 0; k < kBlock; ++k) {
      part += static_cast<std::uint32_t>(t[i + k]) * static_cast<std::uint32_t>(w[i + k]);
    }
    acc += part;
  }
  for (; i < n; ++i) {
    acc += static_cast<std::uint32_t>(t[i]) * static_cast<std::uint32_t>(w[i]);
  }
  return acc;
}

/** sum(T * W) for the template at window offset (x, y); fits uint32 by the static_assert. */
std::uint32_t dot_at(ConstImageU8 tmpl, ConstImageU8 window, std::int32_t x, std::int32_t y) noexcept {
  std::uint32_t acc = 0U;
  for (std::int32_t j = 0; j < tmpl.height; ++j) {
    acc += dot_row(tmpl.row(j), window.row(y + j) + x, tmpl.width);
  }
  return acc;
}

/** One score from exact integer terms; flat windows give 0. */
float score_of(std::int64_t num, std::int64_t var_t, std::int64_t var_w) noexcept {
  const double den = std::sqrt(static_cast<double>(var_t) * static_cast<double>(var_w));
  double r = static_cast<double>(num) / den;
  // Rounding can push a perfect match a hair beyond 1.
  r = r > 1.0 ? 1.0 : (r < -1.0 ? -1.0 : r);
  return static_cast<float>(r);
}

}  // namespace
}  // namespace detail

Status template_stats(ConstImageU8 tmpl, TemplateStats& out, bsp::Work& work) noexcept {
  if (!tmpl.valid()) {
    return Status::kBadInput;
  }
  const std::int64_t n = static_cast<std::int64_t>(tmpl.width) * tmpl.height;
  if (n > kNccMaxTemplatePixels) {
    return Status::kTooLarge;
  }
  std::int64_t sum = 0;
  std::int64_t sum_sq = 0;
  for (std::int32_t y = 0; y < tmpl.height; ++y) {
    const std::uint8_t* t = tmpl.row(y);
    for (std::int32_t x = 0; x < tmpl.width; ++x) {
      const std::int64_t v = t[x];
      sum += v;
      sum_sq += v * v;
    }
  }
  out.width = tmpl.width;
  out.height = tmpl.height;
  out.n = n;
  out.sum = sum;
  out.var_n2 = n * sum_sq - sum * sum;
  out.flat = out.var_n2 <= 0;
  work.int_macs += static_cast<std::uint64_t>(n);
  work.int_ops += static_cast<std::uint64_t>(n) + 4U;
  work.mem_words += static_cast<std::uint64_t>(n) / 4U + 1U;
  return Status::kOk;
}

bsp::Work ncc_surface_work(std::int32_t tmpl_w, std::int32_t tmpl_h, std::int32_t surf_w,
                           std::int32_t surf_h) noexcept {
  const auto n = static_cast<std::uint64_t>(tmpl_w) * static_cast<std::uint64_t>(tmpl_h);
  const auto positions = static_cast<std::uint64_t>(surf_w) * static_cast<std::uint64_t>(surf_h);
  bsp::Work w;
  w.int_macs = positions * (n + 3U);            // dot product, n*dot, sum products
  w.int_ops = positions * (n / 8U + 12U);       // row accumulations, integral corners, subtractions
  w.mem_words = positions * (n / 2U + 12U + 1U);  // template + window bytes, 8 integral words, output
  w.flops = positions * 3U;                     // product, convert, clamp
  w.fdivs = positions * 2U;                     // square root and division
  return w;
}

Status ncc_surface(ConstImageU8 tmpl, const TemplateStats& stats, ConstImageU8 window, const IntegralRef& integral,
                   ImageF32 surface, ImageU8 flags, std::int32_t& flat_count, bsp::Work& work) noexcept {
  flat_count = 0;
  const bool sizes_ok = tmpl.valid() && window.valid() && surface.valid() && stats.width == tmpl.width &&
                        stats.height == tmpl.height && integral.width == window.width &&
                        integral.height == window.height && surface.width == window.width - tmpl.width + 1 &&
                        surface.height == window.height - tmpl.height + 1;
  const bool flags_ok = !flags.valid() || (flags.width == surface.width && flags.height == surface.height);
  if (!sizes_ok || !flags_ok || stats.flat || integral.sum == nullptr) {
    return Status::kBadInput;
  }
  const std::int64_t n = stats.n;
  for (std::int32_t y = 0; y < surface.height; ++y) {
    float* out = surface.row(y);
    for (std::int32_t x = 0; x < surface.width; ++x) {
      const std::int64_t sw = integral.rect_sum(x, y, tmpl.width, tmpl.height);
      const auto sww = static_cast<std::int64_t>(integral.rect_sum_sq(x, y, tmpl.width, tmpl.height));
      const std::int64_t var_w = n * sww - sw * sw;
      const bool flat = var_w <= 0;
      if (flat) {
        out[x] = 0.0F;
        ++flat_count;
      } else {
        const std::int64_t num = n * static_cast<std::int64_t>(detail::dot_at(tmpl, window, x, y)) - stats.sum * sw;
        out[x] = detail::score_of(num, stats.var_n2, var_w);
      }
      if (flags.valid()) {
        flags.at(x, y) = flat ? 1U : 0U;
      }
    }
  }
  work += ncc_surface_work(tmpl.width, tmpl.height, surface.width, surface.height);
  return Status::kOk;
}

}  // namespace trn::vision
