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

#include "bsp_tile64/work.hpp"
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

/** Bilinear sample of @p src at (x, y); false when a neighbour is outside. */
bool sample_bilinear(ConstImageU8 src, double x, double y, std::uint8_t& value) noexcept;

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
