/**
 * @file peak.hpp
 * @brief Correlation peak: sub-pixel location and the quality checks that reject doubtful matches.
 *
 * Sub-pixel methods (QualityParams::subpixel):
 * - kParabola: a 3-point parabola per axis through the peak and its two
 *   neighbours along that axis, d = (s[-1] - s[+1]) / (2 (s[-1] - 2 s[0] + s[+1])),
 *   clamped to [-0.5, 0.5]. Cheap, but blind to a peak elongated along a
 *   diagonal (it ignores the xy term).
 * - kParaboloid (default): least-squares fit of s = a + b x + c y + d x^2 + e xy + f y^2
 *   to the 3x3 neighbourhood and its vertex; falls back to the per-axis
 *   parabola when the fit is not a maximum or its vertex leaves the
 *   neighbourhood (|offset| > 1).
 * Checks, in order: peak height (min_peak), peak on the surface edge (the true
 * maximum may lie outside the search and the parabola lacks a neighbour), and
 * ambiguity: the highest local maximum outside a disc of exclusion_radius_px
 * around the peak must stay below max_second_ratio * peak (repetitive texture
 * such as stripes or checkers gives near-equal peaks and is rejected).
 */
#pragma once

#include "bsp_tile64/api/work.hpp"
#include "trn/vision/image.hpp"

#include <cstdint>

namespace trn::vision {

/** Why a match was rejected. */
enum class Reject : std::uint8_t {
  kNone,          ///< accepted
  kBadInput,      ///< invalid sizes or buffers
  kFlatTemplate,  ///< the template has no texture
  kFlatWindow,    ///< every window position is flat
  kLowPeak,       ///< best score below min_peak
  kOnEdge,        ///< best score on the edge of the search surface
  kAmbiguous,     ///< a second peak too close in height (repetitive texture)
  kCheckFailed,   ///< the surface failed its checks after every recomputation (correlator.hpp)
};

enum class Subpixel : std::uint8_t { kParabola, kParaboloid };

struct QualityParams {
  float min_peak = 0.6F;              ///< lowest acceptable NCC peak
  float max_second_ratio = 0.8F;      ///< second peak must be below this fraction of the peak
  std::int32_t exclusion_radius_px = 3;  ///< second peak searched outside this radius, surface px
  std::int32_t edge_margin_px = 1;    ///< peak must be at least this far inside the surface edge
  Subpixel subpixel = Subpixel::kParaboloid;  ///< peak refinement method
};

struct Peak {
  std::int32_t ix = 0;      ///< integer peak column in the surface
  std::int32_t iy = 0;      ///< integer peak row in the surface
  double x_px = 0.0;        ///< sub-pixel peak column
  double y_px = 0.0;        ///< sub-pixel peak row
  float score = 0.0F;       ///< surface value at the integer peak
  float second = -1.0F;     ///< highest local maximum outside the exclusion disc (-1 if none)
  Reject reason = Reject::kBadInput;

  constexpr bool accepted() const noexcept { return reason == Reject::kNone; }
};

/** 3-point parabola vertex offset from samples left, centre, right; 0 when not a maximum. */
double parabola_offset(double left, double centre, double right) noexcept;

/**
 * Vertex of the least-squares quadratic through the 3x3 samples @p s (row-major,
 * centre s[4]) as an offset from the centre.
 * @return false (offsets untouched) when the fit is not a maximum or |offset| > 1.
 */
bool paraboloid_offset(const double s[9], double& dx, double& dy) noexcept;

/**
 * Finds the peak of @p surface, refines it and applies the checks of @p q
 * (order: height, ambiguity, edge).
 * Post: x_px, y_px are set whenever the surface is valid, even when rejected.
 */
Peak find_peak(ConstImageF32 surface, const QualityParams& q, bsp::Work& work) noexcept;

}  // namespace trn::vision
