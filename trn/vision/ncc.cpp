/**
 * @file ncc.cpp
 * @brief Integer-arithmetic zero-mean NCC (see ncc.hpp for the formula and bounds).
 */
#include "trn/vision/ncc.hpp"

#include <bit>
#include <cmath>
#include <cstddef>

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

/** Offsets one pass of dots_along_row() computes: a constant trip count the compiler can vectorise. */
constexpr std::int32_t kLanes = 16;

/**
 * The dot products at offsets x0 .. x0 + kLanes - 1 of row @p y, all on the
 * surface: for each template pixel, its value times kLanes consecutive window
 * pixels, added lane by lane (no reduction across lanes). The same integers
 * as dot_at(), in another order of the same exact additions.
 */
void dots_along_row(ConstImageU8 tmpl, ConstImageU8 window, std::int32_t x0, std::int32_t y,
                    std::uint32_t (&out)[kLanes]) noexcept {
  std::uint32_t acc[kLanes] = {};
  for (std::int32_t j = 0; j < tmpl.height; ++j) {
    const std::uint8_t* t = tmpl.row(j);
    const std::uint8_t* w = window.row(y + j) + x0;
    for (std::int32_t i = 0; i < tmpl.width; ++i) {
      const auto tv = static_cast<std::uint32_t>(t[i]);
      const std::uint8_t* wi = w + i;
      for (std::int32_t k = 0; k < kLanes; ++k) {
        acc[k] += tv * static_cast<std::uint32_t>(wi[k]);
      }
    }
  }
  for (std::int32_t k = 0; k < kLanes; ++k) {
    out[k] = acc[k];
  }
}

/**
 * dot_at() for a surface visited row by row, left to right: kLanes offsets
 * computed at once (dots_along_row()) and served from there; a row's last
 * pass is moved left to end on the surface's last offset. Surfaces narrower
 * than kLanes go offset by offset.
 */
class RowDots {
 public:
  RowDots(ConstImageU8 tmpl, ConstImageU8 window, std::int32_t surface_width) noexcept
      : tmpl_(tmpl), window_(window), width_(surface_width) {}

  std::uint32_t operator()(std::int32_t x, std::int32_t y) noexcept {
    if (width_ < kLanes) {
      return dot_at(tmpl_, window_, x, y);
    }
    if (y != y_ || x < x0_ || x >= x0_ + kLanes) {
      x0_ = x <= width_ - kLanes ? x : width_ - kLanes;
      y_ = y;
      dots_along_row(tmpl_, window_, x0_, y_, dots_);
    }
    return dots_[x - x0_];
  }

 private:
  ConstImageU8 tmpl_;
  ConstImageU8 window_;
  std::int32_t width_;
  std::int32_t y_ = -1;
  std::int32_t x0_ = 0;
  std::uint32_t dots_[kLanes] = {};
};

/** Columns of a template's 16-bit copy: its width rounded up to a vector of eight 16-bit lanes. */
constexpr std::int32_t wide_columns(std::int32_t tmpl_width) noexcept { return (tmpl_width + 7) / 8 * 8; }

/**
 * dot_at() from 16-bit copies (widen()): the template's rows padded with zeros
 * to P columns, the window's to @p stride = window width - template width + P,
 * so every offset of the surface reads P columns of each row inside the copy.
 * A row is a sum of P products of 16-bit integers with a constant trip count,
 * which compilers turn into multiply-add-pairs vector instructions. The
 * integers are dot_at()'s: the padding multiplies zeros, and the sum is at
 * most 255^2 * 32 * 32 (kNccWideMaxTemplatePx), far inside int32.
 */
template <std::int32_t P>
class WideDots {
 public:
  WideDots(const std::int16_t* tmpl, std::int32_t tmpl_height, const std::int16_t* window,
           std::int32_t stride) noexcept
      : tmpl_(tmpl), height_(tmpl_height), window_(window), stride_(stride) {}

  std::uint32_t operator()(std::int32_t x, std::int32_t y) const noexcept {
    std::int32_t acc = 0;
    const std::int16_t* t = tmpl_;
    const std::int16_t* w = window_ + static_cast<std::ptrdiff_t>(y) * stride_ + x;
    for (std::int32_t j = 0; j < height_; ++j) {
      std::int32_t row = 0;
      for (std::int32_t i = 0; i < P; ++i) {
        row += static_cast<std::int32_t>(t[i]) * static_cast<std::int32_t>(w[i]);
      }
      acc += row;
      t += P;
      w += stride_;
    }
    return static_cast<std::uint32_t>(acc);
  }

 private:
  const std::int16_t* tmpl_;
  std::int32_t height_;
  const std::int16_t* window_;
  std::int32_t stride_;
};

/**
 * Fills @p buf with the 16-bit copies WideDots<wide_columns(tmpl.width)> reads:
 * the template first, then the window. @return false (nothing written) when
 * the template is too wide or @p buf too small.
 */
bool widen(ConstImageU8 tmpl, ConstImageU8 window, NccWideBuffer buf, std::int32_t& stride) noexcept {
  const std::int32_t cols = wide_columns(tmpl.width);
  stride = window.width - tmpl.width + cols;
  const std::int64_t need = std::int64_t{tmpl.height} * cols + std::int64_t{window.height} * stride;
  if (buf.data == nullptr || tmpl.width > kNccWideMaxTemplatePx || need > buf.entries) {
    return false;
  }
  std::int16_t* out = buf.data;
  for (std::int32_t j = 0; j < tmpl.height; ++j) {
    const std::uint8_t* t = tmpl.row(j);
    for (std::int32_t i = 0; i < cols; ++i) {
      out[i] = i < tmpl.width ? static_cast<std::int16_t>(t[i]) : std::int16_t{0};
    }
    out += cols;
  }
  for (std::int32_t j = 0; j < window.height; ++j) {
    const std::uint8_t* w = window.row(j);
    for (std::int32_t i = 0; i < stride; ++i) {
      out[i] = i < window.width ? static_cast<std::int16_t>(w[i]) : std::int16_t{0};
    }
    out += stride;
  }
  return true;
}

/** One score from exact integer terms; flat windows give 0. */
float score_of(std::int64_t num, std::int64_t var_t, std::int64_t var_w) noexcept {
  const double den = std::sqrt(static_cast<double>(var_t) * static_cast<double>(var_w));
  double r = static_cast<double>(num) / den;
  // Rounding can push a perfect match a hair beyond 1.
  r = r > 1.0 ? 1.0 : (r < -1.0 ? -1.0 : r);
  return static_cast<float>(r);
}

/** A window's exact terms at one offset: its sum and n^2 times its variance (<= 0: flat). */
struct WindowTerms {
  std::int64_t sw = 0;
  std::int64_t var_w = 0;
};

WindowTerms window_terms(const IntegralRef& integral, std::int32_t x, std::int32_t y, std::int32_t tw,
                         std::int32_t th, std::int64_t n) noexcept {
  WindowTerms t;
  t.sw = integral.rect_sum(x, y, tw, th);
  const auto sww = static_cast<std::int64_t>(integral.rect_sum_sq(x, y, tw, th));
  t.var_w = n * sww - t.sw * t.sw;
  return t;
}

/** The score of a non-flat window from its dot product (the one formula of the surface and of ncc_score_at). */
float score_from(const TemplateStats& stats, const WindowTerms& t, std::uint32_t dot) noexcept {
  const std::int64_t num = stats.n * static_cast<std::int64_t>(dot) - stats.sum * t.sw;
  return score_of(num, stats.var_n2, t.var_w);
}

/** The bits of a score, for the surface's digest. */
std::uint64_t bits_of(float v) noexcept { return std::bit_cast<std::uint32_t>(v); }

/** Whether the surface, flags and integral fit each other and a non-flat template of @p stats. */
bool shape_ok(const TemplateStats& stats, const IntegralRef& integral, ImageF32 surface, ImageU8 flags) noexcept {
  const bool sizes_ok = surface.valid() && integral.sum != nullptr &&
                        surface.width == integral.width - stats.width + 1 &&
                        surface.height == integral.height - stats.height + 1;
  const bool flags_ok = !flags.valid() || (flags.width == surface.width && flags.height == surface.height);
  return sizes_ok && flags_ok && !stats.flat;
}

/** Whether the views and sizes suit ncc_surface(). */
bool surface_args_ok(ConstImageU8 tmpl, const TemplateStats& stats, ConstImageU8 window,
                     const IntegralRef& integral, ImageF32 surface, ImageU8 flags) noexcept {
  return tmpl.valid() && window.valid() && stats.width == tmpl.width && stats.height == tmpl.height &&
         integral.width == window.width && integral.height == window.height &&
         shape_ok(stats, integral, surface, flags);
}

/**
 * The surface, position by position: the one loop of both paths. @p dot_at(x, y)
 * gives the dot product at a non-flat offset; it is published in place before its
 * use, so a corruption injected there is what the score and the sum see.
 */
template <typename DotAt>
void score_surface(const TemplateStats& stats, const IntegralRef& integral, ImageF32 surface, ImageU8 flags,
                   std::int32_t& flat_count, NccCheck& c, const DotAt& dot_at) noexcept {
  c.dot_sum = 0;
  c.surface_sum = 0U;
  for (std::int32_t y = 0; y < surface.height; ++y) {
    float* out = surface.row(y);
    for (std::int32_t x = 0; x < surface.width; ++x) {
      const WindowTerms t = window_terms(integral, x, y, stats.width, stats.height, stats.n);
      const bool flat = t.var_w <= 0;
      if (flat) {
        out[x] = 0.0F;
        ++flat_count;
        c.dot_sum += stats.sum * (t.sw / stats.n);  // every pixel is sw / n, exactly
      } else {
        std::uint32_t dot = dot_at(x, y);
        if (c.publish != nullptr) {
          (void)c.publish(c.dot_channel, &dot, sizeof dot);
        }
        c.dot_sum += dot;
        out[x] = score_from(stats, t, dot);
      }
      c.surface_sum += bits_of(out[x]);
      if (flags.valid()) {
        flags.at(x, y) = flat ? 1U : 0U;
      }
    }
  }
}

/** score_surface() with its dot products from the 16-bit copies in @p buf (widen()), P columns a row. */
template <std::int32_t P>
void score_wide(const TemplateStats& stats, const IntegralRef& integral, ImageF32 surface, ImageU8 flags,
                std::int32_t& flat_count, NccCheck& c, const std::int16_t* buf, std::int32_t stride) noexcept {
  const WideDots<P> dots(buf, stats.height, buf + static_cast<std::ptrdiff_t>(stats.height) * P, stride);
  score_surface(stats, integral, surface, flags, flat_count, c, [&dots](std::int32_t x, std::int32_t y) { return dots(x, y); });
}

/**
 * The surface with its dot products from 16-bit copies when @p wide has room
 * for them (@return true), else nothing done (@return false).
 */
bool score_surface_wide(ConstImageU8 tmpl, const TemplateStats& stats, ConstImageU8 window,
                        const IntegralRef& integral, ImageF32 surface, ImageU8 flags, std::int32_t& flat_count,
                        NccCheck& c, NccWideBuffer wide) noexcept {
  std::int32_t stride = 0;
  if (!widen(tmpl, window, wide, stride)) {
    return false;
  }
  switch (wide_columns(tmpl.width)) {
    case 8:
      score_wide<8>(stats, integral, surface, flags, flat_count, c, wide.data, stride);
      return true;
    case 16:
      score_wide<16>(stats, integral, surface, flags, flat_count, c, wide.data, stride);
      return true;
    case 24:
      score_wide<24>(stats, integral, surface, flags, flat_count, c, wide.data, stride);
      return true;
    case 32:
      score_wide<32>(stats, integral, surface, flags, flat_count, c, wide.data, stride);
      return true;
    default:
      return false;
  }
}

/** The two sums of a checked surface, when asked for. */
void charge_check(const NccCheck* check, ImageF32 surface, bsp::Work& work) noexcept {
  if (check != nullptr) {
    const auto positions = static_cast<std::uint64_t>(surface.width) * static_cast<std::uint64_t>(surface.height);
    work.int_ops += 2U * positions;
  }
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

bsp::Work ncc_score_work(std::int32_t surf_w, std::int32_t surf_h) noexcept {
  const auto positions = static_cast<std::uint64_t>(surf_w) * static_cast<std::uint64_t>(surf_h);
  bsp::Work w;
  w.int_macs = positions * 3U;    // n*dot, sum products
  w.int_ops = positions * 12U;    // integral corners, subtractions
  w.mem_words = positions * 13U;  // the corners (four uint32, four uint64: 12 words), one output
  w.flops = positions * 3U;       // product, convert, clamp
  w.fdivs = positions * 2U;       // square root and division
  return w;
}

bsp::Work ncc_surface_work(std::int32_t tmpl_w, std::int32_t tmpl_h, std::int32_t surf_w,
                           std::int32_t surf_h) noexcept {
  const auto n = static_cast<std::uint64_t>(tmpl_w) * static_cast<std::uint64_t>(tmpl_h);
  const auto positions = static_cast<std::uint64_t>(surf_w) * static_cast<std::uint64_t>(surf_h);
  bsp::Work w = ncc_score_work(surf_w, surf_h);
  w.int_macs += positions * n;        // the dot product
  w.int_ops += positions * (n / 8U);  // row accumulations
  w.mem_words += positions * (n / 2U);  // template and window bytes
  return w;
}

Status ncc_surface(ConstImageU8 tmpl, const TemplateStats& stats, ConstImageU8 window, const IntegralRef& integral,
                   ImageF32 surface, ImageU8 flags, std::int32_t& flat_count, bsp::Work& work,
                   NccCheck* check, NccWideBuffer wide) noexcept {
  flat_count = 0;
  if (!detail::surface_args_ok(tmpl, stats, window, integral, surface, flags)) {
    return Status::kBadInput;
  }
  NccCheck none;
  NccCheck& c = check != nullptr ? *check : none;
  if (!detail::score_surface_wide(tmpl, stats, window, integral, surface, flags, flat_count, c, wide)) {
    detail::RowDots row_dots(tmpl, window, surface.width);
    detail::score_surface(stats, integral, surface, flags, flat_count, c,
                          [&row_dots](std::int32_t x, std::int32_t y) { return row_dots(x, y); });
  }
  work += ncc_surface_work(tmpl.width, tmpl.height, surface.width, surface.height);
  detail::charge_check(check, surface, work);
  return Status::kOk;
}

Status ncc_surface_from_dots(const TemplateStats& stats, const IntegralRef& integral,
                             ImageView<const std::uint32_t> dots, ImageF32 surface, ImageU8 flags,
                             std::int32_t& flat_count, bsp::Work& work, NccCheck* check) noexcept {
  flat_count = 0;
  if (!dots.valid() || !detail::shape_ok(stats, integral, surface, flags) || dots.width != surface.width ||
      dots.height != surface.height) {
    return Status::kBadInput;
  }
  NccCheck none;
  detail::score_surface(stats, integral, surface, flags, flat_count, check != nullptr ? *check : none,
                        [&](std::int32_t x, std::int32_t y) { return dots.at(x, y); });
  work += ncc_score_work(surface.width, surface.height);
  work.mem_words += static_cast<std::uint64_t>(surface.width) * static_cast<std::uint64_t>(surface.height);
  detail::charge_check(check, surface, work);
  return Status::kOk;
}

float ncc_score_at(ConstImageU8 tmpl, const TemplateStats& stats, ConstImageU8 window, const IntegralRef& integral,
                   std::int32_t x, std::int32_t y, bsp::Work& work) noexcept {
  work += ncc_surface_work(tmpl.width, tmpl.height, 1, 1);
  const detail::WindowTerms t = detail::window_terms(integral, x, y, tmpl.width, tmpl.height, stats.n);
  if (t.var_w <= 0) {
    return 0.0F;
  }
  return detail::score_from(stats, t, detail::dot_at(tmpl, window, x, y));
}

std::int64_t ncc_dot_checksum(ConstImageU8 tmpl, const IntegralRef& integral, std::int32_t surf_w,
                              std::int32_t surf_h, bsp::Work& work) noexcept {
  std::int64_t sum = 0;
  for (std::int32_t j = 0; j < tmpl.height; ++j) {
    const std::uint8_t* t = tmpl.row(j);
    for (std::int32_t i = 0; i < tmpl.width; ++i) {
      sum += static_cast<std::int64_t>(t[i]) * static_cast<std::int64_t>(integral.rect_sum(i, j, surf_w, surf_h));
    }
  }
  const auto n = static_cast<std::uint64_t>(tmpl.width) * static_cast<std::uint64_t>(tmpl.height);
  work.int_macs += n;
  work.int_ops += 3U * n;   // the box's corners
  work.mem_words += 4U * n + n / 4U;
  return sum;
}

std::uint64_t surface_digest(ConstImageF32 surface, bsp::Work& work) noexcept {
  std::uint64_t sum = 0U;
  for (std::int32_t y = 0; y < surface.height; ++y) {
    const float* row = surface.row(y);
    for (std::int32_t x = 0; x < surface.width; ++x) {
      sum += detail::bits_of(row[x]);
    }
  }
  const auto positions = static_cast<std::uint64_t>(surface.width) * static_cast<std::uint64_t>(surface.height);
  work.int_ops += positions;
  work.mem_words += positions;
  return sum;
}

}  // namespace trn::vision
