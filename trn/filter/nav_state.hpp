/**
 * @file nav_state.hpp
 * @brief Nominal navigation state of the error-state filter and its initial estimate.
 */
#pragma once

#include "trn/filter/linalg.hpp"

namespace trn::filter {

/** Nominal (full) state; the 15 error states live in the covariance only. */
struct NominalState {
  Vec3 p_m = Vec3::Zero();            ///< position in the map frame (ENU), m
  Vec3 v_mps = Vec3::Zero();          ///< velocity in the map frame, m/s
  Quat q_mb = Quat::Identity();       ///< attitude, body (FRD) to map
  Vec3 bg_rads = Vec3::Zero();        ///< gyro bias, rad/s
  Vec3 ba_mps2 = Vec3::Zero();        ///< accelerometer bias, m/s^2
};

/**
 * Initial estimate: the nominal state plus 1-sigma uncertainties per axis.
 * Bias sigmas of zero mean "take them from the IMU specification"
 * (turn-on and in-run combined).
 */
struct InitialEstimate {
  double t_s = 0.0;                   ///< time of the estimate, emulated s
  NominalState x{};
  Vec3 sigma_p_m = Vec3::Constant(100.0);
  Vec3 sigma_v_mps = Vec3::Constant(1.0);
  Vec3 sigma_th_rad = Vec3::Constant(1e-3);  ///< body-frame attitude error sigma
  Vec3 sigma_bg_rads = Vec3::Zero();
  Vec3 sigma_ba_mps2 = Vec3::Zero();
};

}  // namespace trn::filter
