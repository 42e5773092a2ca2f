/**
 * @file strapdown.hpp
 * @brief Strapdown mechanization: one IMU increment moves the nominal state, and its error Jacobian.
 *
 * Integration (per increment of dt seconds, body increments dtheta, dv):
 *   dth = dtheta - b_g dt,  dvc = dv - b_a dt
 *   u   = dvc + 1/2 dth x dvc        (rotation compensation; no coning or
 *                                     sculling: one increment per interval)
 *   v+  = v + R u + g(p_z) dt,  p+ = p + (v + v+)/2 dt,  q+ = q (x) Exp(dth)
 * with R = R(q_MB) at the start of the interval and g = (0, 0, -g(h)).
 * Error dynamics, first order, with local attitude error (R_true = R Exp(dth)):
 *   F_vth = -R [u]x,  F_vba = -R dt,  F_vp(z,z) = dg/dh dt,
 *   F_pv = dt I, F_p* = dt/2 F_v* (trapezoid), F_thth = Exp(dth)^T, F_thbg = -dt I.
 * Neglected (first order in the increment, checked by finite differences in
 * tests/trn/filter/jacobian_test.cpp): d(rotation compensation)/d(b_g) =
 * dt/2 [dvc]x, d(rotation compensation)/d(b_a) = -dt/2 [dth]x, and the right
 * Jacobian of Exp in F_thbg = -dt J_r(dth) ~ -dt I.
 */
#pragma once

#include "bsp_tile64/api/work.hpp"
#include "trn/filter/linalg.hpp"
#include "trn/filter/nav_state.hpp"

namespace trn::filter {

/** Body-frame IMU increments over one interval. */
struct ImuIncrement {
  Vec3 dtheta_rad = Vec3::Zero();
  Vec3 dv_mps = Vec3::Zero();
  double dt_s = 0.0;
};

// Counted by hand from strapdown_step (a 3x3 by 3-vector product is 9 mul +
// 6 add; a quaternion product 16 mul + 12 add; a rotation matrix 24): the
// nominal update, the Jacobian blocks, and the rotation matrix of Exp(dth).
inline constexpr std::uint64_t kFlopsStrapdown =
    (6 + 6 + 15 + 15 + 3 + 6 + 9 + 28 + 24 + 30) + (9 * 5 + 9 + 9 + 18 + 9 + 4) + 24;
/** Divisions, square roots and transcendental calls (gravity, Exp, normalize). */
inline constexpr std::uint64_t kFdivsStrapdown = 6;

/** d g_z / d h of the map-frame gravity (0, 0, -g(h)), 1/s^2 (positive: g weakens upward). */
double gravity_gradient_per_s2(double h_m) noexcept;

/**
 * Moves @p x over one increment and writes the error-state transition @p f.
 * Pre: dt_s > 0, q_mb unit. Post: q_mb unit. Counts its flops into @p work.
 * @return the body rotation of the step, Exp(dth) (the pose history applies it to its reference).
 */
Quat strapdown_step(NominalState& x, const ImuIncrement& imu, Mat15& f, bsp::Work& work) noexcept;

}  // namespace trn::filter
