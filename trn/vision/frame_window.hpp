/**
 * @file frame_window.hpp
 * @brief Internals of the per-frame vision (frame.hpp): input checks and a landmark's search window in map geometry.
 *
 * A landmark's search window is a square of map-sized pixels around it,
 * north-up, resampled from the frame through the prior pose:
 * - window pixel (i, j) is the plane point of map pixel
 *   (col0 + shift_col + i, row0 + shift_row + j) on the horizontal plane at the
 *   landmark's height z0, mapped to the image by H = K [a_i a_j a_0]
 *   (pose_geometry.hpp);
 * - with terrain, that point is lifted by the height of map pixel
 *   (col0 + i, row0 + j) above z0: (u w, v w, w) = H (i, j, 1) + dz g (ortho.hpp).
 * Without a shift, each pixel is lifted by its own height: exact when the
 * prior is. When the prior is off by d map pixels (fractional), the frame
 * shows the landmark's neighbourhood (and its relief) around window position
 * c + d, so a second window is cut with shift = d: its pixels sit on the plane
 * around the match but carry the relief of the landmark's own neighbourhood.
 */
#pragma once

#include "bsp_tile64/api/camera_model.hpp"
#include "bsp_tile64/api/work.hpp"
#include "trn/vision/frame.hpp"
#include "trn/vision/pose_geometry.hpp"
#include "trn/vision/warp.hpp"

#include <cstdint>

namespace trn::vision::detail {

inline constexpr std::int32_t kHalfTemplate = (kFineTemplatePx - 1) / 2;

/** True when all @p n values are finite and >= 0. */
bool finite_nonneg(const double* v, std::int32_t n) noexcept;

/** True when @p frame is a valid view of the camera's size. */
bool frame_matches(ConstImageU8 frame, const bsp::CameraModel& cam) noexcept;

/** True when @p map has an image, an elevation and a finite geometry. */
bool map_ok(const MapView& map) noexcept;

/** True when the vector is not all zero. */
bool nonzero3(const double v[3]) noexcept;

/** The prior as a pose; false for a bad camera or a non-finite pose. */
bool prior_pose(const PosePrior& prior, const bsp::CameraModel& cam, PoseGeometry& pose, bsp::Work& work) noexcept;

/** A landmark's search window (file comment). */
struct Window {
  Homography h;
  double g[3] = {0.0, 0.0, 0.0};  ///< zero without terrain
  std::int32_t col0 = 0;          ///< map column of the height under window pixel (0, 0)
  std::int32_t row0 = 0;          ///< map row of the height under window pixel (0, 0)
  std::int32_t side = 0;
  double z0_m = 0.0;              ///< plane height (the landmark's)
};

/**
 * Window of side kFineTemplatePx + 2 r around @p lm, its plane shifted by
 * (@p shift_col, @p shift_row) map pixels (fractional).
 * @return false when the heights it needs (col0, row0, side) leave the map.
 */
bool make_window(const bsp::CameraModel& cam, const PoseGeometry& pose, const MapView& map, const Landmark& lm,
                 std::int32_t radius_px, bool terrain, double shift_col, double shift_row, Window& out,
                 bsp::Work& work) noexcept;

/** Height above the window's plane of the point under window position (x, y) (0 without terrain). */
double window_dz(const MapView& map, const Window& win, double x, double y) noexcept;

/** Image position of window position (x, y); false behind the camera. */
bool window_to_image(const MapView& map, const Window& win, double x, double y, double& u, double& v) noexcept;

/**
 * True when every corner of the window lands at least a pixel inside the frame
 * (so, but for terrain bulging out between corners, the whole window does).
 */
bool window_inside(const bsp::CameraModel& cam, const MapView& map, const Window& win, bsp::Work& work) noexcept;

}  // namespace trn::vision::detail
