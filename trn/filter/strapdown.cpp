/**
 * @file strapdown.cpp
 * @brief Strapdown mechanization and its error-state transition matrix.
 */
#include "trn/filter/strapdown.hpp"

#include "bsp_tile64/api/frames.hpp"

namespace trn::filter {

double gravity_gradient_per_s2(double h_m) noexcept {
  const double r = bsp::frames::kRadiusMars + h_m;
  return 2.0 * bsp::frames::kGmMars / (r * r * r);
}

Quat strapdown_step(NominalState& x, const ImuIncrement& imu, Mat15& f, bsp::Work& work) noexcept {
  const double dt = imu.dt_s;
  const Vec3 dth = imu.dtheta_rad - x.bg_rads * dt;
  const Vec3 dvc = imu.dv_mps - x.ba_mps2 * dt;
  const Vec3 u = dvc + 0.5 * dth.cross(dvc);
  const Mat3 r = x.q_mb.toRotationMatrix();
  Quat dq = quat_exp(dth);  // also what the step returns
  const double h_m = x.p_m.z();
  const double dgdh = gravity_gradient_per_s2(h_m);

  // Error transition first: it linearizes about the state at the start of the interval.
  f.setIdentity();
  const Mat3 f_vth = -(r * skew(u));
  const Mat3 f_vba = -dt * r;
  f.block<3, 3>(kIdxP, kIdxV) = dt * Mat3::Identity();
  f.block<3, 3>(kIdxV, kIdxTh) = f_vth;
  f.block<3, 3>(kIdxV, kIdxBa) = f_vba;
  f(kIdxV + 2, kIdxP + 2) = dgdh * dt;
  f.block<3, 3>(kIdxP, kIdxTh) = (0.5 * dt) * f_vth;
  f.block<3, 3>(kIdxP, kIdxBa) = (0.5 * dt) * f_vba;
  f(kIdxP + 2, kIdxP + 2) = 1.0 + 0.5 * dt * dgdh * dt;
  f.block<3, 3>(kIdxTh, kIdxTh) = dq.toRotationMatrix().transpose();
  f.block<3, 3>(kIdxTh, kIdxBg) = -dt * Mat3::Identity();

  const Vec3 g(0.0, 0.0, -bsp::frames::gravity_mps2(h_m));
  const Vec3 v_new = x.v_mps + r * u + g * dt;
  x.p_m += (0.5 * dt) * (x.v_mps + v_new);
  x.v_mps = v_new;
  x.q_mb = (x.q_mb * dq).normalized();

  work.flops += kFlopsStrapdown;
  work.fdivs += kFdivsStrapdown;
  work.mem_words += 2ULL * kErrDim * kErrDim;  // F written as doubles
  return dq;
}

}  // namespace trn::filter
