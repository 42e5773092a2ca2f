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
 * dp_C/ddth = R_CB [p_B]x; H = J_pi [dp_C/ddp, 0, dp_C/ddth, 0, 0].
 */
#pragma once

#include "bsp_tile64/devices/camera_model.hpp"
#include "bsp_tile64/work.hpp"
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
 * Forms residual, noise and Jacobian of match @p mt against the state @p x.
 * @p min_depth bounds z of both unit bearings; @p sigma_floor_px is the
 * smallest pixel sigma believed. On a status other than kOk, @p out is untouched.
 */
BearingStatus bearing_measurement(const NominalState& x, const CameraGeometry& cam, const Match& mt,
                                  double min_depth, double sigma_floor_px, Meas2& out,
                                  bsp::Work& work) noexcept;

/** Flops of one bearing_measurement. */
inline constexpr std::uint64_t kFlopsBearing = 24 + 3 + 15 + 15 + 10 + 30 + 30 + 30 + 30 + 6;

}  // namespace trn::filter
