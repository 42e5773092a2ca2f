/**
 * @file pose_geometry.cpp
 * @brief Projection at a pose and the map-plane homography (see pose_geometry.hpp for the frames).
 */
#include "trn/vision/pose_geometry.hpp"

#include <cmath>
#include <cstddef>

namespace trn::vision {

namespace {

bool all_finite(const double* v, std::int32_t n) noexcept {
  for (std::int32_t i = 0; i < n; ++i) {
    if (!std::isfinite(v[i])) {
      return false;
    }
  }
  return true;
}

}  // namespace

bool camera_ok(const bsp::CameraModel& cam) noexcept {
  if (cam.width_px == 0U || cam.height_px == 0U || cam.width_px > 65536U || cam.height_px > 65536U ||
      !(std::isfinite(cam.fx_px) && cam.fx_px > 0.0) || !(std::isfinite(cam.fy_px) && cam.fy_px > 0.0) ||
      !std::isfinite(cam.cx_px) || !std::isfinite(cam.cy_px) || !all_finite(cam.r_bc, 9)) {
    return false;
  }
  // The mounting must be a rotation: R^T R = I to well below any pixel effect.
  for (std::int32_t a = 0; a < 3; ++a) {
    for (std::int32_t b = 0; b < 3; ++b) {
      const double d = cam.r_bc[a] * cam.r_bc[b] + cam.r_bc[3 + a] * cam.r_bc[3 + b] +
                       cam.r_bc[6 + a] * cam.r_bc[6 + b] - (a == b ? 1.0 : 0.0);
      if (!(std::fabs(d) < 1e-6)) {
        return false;
      }
    }
  }
  return true;
}

bool make_pose(const double p_m[3], const double q_mb[4], const bsp::CameraModel& cam, PoseGeometry& out,
               bsp::Work& work) noexcept {
  if (!all_finite(p_m, 3) || !all_finite(q_mb, 4)) {
    return false;
  }
  const double n = std::sqrt(q_mb[0] * q_mb[0] + q_mb[1] * q_mb[1] + q_mb[2] * q_mb[2] + q_mb[3] * q_mb[3]);
  if (!(n >= 0.5)) {
    return false;
  }
  const double w = q_mb[0] / n;
  const double x = q_mb[1] / n;
  const double y = q_mb[2] / n;
  const double z = q_mb[3] / n;
  // R_MB of the unit quaternion (Hamilton, w x y z): v_M = R_MB v_B.
  const double r_mb[9] = {1.0 - 2.0 * (y * y + z * z), 2.0 * (x * y - w * z),       2.0 * (x * z + w * y),
                          2.0 * (x * y + w * z),       1.0 - 2.0 * (x * x + z * z), 2.0 * (y * z - w * x),
                          2.0 * (x * z - w * y),       2.0 * (y * z + w * x),       1.0 - 2.0 * (x * x + y * y)};
  // R_MC = R_MB R_BC.
  for (std::size_t i = 0; i < 3U; ++i) {
    for (std::size_t j = 0; j < 3U; ++j) {
      out.r_mc[3U * i + j] =
          r_mb[3U * i] * cam.r_bc[j] + r_mb[3U * i + 1U] * cam.r_bc[3U + j] + r_mb[3U * i + 2U] * cam.r_bc[6U + j];
    }
    out.c_m[i] = p_m[i];
  }
  work.flops += 45U + 30U + 7U;
  work.fdivs += 5U;
  return true;
}

void to_camera(const PoseGeometry& pose, const double p[3], double p_c[3]) noexcept {
  const double d[3] = {p[0] - pose.c_m[0], p[1] - pose.c_m[1], p[2] - pose.c_m[2]};
  const double* r = pose.r_mc;
  // R_MC^T d: column k of R_MC dotted with d.
  for (std::int32_t k = 0; k < 3; ++k) {
    p_c[k] = r[k] * d[0] + r[3 + k] * d[1] + r[6 + k] * d[2];
  }
}

void to_map(const PoseGeometry& pose, const double v_c[3], double v_m[3]) noexcept {
  const double* r = pose.r_mc;
  for (std::size_t k = 0; k < 3U; ++k) {
    v_m[k] = r[3U * k] * v_c[0] + r[3U * k + 1U] * v_c[1] + r[3U * k + 2U] * v_c[2];
  }
}

bool project_point(const bsp::CameraModel& cam, const PoseGeometry& pose, const double p[3], double& u, double& v,
                   double* z_c, bsp::Work& work) noexcept {
  double pc[3];
  to_camera(pose, p, pc);
  work.flops += kFlopsProject;
  work.fdivs += 1U;
  if (z_c != nullptr) {
    *z_c = pc[2];
  }
  if (!(pc[2] > 1e-3)) {
    return false;
  }
  const double iz = 1.0 / pc[2];
  u = cam.cx_px + cam.fx_px * pc[0] * iz;
  v = cam.cy_px + cam.fy_px * pc[1] * iz;
  return true;
}

void pixel_ray(const bsp::CameraModel& cam, double u, double v, double w_c[3], bsp::Work& work) noexcept {
  const double x = (u - cam.cx_px) / cam.fx_px;
  const double y = (v - cam.cy_px) / cam.fy_px;
  const double in = 1.0 / std::sqrt(x * x + y * y + 1.0);
  w_c[0] = x * in;
  w_c[1] = y * in;
  w_c[2] = in;
  work.flops += 9U;
  work.fdivs += 4U;
}

Homography plane_homography(const bsp::CameraModel& cam, const PoseGeometry& pose, const PlaneGrid& grid,
                            bsp::Work& work) noexcept {
  const double s = grid.m_per_px;
  const double* r = pose.r_mc;
  // Columns of [a_i a_j a_0] in the camera frame: a_i = s R^T e_x (row 0 of R^T is column 0 of R).
  const double ai[3] = {s * r[0], s * r[1], s * r[2]};
  const double aj[3] = {-s * r[3], -s * r[4], -s * r[5]};
  double a0[3];
  to_camera(pose, grid.origin_m, a0);
  // H = K [a_i a_j a_0]: rows u, v, w.
  Homography h;
  const double* cols[3] = {ai, aj, a0};
  for (std::int32_t k = 0; k < 3; ++k) {
    const double* a = cols[k];
    h.h[k] = cam.fx_px * a[0] + cam.cx_px * a[2];
    h.h[3 + k] = cam.fy_px * a[1] + cam.cy_px * a[2];
    h.h[6 + k] = a[2];
  }
  work.flops += 6U + 18U + 12U;
  return h;
}

void vertical_column(const bsp::CameraModel& cam, const PoseGeometry& pose, double g[3]) noexcept {
  // R_MC^T e_z is the third row of R_MC.
  const double* r = pose.r_mc;
  g[0] = cam.fx_px * r[6] + cam.cx_px * r[8];
  g[1] = cam.fy_px * r[7] + cam.cy_px * r[8];
  g[2] = r[8];
}

bool apply_homography(const Homography& h, double x, double y, double& u, double& v) noexcept {
  const double w = h.h[6] * x + h.h[7] * y + h.h[8];
  if (!(w > 1e-9)) {
    return false;
  }
  u = (h.h[0] * x + h.h[1] * y + h.h[2]) / w;
  v = (h.h[3] * x + h.h[4] * y + h.h[5]) / w;
  return true;
}

bool apply_lifted(const Homography& h, const double g[3], double dz, double x, double y, double& u,
                  double& v) noexcept {
  const double w = h.h[6] * x + h.h[7] * y + h.h[8] + dz * g[2];
  if (!(w > 1e-9)) {
    return false;
  }
  u = (h.h[0] * x + h.h[1] * y + h.h[2] + dz * g[0]) / w;
  v = (h.h[3] * x + h.h[4] * y + h.h[5] + dz * g[1]) / w;
  return true;
}

double homography_scale(const Homography& h, double x, double y, bsp::Work& work) noexcept {
  double u = 0.0;
  double v = 0.0;
  work.flops += 40U;
  work.fdivs += 4U;
  if (!apply_homography(h, x, y, u, v)) {
    return 0.0;
  }
  const double iw = 1.0 / (h.h[6] * x + h.h[7] * y + h.h[8]);
  // d(u)/dx = (h0 - u h6) / w, and so on.
  const double a = (h.h[0] - u * h.h[6]) * iw;
  const double b = (h.h[1] - u * h.h[7]) * iw;
  const double c = (h.h[3] - v * h.h[6]) * iw;
  const double d = (h.h[4] - v * h.h[7]) * iw;
  // Largest singular value of [a b; c d]: s^2 = (T + sqrt(T^2 - 4 D^2)) / 2.
  const double t = a * a + b * b + c * c + d * d;
  const double det = a * d - b * c;
  const double disc = t * t - 4.0 * det * det;
  return std::sqrt(0.5 * (t + std::sqrt(disc > 0.0 ? disc : 0.0)));
}

}  // namespace trn::vision
