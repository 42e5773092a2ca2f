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
 */
#pragma once

#include "bsp_tile64/work.hpp"
#include "trn/vision/image.hpp"
#include "trn/vision/integral.hpp"
#include "trn/vision/status.hpp"

#include <cstdint>

namespace trn::vision {

/** Largest template, pixels (128 x 128). */
inline constexpr std::int64_t kNccMaxTemplatePixels = std::int64_t{128} * 128;
// A template-window dot product is at most 255^2 * n; it must fit the uint32 accumulator
// with room for the sign-free int32 view used in the numerator.
static_assert(65025ULL * static_cast<std::uint64_t>(kNccMaxTemplatePixels) < (1ULL << 31U),
              "dot products must fit 31 bits");
// n * dot <= 255^2 * n^2 ~ 1.7e13 and sum(T) * sum(W) likewise: far inside int64.

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
 * @return kBadInput when sizes disagree or the template is flat (surface untouched).
 */
Status ncc_surface(ConstImageU8 tmpl, const TemplateStats& stats, ConstImageU8 window, const IntegralRef& integral,
                   ImageF32 surface, ImageU8 flags, std::int32_t& flat_count, bsp::Work& work) noexcept;

/** Work one surface costs, as ncc_surface() counts it (for budgets and tests). */
bsp::Work ncc_surface_work(std::int32_t tmpl_w, std::int32_t tmpl_h, std::int32_t surf_w,
                           std::int32_t surf_h) noexcept;

}  // namespace trn::vision
