/**
 * @file fine.hpp
 * @brief Fine stage: one landmark template (21x21 class) over a small search window, sub-pixel.
 *
 * The caller predicts where the landmark falls in the image (already brought to
 * map geometry with warp.hpp), cuts a window of template + 2 * search radius
 * around it, and calls fine_match(). With the default capacities a window is at
 * most 80 px (a 31 px template searched +/- 24 px); a workspace is ~110 KiB and
 * belongs in tile RAM (carved) or static storage, one per tile.
 */
#pragma once

#include "bsp_tile64/api/work.hpp"
#include "trn/vision/correlator.hpp"

#include <cstdint>

namespace trn::vision {

inline constexpr std::int32_t kFineTemplatePx = 21;     ///< default landmark template side
inline constexpr std::int32_t kFineMaxTemplatePx = 31;  ///< largest fine template side
inline constexpr std::int32_t kFineMaxSearchPx = 24;    ///< largest search radius
inline constexpr std::int32_t kFineMaxWindowPx = kFineMaxTemplatePx + 2 * kFineMaxSearchPx;
static_assert(kFineMaxWindowPx <= 80, "fine workspace stays inside its tile RAM share");

using FineWorkspace = CorrelatorWorkspace<kFineMaxWindowPx, true>;

/**
 * Fine-stage checks. min_peak 0.8: of 500 unrelated pairs of smooth 21x21 / 49x49
 * textures, 10 peaked at >= 0.7 and none at >= 0.8, while true matches with 4 DN
 * noise peaked at >= 0.948 (docs/VISION.md).
 */
inline constexpr QualityParams kFineQuality{0.8F, 0.8F, 3, 1, Subpixel::kParaboloid};

/**
 * Matches @p tmpl (side <= kFineMaxTemplatePx) inside @p window.
 * Post (accepted): the template's top-left lies at window pixel (out.x_px, out.y_px),
 * so its centre is at (x_px + (tw - 1) / 2, y_px + (th - 1) / 2).
 * @return kTooLarge for a template or window above the capacities; else as correlate().
 */
Status fine_match(ConstImageU8 tmpl, ConstImageU8 window, const QualityParams& q, FineWorkspace& ws,
                  MatchResult& out, bsp::Work& work) noexcept;

}  // namespace trn::vision
