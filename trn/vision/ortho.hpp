/**
 * @file ortho.hpp
 * @brief Orthorectifying resampling: an image brought onto a map-pixel grid that follows the terrain's heights.
 *
 * warp_homography() puts every destination pixel on one plane. Terrain off
 * that plane is displaced in the image by its height times the view's
 * obliquity (parallax), which distorts a landmark's neighbourhood and shifts
 * the correlation peak. Here each destination pixel (x, y) is lifted by its
 * own height above the plane, dz(x, y), known from the map's elevation:
 *   (u w, v w, w) = H (x, y, 1) + dz(x, y) g,   g = K R_MC^T e_z
 * (pose_geometry.hpp: H is the plane's homography, g the image motion of a
 * unit rise). Optionally each destination pixel is the mean of sub x sub
 * bilinear samples over its footprint, a box filter like the map's own pixel
 * means, for when the image is finer than the map.
 */
#pragma once

#include "bsp_tile64/api/work.hpp"
#include "trn/vision/image.hpp"
#include "trn/vision/status.hpp"
#include "trn/vision/warp.hpp"

#include <cstdint>

namespace trn::vision {

/** Largest sub-sampling factor of warp_terrain(). */
inline constexpr std::int32_t kMaxSubsamples = 4;

/** Heights of the destination pixels: an int16 raster (map elevation counts) aligned with the destination. */
struct GridHeights {
  const std::int16_t* first = nullptr;  ///< count under destination pixel (0, 0)
  std::int64_t stride = 0;              ///< counts from one destination row to the next
  double scale_m = 0.1;                 ///< metres per count
  double plane_z_m = 0.0;               ///< height of the plane of H
};

/**
 * Fills @p dst from @p src: destination pixel (x, y) samples the image at
 * H (x, y, 1) + dz g (dehomogenised), dz = first[y stride + x] scale - plane_z,
 * averaged over sub x sub points at offsets ((k + 0.5) / sub - 0.5) inside the
 * pixel when @p sub > 1. A pixel with any sample behind the camera or without
 * its bilinear neighbours gets @p fill and is counted in @p outside_px.
 * Pre: the raster covers the destination.
 * @return kBadInput for invalid views, a null raster or sub out of 1..kMaxSubsamples.
 */
Status warp_terrain(ConstImageU8 src, const Homography& h, const double g[3], const GridHeights& heights,
                    std::int32_t sub, ImageU8 dst, std::uint8_t fill, std::int32_t& outside_px,
                    bsp::Work& work) noexcept;

}  // namespace trn::vision
