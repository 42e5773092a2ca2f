/**
 * @file ncc.hpp
 * @brief Zero-mean normalized cross-correlation of a template over a search window.
 *
 * The score at offset (x, y) is OpenCV's TM_CCOEFF_NORMED:
 *   r = sum (T - mean T)(W - mean W) / sqrt(sum (T - mean T)^2 * sum (W - mean W)^2)
 * over the template-sized window W at (x, y). Multiplied through by n^2 (n the
 * template's pixel count) every term is an exact integer:
 *   num = n * sum(T W) - sum(T) sum(W),  var_t = n sum(T^2) - sum(T)^2,
 *   var_w = n sum(W^2) - sum(W)^2,       r = num / sqrt(var_t * var_w).
 * The dot products run in uint32 (bound below), window sums come from the
 * integral image, the template's sums are computed once. Only the final
 * product, square root and division are floating point.
 * A window with var_w == 0 (flat) scores 0 and is flagged; there is no division by zero.
 *
 * Checksum of the dot products (a checked correlation, correlator.hpp). Summed
 * over every offset o of the surface, sum_o sum_p T(p) W(p + o) =
 * sum_p T(p) B(p), where B(p) is the sum of the window over the surf_w x surf_h
 * box at p: one integral-image lookup per template pixel (ncc_dot_checksum),
 * against n lookups per offset for the surface. Both sides are integers, so
 * the identity is exact: any one wrong dot product makes it fail, whatever its
 * size. A flat window's dot product is not computed; it is exactly
 * sum(T) * sum(W) / n (all its pixels are sum(W) / n), and that enters the sum.
 */
#pragma once

#include "bsp_tile64/api/work.hpp"
#include "trn/vision/image.hpp"
#include "trn/vision/integral.hpp"
#include "trn/vision/status.hpp"

#include <cstddef>
#include <cstdint>

namespace trn::vision {

/** Largest template, pixels (128 x 128). */
inline constexpr std::int64_t kNccMaxTemplatePixels = std::int64_t{128} * 128;
// A template-window dot product is at most 255^2 * n; it must fit the uint32 accumulator
// with room for the sign-free int32 view used in the numerator.
static_assert(65025ULL * static_cast<std::uint64_t>(kNccMaxTemplatePixels) < (1ULL << 31U),
              "dot products must fit 31 bits");
// n * dot <= 255^2 * n^2 ~ 1.7e13 and sum(T) * sum(W) likewise: far inside int64.
// The sum of every dot product of a surface is at most 255^2 * n * positions, positions
// below kIntegralMaxPixels: 2^16 * 2^14 * 2^24 = 2^54, inside int64 (ncc_dot_checksum likewise).
static_assert(65025.0 * static_cast<double>(kNccMaxTemplatePixels) * static_cast<double>(kIntegralMaxPixels) <
                  0x1p62,
              "dot-product sums must fit int64");

/** A publication hook (bsp::publish_filter's form): where a silent corruption of a result is injected. */
using PublishFn = bool (*)(std::uint32_t channel, void* data, std::size_t bytes) noexcept;

/** What ncc_surface() publishes and sums for a checked correlation (all optional). */
struct NccCheck {
  PublishFn publish = nullptr;   ///< called on each dot product before it is used (nullptr: none)
  std::uint32_t dot_channel = 0U;
  std::int64_t dot_sum = 0;      ///< out: the sum of every position's dot product (see the file comment)
  std::uint64_t surface_sum = 0; ///< out: the sum of the surface's bit patterns as written (surface_digest)
};

/** Widest template whose dot products ncc_surface() takes from 16-bit copies (NccWideBuffer). */
inline constexpr std::int32_t kNccWideMaxTemplatePx = 32;

/**
 * Room for ncc_surface()'s 16-bit copies of a template and its window: the
 * template's rows padded with zeros to its width rounded up to 8, the window's
 * rows to (window width - template width + that). Host speed only: the same
 * integers, the same emulated work. Entries for windows up to @p max_window_px
 * and templates up to kNccWideMaxTemplatePx.
 */
constexpr std::int64_t ncc_wide_entries(std::int32_t max_window_px) noexcept {
  return std::int64_t{kNccWideMaxTemplatePx} * kNccWideMaxTemplatePx +
         std::int64_t{max_window_px} * (std::int64_t{max_window_px} + 7);
}

/** Scratch for ncc_surface()'s 16-bit copies (none: the dot products come from the bytes). */
struct NccWideBuffer {
  std::int16_t* data = nullptr;
  std::int64_t entries = 0;  ///< capacity of data
};

/** Template statistics, computed once per template. */
struct TemplateStats {
  std::int32_t width = 0;
  std::int32_t height = 0;
  std::int64_t n = 0;      ///< pixel count
  std::int64_t sum = 0;    ///< sum of values
  std::int64_t var_n2 = 0; ///< n * sum(T^2) - sum(T)^2 = n^2 * variance
  bool flat = true;        ///< var_n2 == 0: no texture, NCC undefined
};

/**
 * Computes the statistics of @p tmpl.
 * @return kBadInput for an invalid view, kTooLarge above kNccMaxTemplatePixels.
 */
Status template_stats(ConstImageU8 tmpl, TemplateStats& out, bsp::Work& work) noexcept;

/**
 * Correlation surface of @p tmpl over @p window.
 * @param stats template_stats() of @p tmpl
 * @param integral built over @p window (same width and height)
 * @param surface output of (W - tw + 1) x (H - th + 1); entry (x, y) is the score of
 *        the template's top-left at window pixel (x, y), in [-1, 1]
 * @param flags optional (an invalid view means none), same size as @p surface:
 *        1 where the window was flat (score forced to 0), else 0
 * @param flat_count number of flat windows
 * @param check optional: each dot product is published there before it is used, and the
 *        sums of the dot products and of the surface's bits are returned (charged to @p work)
 * @param wide optional scratch: with room for the copies (ncc_wide_entries) and a template
 *        at most kNccWideMaxTemplatePx wide, the dot products are taken from 16-bit copies,
 *        which the host's vector units multiply and add in pairs. Same integers, same
 *        scores, same charge to @p work either way.
 * @return kBadInput when sizes disagree or the template is flat (surface untouched).
 */
Status ncc_surface(ConstImageU8 tmpl, const TemplateStats& stats, ConstImageU8 window, const IntegralRef& integral,
                   ImageF32 surface, ImageU8 flags, std::int32_t& flat_count, bsp::Work& work,
                   NccCheck* check = nullptr, NccWideBuffer wide = {}) noexcept;

/**
 * The correlation surface from dot products computed elsewhere (transform_dots.hpp):
 * @p dots (x, y) is sum T W with the template at window offset (x, y), for every
 * offset of @p surface. The rest is ncc_surface()'s, by the same code: given the
 * same dot products, the same scores, flags, flat count, publications (each
 * non-flat offset's dot product, in place before its use, in the same order) and
 * check sums, bit for bit. A flat window's dot product is neither read nor
 * published; it enters the sum by its exact value, as in ncc_surface().
 * @param integral built over the window the dot products came from
 * @return kBadInput when sizes disagree or the template is flat (surface untouched).
 */
Status ncc_surface_from_dots(const TemplateStats& stats, const IntegralRef& integral,
                             ImageView<const std::uint32_t> dots, ImageF32 surface, ImageU8 flags,
                             std::int32_t& flat_count, bsp::Work& work, NccCheck* check = nullptr) noexcept;

/**
 * The score ncc_surface() gives offset (@p x, @p y), computed alone by the same
 * operations in the same order: bit for bit the surface's value (0 for a flat
 * window). Pre: the arguments passed ncc_surface()'s checks and (x, y) is on its surface.
 */
float ncc_score_at(ConstImageU8 tmpl, const TemplateStats& stats, ConstImageU8 window, const IntegralRef& integral,
                   std::int32_t x, std::int32_t y, bsp::Work& work) noexcept;

/**
 * The reference of NccCheck::dot_sum: sum_p T(p) B(p), B(p) the sum of the
 * window over the @p surf_w x @p surf_h box at template pixel p, from @p integral
 * (built over the window). Pre: the surface fits the window (as ncc_surface()).
 */
std::int64_t ncc_dot_checksum(ConstImageU8 tmpl, const IntegralRef& integral, std::int32_t surf_w,
                              std::int32_t surf_h, bsp::Work& work) noexcept;

/** The sum of the bit patterns of @p surface's values (NccCheck::surface_sum of an intact surface). */
std::uint64_t surface_digest(ConstImageF32 surface, bsp::Work& work) noexcept;

/**
 * Work of the scores of a surface from given dot products (window sums, numerator,
 * square root, division); ncc_surface_from_dots() adds one word per offset to read its dot product.
 */
bsp::Work ncc_score_work(std::int32_t surf_w, std::int32_t surf_h) noexcept;

/** Work one surface costs, as ncc_surface() counts it: the dot products plus ncc_score_work() (for budgets and tests). */
bsp::Work ncc_surface_work(std::int32_t tmpl_w, std::int32_t tmpl_h, std::int32_t surf_w,
                           std::int32_t surf_h) noexcept;

}  // namespace trn::vision
