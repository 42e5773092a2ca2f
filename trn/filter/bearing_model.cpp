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
  g.inv_fx2 = 1.0 / (cam.fx_px * cam.fx_px);
  g.inv_fy2 = 1.0 / (cam.fy_px * cam.fy_px);
  return g;
}

void bearing_pose(const Vec3& p_m, const Quat& q_mb, const Quat* q_rel, const CameraGeometry& cam, BearingPose& out,
                  bsp::Work& work) noexcept {
  const Mat3 r_mb = q_mb.toRotationMatrix();
  out.p_m = p_m;
  out.r_cm.noalias() = cam.r_bc.transpose() * r_mb.transpose();
  work.flops += kFlopsBearingPose;
  if (q_rel == nullptr) {
    out.r_cth = cam.r_bc.transpose();
    return;
  }
  const Mat3 r_rel = q_rel->toRotationMatrix();
  out.r_cth.noalias() = cam.r_bc.transpose() * r_rel;
  work.flops += kFlopsBearingPoseLag;
}

namespace {

/** z >= min_depth |v| without a root: z >= 0 and z^2 >= min_depth^2 |v|^2. */
bool in_front(const Vec3& v, double min_depth2) noexcept {
  return v.z() >= 0.0 && v.z() * v.z() >= min_depth2 * v.squaredNorm();
}

}  // namespace

BearingStatus bearing_measurement(const BearingPose& pose, const CameraGeometry& cam, const Match& mt,
                                  double min_depth, double sigma_floor_px, Meas2& out,
                                  bsp::Work& work) noexcept {
  work.flops += kFlopsBearing;
  work.fdivs += kFdivsBearing;
  const double md2 = min_depth * min_depth;
  const Vec3 w(mt.w_c[0], mt.w_c[1], mt.w_c[2]);
  if (!w.allFinite() || !in_front(w, md2)) {
    return BearingStatus::kBadBearing;
  }
  if (!std::isfinite(mt.sigma_px) || !(mt.sigma_px > 0.0)) {
    return BearingStatus::kBadSigma;
  }
  const Vec3 p_c = pose.r_cm * (Vec3(mt.p_m[0], mt.p_m[1], mt.p_m[2]) - pose.p_m);
  if (!p_c.allFinite() || !in_front(p_c, md2)) {
    return BearingStatus::kBehindCamera;
  }
  // J_pi = iz [1 0 -u; 0 1 -v] with (u, v) the predicted normalized coordinates.
  const double iz = 1.0 / p_c.z();
  const double u = p_c.x() * iz;
  const double v = p_c.y() * iz;
  out.hp.row(0) = iz * (u * pose.r_cm.row(2) - pose.r_cm.row(0));
  out.hp.row(1) = iz * (v * pose.r_cm.row(2) - pose.r_cm.row(1));
  // J_pi [p_C]x, then onto the current attitude error.
  Mat23 jx;
  jx << u * p_c.y(), -p_c.z() - u * p_c.x(), p_c.y(), p_c.z() + v * p_c.y(), -v * p_c.x(), -p_c.x();
  jx *= iz;
  out.hth.noalias() = jx * pose.r_cth;
  const double iwz = 1.0 / w.z();
  out.r = Vec2(w.x() * iwz - u, w.y() * iwz - v);
  const double s = mt.sigma_px > sigma_floor_px ? mt.sigma_px : sigma_floor_px;
  const double s2 = s * s;
  out.r_var = Vec2(s2 * cam.inv_fx2, s2 * cam.inv_fy2);
  return BearingStatus::kOk;
}

BearingStatus bearing_measurement(const NominalState& x, const CameraGeometry& cam, const Match& mt,
                                  double min_depth, double sigma_floor_px, Meas2& out,
                                  bsp::Work& work) noexcept {
  BearingPose pose;
  bearing_pose(x.p_m, x.q_mb, nullptr, cam, pose, work);
  return bearing_measurement(pose, cam, mt, min_depth, sigma_floor_px, out, work);
}

}  // namespace trn::filter
