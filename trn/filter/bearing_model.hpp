/**
 * @file bearing_model.hpp
 * @brief Landmark bearing measurement: prediction, residual and Jacobian in the normalized image plane.
 *
 * Residual choice: the normalized image plane (x/z, y/z) of the camera frame.
 * It is the pixel position minus the intrinsics, scaled by 1/f, so the
 * matcher's pixel noise maps to it linearly and exactly: R = diag((s/fx)^2,
 * (s/fy)^2). A tangent-plane residual of the unit vector would be as good
 * near the axis but its noise is only approximately isotropic off-axis.
 * Validity needs z > 0 on both sides, which a 90 deg field of view keeps
 * far from zero (z >= cos 55 deg in the corners).
 *
 * Model: p_B = R_MB^T (p_lm - p), p_C = R_BC^T p_B, h = (x_C/z_C, y_C/z_C).
 * With R_MB,true = R_MB Exp(dth): dp_C/ddp = -R_CB R_MB^T,
 * dp_C/ddth = R_CB [p_B]x = [p_C]x R_CB; H = J_pi [dp_C/ddp, 0, dp_C/ddth, 0, 0].
 *
 * What depends on the pose only (R_CM = R_CB R_MB^T, and the matrix that
 * takes the current attitude error into the camera frame) is computed once
 * per image time (bearing_pose()); a frame's matches share it, and each
 * match then costs kFlopsBearing.
 */
#pragma once

#include "bsp_tile64/api/camera_model.hpp"
#include "bsp_tile64/api/work.hpp"
#include "trn/filter/covariance.hpp"
#include "trn/filter/linalg.hpp"
#include "trn/filter/nav_state.hpp"
#include "trn/match.hpp"

namespace trn::filter {

/** Camera mounting and intrinsics as the filter uses them. */
struct CameraGeometry {
  Mat3 r_bc = Mat3::Identity();  ///< camera to body rotation
  double fx_px = 512.0;
  double fy_px = 512.0;
  double inv_fx2 = 1.0 / (512.0 * 512.0);  ///< 1 / fx^2 (the noise in the normalized plane)
  double inv_fy2 = 1.0 / (512.0 * 512.0);
};

/** The camera's pose at an image time, as a bearing reads it (bearing_pose()). */
struct BearingPose {
  Vec3 p_m = Vec3::Zero();         ///< body (camera) position in the map at the image time, m
  Mat3 r_cm = Mat3::Identity();    ///< map to camera: R_CB R_MB^T at the image time
  Mat3 r_cth = Mat3::Identity();   ///< the current attitude error into the camera frame: R_CB R(q_rel)
};

/** Filter view of the board's camera model (row-major r_bc). */
CameraGeometry camera_geometry(const bsp::CameraModel& cam) noexcept;

enum class BearingStatus : std::uint8_t {
  kOk,
  kBadBearing,    ///< measured bearing not in front of the camera, or not finite
  kBehindCamera,  ///< predicted landmark not in front of the camera
  kBadSigma,      ///< sigma_px not finite or not positive
};

/**
 * The pose part of the bearings of an image taken at position @p p_m and
 * attitude @p q_mb; @p q_rel (null: the current time) rotates the attitude
 * error of the current state into the one at the image time
 * (pose_history.hpp). Charges kFlopsBearingPose (+ kFlopsBearingPoseLag).
 */
void bearing_pose(const Vec3& p_m, const Quat& q_mb, const Quat* q_rel, const CameraGeometry& cam, BearingPose& out,
                  bsp::Work& work) noexcept;

/**
 * Forms residual, noise and Jacobian of match @p mt against the camera pose
 * @p pose. @p min_depth bounds z of both unit bearings; @p sigma_floor_px is
 * the smallest pixel sigma believed. On a status other than kOk, @p out is
 * untouched. The Jacobian's attitude columns are on the current error state
 * (pose.r_cth).
 */
BearingStatus bearing_measurement(const BearingPose& pose, const CameraGeometry& cam, const Match& mt,
                                  double min_depth, double sigma_floor_px, Meas2& out,
                                  bsp::Work& work) noexcept;

/** The same against the nominal state @p x at its own time (its pose, then the bearing). */
BearingStatus bearing_measurement(const NominalState& x, const CameraGeometry& cam, const Match& mt,
                                  double min_depth, double sigma_floor_px, Meas2& out,
                                  bsp::Work& work) noexcept;

// Counted by hand, every add and multiply (a 3 x 3 product 27 mul + 18 add).
/** Flops of bearing_pose at the current time: R_MB from the quaternion, R_CB R_MB^T. */
inline constexpr std::uint64_t kFlopsBearingPose = 24 + 45;
/** Flops bearing_pose adds for a past time: R(q_rel), R_CB R(q_rel). */
inline constexpr std::uint64_t kFlopsBearingPoseLag = 24 + 45;
/**
 * Flops of one bearing_measurement from a pose: the two depth tests (squared,
 * no root), p_lm - p, p_C, the normalized coordinates, H_p, J_pi [p_C]x,
 * H_th, residual, noise.
 */
inline constexpr std::uint64_t kFlopsBearing = 8 + 3 + 15 + 7 + 2 + 18 + 12 + 30 + 4 + 3;
/** Divisions of one bearing_measurement: 1 / z of the prediction and of the measured bearing. */
inline constexpr std::uint64_t kFdivsBearing = 2;

}  // namespace trn::filter
