/**
 * @file pose_geometry.hpp
 * @brief Pinhole projection at a pose, and the homography from a map-plane pixel grid to the image.
 *
 * Frames (bsp_tile64/api/frames.hpp, camera_model.hpp):
 * - map M: x east, y north, z up, metres;
 * - body B: x forward, y right, z down; R_MB (from q_mb, w x y z) maps body vectors to map;
 * - camera C: z along the optical axis, x along image columns, y along rows;
 *   R_BC = CameraModel::r_bc maps camera vectors to body, so R_MC = R_MB R_BC.
 * The camera centre is the body origin (no lever arm, as in the device model
 * and the filter's bearing model), so a map point P is, in the camera frame,
 *   p_C = R_MC^T (P - c),   u = cx + fx x_C / z_C,   v = cy + fy y_C / z_C,
 * with pixel centres at integer (u, v).
 *
 * Map-plane grid: a square grid of pixels of side s (metres) on the horizontal
 * plane z = z0, north-up like the map layers (columns go east, rows go south).
 * Grid pixel (i, j) is the map point
 *   P(i, j) = O + i s e_x - j s e_y,   O = (ox, oy, z0) the centre of grid pixel (0, 0).
 * Substituting, p_C(i, j) = i a_i + j a_j + a_0 with
 *   a_i = s R_MC^T e_x,  a_j = -s R_MC^T e_y,  a_0 = R_MC^T (O - c),
 * and with K = [fx 0 cx; 0 fy cy; 0 0 1] the homogeneous image point is
 *   (u w, v w, w) = K [a_i a_j a_0] (i, j, 1):   H = K [a_i a_j a_0].
 * H maps grid pixels (destination) to image pixels (source): exactly the
 * dst-to-src homography warp_homography() takes to resample the image into
 * map geometry. w = z_C, so w > 0 means the point is in front of the camera.
 */
#pragma once

#include "bsp_tile64/api/camera_model.hpp"
#include "bsp_tile64/api/work.hpp"
#include "trn/vision/warp.hpp"

#include <cstdint>

namespace trn::vision {

/** Camera centre and orientation at one instant, as the projections use them. */
struct PoseGeometry {
  double c_m[3] = {0.0, 0.0, 0.0};                          ///< camera centre (= body origin), map frame
  double r_mc[9] = {1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0};  ///< camera to map, row-major
};

/** Flops charged for one projection (rotation 15, offsets 3, pinhole 4; one reciprocal as an fdiv). */
inline constexpr std::uint64_t kFlopsProject = 22;

/** True when @p cam has a positive size, finite positive focal lengths and a finite mounting. */
bool camera_ok(const bsp::CameraModel& cam) noexcept;

/**
 * Pose from a body position and a body-to-map quaternion (w, x, y, z; normalised
 * here) under the mounting of @p cam.
 * @return false (out untouched) for a non-finite input or a quaternion of norm < 0.5.
 */
bool make_pose(const double p_m[3], const double q_mb[4], const bsp::CameraModel& cam, PoseGeometry& out,
               bsp::Work& work) noexcept;

/** Map point @p p in the camera frame: p_C = R_MC^T (p - c). */
void to_camera(const PoseGeometry& pose, const double p[3], double p_c[3]) noexcept;

/** Camera-frame vector @p v_c in the map frame: R_MC v_c. */
void to_map(const PoseGeometry& pose, const double v_c[3], double v_m[3]) noexcept;

/**
 * Projects map point @p p to pixel (@p u, @p v).
 * @param z_c depth along the optical axis (may be null)
 * @return false (u, v untouched) when the point is not at least 1 mm in front of the camera.
 */
bool project_point(const bsp::CameraModel& cam, const PoseGeometry& pose, const double p[3], double& u, double& v,
                   double* z_c, bsp::Work& work) noexcept;

/** Unit ray in the camera frame through pixel (@p u, @p v): normalise((u - cx) / fx, (v - cy) / fy, 1). */
void pixel_ray(const bsp::CameraModel& cam, double u, double v, double w_c[3], bsp::Work& work) noexcept;

/** A north-up grid of square pixels on a horizontal plane (see the file comment). */
struct PlaneGrid {
  double origin_m[3] = {0.0, 0.0, 0.0};  ///< centre of grid pixel (0, 0); origin_m[2] is the plane's height
  double m_per_px = 1.0;                 ///< pixel side
};

/** H = K [a_i a_j a_0]: grid pixel (i, j) to image pixel (file comment). */
Homography plane_homography(const bsp::CameraModel& cam, const PoseGeometry& pose, const PlaneGrid& grid,
                            bsp::Work& work) noexcept;

/**
 * g = K R_MC^T e_z: how a grid point raised by dz metres moves in homogeneous
 * image coordinates, (u w, v w, w) = H (i, j, 1) + dz g (terrain off the plane).
 */
void vertical_column(const bsp::CameraModel& cam, const PoseGeometry& pose, double g[3]) noexcept;

/** Applies @p h to (@p x, @p y); false (outputs untouched) when w <= 1e-9 (behind the camera). */
bool apply_homography(const Homography& h, double x, double y, double& u, double& v) noexcept;

/** (u w, v w, w) = H (x, y, 1) + dz g, dehomogenised; false (outputs untouched) when w <= 1e-9. */
bool apply_lifted(const Homography& h, const double g[3], double dz, double x, double y, double& u,
                  double& v) noexcept;

/**
 * Largest singular value of the Jacobian d(u, v) / d(x, y) of @p h at (@p x, @p y):
 * image pixels per grid pixel along the most stretched direction.
 * @return 0 when the point is behind the camera.
 */
double homography_scale(const Homography& h, double x, double y, bsp::Work& work) noexcept;

}  // namespace trn::vision
