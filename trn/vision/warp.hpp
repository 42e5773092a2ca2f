/**
 * @file warp.hpp
 * @brief Resampling of an image patch under an affine map or a homography, bilinear.
 *
 * Transforms map destination pixel coordinates to source pixel coordinates
 * (inverse mapping, so every destination pixel gets exactly one value):
 *   affine:     xs = a[0] x + a[1] y + a[2],  ys = a[3] x + a[4] y + a[5]
 *   homography: (xs, ys, w) = H (x, y, 1), xs /= w, ys /= w, H row-major.
 * Pixel centres are at integer coordinates (camera_model.hpp). Source samples
 * need all four bilinear neighbours inside the source; otherwise the
 * destination pixel gets the fill value and is counted as outside.
 * The integrator uses this to bring a camera patch into map geometry from the
 * altitude and attitude, or a map template into image geometry.
 */
#pragma once

#include "bsp_tile64/api/work.hpp"
#include "trn/vision/image.hpp"
#include "trn/vision/status.hpp"

#include <cstdint>

namespace trn::vision {

/** Destination-to-source affine map. */
struct Affine2 {
  double a[6] = {1.0, 0.0, 0.0, 0.0, 1.0, 0.0};
};

/** Destination-to-source homography, row-major 3x3. */
struct Homography {
  double h[9] = {1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0};
};

/** Inverse of an affine map; false (and @p inv untouched) when singular. */
bool invert_affine(const Affine2& m, Affine2& inv) noexcept;

/**
 * Bilinear sample of @p src at (x, y), rounded to the nearest DN (half up);
 * false when a neighbour is outside. Inline: it is the warps' inner loop.
 * Inside the image x and y are non-negative, so truncation is floor and
 * `t + (v - t >= 0.5)` is std::lround, exactly (v - t is exact below 2^52).
 */
inline bool sample_bilinear(ConstImageU8 src, double x, double y, std::uint8_t& value) noexcept {
  // Exact integer positions on the last row/column need no right/lower neighbour.
  if (!(x >= 0.0 && y >= 0.0 && x <= src.width - 1 && y <= src.height - 1)) {
    return false;
  }
  const auto x0 = static_cast<std::int32_t>(x);
  const auto y0 = static_cast<std::int32_t>(y);
  const double fx = x - static_cast<double>(x0);
  const double fy = y - static_cast<double>(y0);
  const std::int32_t x1 = x0 + 1 < src.width ? x0 + 1 : x0;
  const std::int32_t y1 = y0 + 1 < src.height ? y0 + 1 : y0;
  const std::uint8_t* r0 = src.row(y0);
  const std::uint8_t* r1 = src.row(y1);
  const double top = r0[x0] + fx * (r0[x1] - r0[x0]);
  const double bot = r1[x0] + fx * (r1[x1] - r1[x0]);
  const double v = top + fy * (bot - top);  // in [0, 255]: rounding stays in range
  const auto t = static_cast<std::int32_t>(v);
  value = static_cast<std::uint8_t>(t + (v - static_cast<double>(t) >= 0.5 ? 1 : 0));
  return true;
}

/**
 * Fills @p dst from @p src under @p dst_to_src.
 * @param outside_px destination pixels that fell outside the source (given @p fill)
 * @return kBadInput for invalid views.
 */
Status warp_affine(ConstImageU8 src, const Affine2& dst_to_src, ImageU8 dst, std::uint8_t fill,
                   std::int32_t& outside_px, bsp::Work& work) noexcept;

/** As warp_affine(), under a homography; points with w <= 0 count as outside. */
Status warp_homography(ConstImageU8 src, const Homography& dst_to_src, ImageU8 dst, std::uint8_t fill,
                       std::int32_t& outside_px, bsp::Work& work) noexcept;

}  // namespace trn::vision
