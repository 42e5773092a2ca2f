/**
 * @file coarse.hpp
 * @brief Coarse stage: removes kilometre-level position error by a wide, downsampled NCC search.
 *
 * Both the map search region and the camera image (already in map geometry,
 * see warp.hpp) are box-filtered and decimated by `factor`; the central
 * template_px square of the small image is correlated (spatial NCC, integer
 * dot products) over the whole small map region. At 12 m/px and factor 4 a
 * 1024 px map region is 256 coarse px (48 m each): a +/- 3 km error is
 * +/- 64 coarse px. Work, spatially: (256 - 64 + 1)^2 positions x 4096 MACs
 * ~ 153 M MACs. CoarseParams::method = kTransform computes the same dot products
 * by the exact integer transform (transform_dots.hpp) instead: the same
 * CoarseResult bit for bit, about a fifth of the TILE64 cycles (docs/VISION.md).
 * A workspace is ~1.7 MiB: DDR or static storage, one per coarse task.
 */
#pragma once

#include "bsp_tile64/api/work.hpp"
#include "trn/vision/correlator.hpp"
#include "trn/vision/image.hpp"

#include <cstdint>

namespace trn::vision {

inline constexpr std::int32_t kCoarseMaxPx = 256;        ///< side capacity at the coarse scale
inline constexpr std::int32_t kCoarseMaxFactor = 16;     ///< largest decimation factor
inline constexpr std::int32_t kCoarseMaxTemplatePx = 128;  ///< largest coarse template side

struct CoarseParams {
  std::int32_t factor = 4;        ///< decimation factor (box filter side), 1..kCoarseMaxFactor
  std::int32_t template_px = 64;  ///< template side at the coarse scale
  QualityParams quality{0.5F, 0.8F, 4, 1, Subpixel::kParaboloid};
  CorrelationMethod method = CorrelationMethod::kSpatial;  ///< how the dot products are computed (same result)
};

struct CoarseWorkspace {
  FixedImage<std::uint8_t, kCoarseMaxPx, kCoarseMaxPx> map_small;
  FixedImage<std::uint8_t, kCoarseMaxPx, kCoarseMaxPx> image_small;
  CorrelatorWorkspace<kCoarseMaxPx> corr;
  TransformWorkspace<kCoarseMaxPx> transform;  ///< planes of CorrelationMethod::kTransform
};

struct CoarseResult {
  MatchResult match;  ///< at the coarse scale
  double x_px = 0.0;  ///< image top-left in map-region pixels (full resolution), valid when accepted
  double y_px = 0.0;

  constexpr bool accepted() const noexcept { return match.accepted(); }
};

/**
 * Box-filter decimation: out(x, y) = rounded mean of the factor x factor block at (x f, y f).
 * Pre: out.width == in.width / factor and out.height == in.height / factor (remainder dropped).
 * @return kBadInput for invalid views, factor out of 1..kCoarseMaxFactor, or a size mismatch.
 */
Status downsample_box(ConstImageU8 in, std::int32_t factor, ImageU8 out, bsp::Work& work) noexcept;

/**
 * Finds where @p image lies inside @p map_region (same scale and orientation).
 * Post (accepted): image pixel (0, 0) lies at map-region pixel (out.x_px, out.y_px).
 * @return kBadInput for bad parameters or an image smaller than the template,
 *         kTooLarge when a decimated input exceeds kCoarseMaxPx.
 */
Status coarse_match(ConstImageU8 map_region, ConstImageU8 image, const CoarseParams& p, CoarseWorkspace& ws,
                    CoarseResult& out, bsp::Work& work) noexcept;

/** coarse_match() before its correlation: the decimated window and the template in the workspace. */
struct CoarsePrepared {
  ConstImageU8 window{};       ///< the decimated map region (ws.map_small)
  ConstImageU8 tmpl{};         ///< the central template_px square of the decimated image (in ws.image_small)
  std::int32_t tx0 = 0;        ///< the template's top-left in the decimated image
  std::int32_t ty0 = 0;
  std::int32_t surface_w = 0;  ///< offsets per row of the correlation surface
  std::int32_t surface_h = 0;  ///< rows of the correlation surface
};

/**
 * coarse_match()'s first half: decimates both inputs into @p ws and picks the
 * template, for a correlation run elsewhere (in bands: correlator.hpp).
 * @return as coarse_match().
 */
Status coarse_prepare(ConstImageU8 map_region, ConstImageU8 image, const CoarseParams& p, CoarseWorkspace& ws,
                      CoarsePrepared& out, bsp::Work& work) noexcept;

/** coarse_match()'s second half: the correlation's outcome @p m as the image's place in the map region. */
void coarse_result(const CoarsePrepared& prep, const CoarseParams& p, const MatchResult& m, CoarseResult& out) noexcept;

}  // namespace trn::vision
