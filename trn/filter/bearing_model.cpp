/**
 * @file bearing_model.cpp
 * @brief Landmark bearing prediction, residual and Jacobian.
 */
#include "trn/filter/bearing_model.hpp"

#include <cmath>

namespace trn::filter {

CameraGeometry camera_geometry(const bsp::CameraModel& cam) noexcept {
  CameraGeometry g;
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) {
      g.r_bc(i, j) = cam.r_bc[3 * i + j];
    }
  }
  g.fx_px = cam.fx_px;
  g.fy_px = cam.fy_px;
  return g;
}

BearingStatus bearing_measurement(const NominalState& x, const CameraGeometry& cam, const Match& mt,
                                  double min_depth, double sigma_floor_px, Meas2& out,
                                  bsp::Work& work) noexcept {
  work.flops += kFlopsBearing;
  work.fdivs += 4;
  const Vec3 w(mt.w_c[0], mt.w_c[1], mt.w_c[2]);
  if (!w.allFinite() || !(w.z() >= min_depth * w.norm())) {
    return BearingStatus::kBadBearing;
  }
  if (!std::isfinite(mt.sigma_px) || !(mt.sigma_px > 0.0)) {
    return BearingStatus::kBadSigma;
  }
  const Mat3 r_mb = x.q_mb.toRotationMatrix();
  const Mat3 r_cb = cam.r_bc.transpose();
  const Vec3 p_b = r_mb.transpose() * (Vec3(mt.p_m[0], mt.p_m[1], mt.p_m[2]) - x.p_m);
  const Vec3 p_c = r_cb * p_b;
  if (!p_c.allFinite() || !(p_c.z() >= min_depth * p_c.norm())) {
    return BearingStatus::kBehindCamera;
  }
  const double iz = 1.0 / p_c.z();
  Mat23 j_pi;
  j_pi << iz, 0.0, -p_c.x() * iz * iz, 0.0, iz, -p_c.y() * iz * iz;
  const Mat23 a = j_pi * r_cb;
  out.hp.noalias() = -a * r_mb.transpose();
  out.hth.noalias() = a * skew(p_b);
  out.r = Vec2(w.x() / w.z() - p_c.x() * iz, w.y() / w.z() - p_c.y() * iz);
  const double s = mt.sigma_px > sigma_floor_px ? mt.sigma_px : sigma_floor_px;
  out.r_var = Vec2((s / cam.fx_px) * (s / cam.fx_px), (s / cam.fy_px) * (s / cam.fy_px));
  return BearingStatus::kOk;
}

}  // namespace trn::filter
