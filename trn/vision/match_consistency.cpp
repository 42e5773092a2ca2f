/**
 * @file match_consistency.cpp
 * @brief A frame's matches against the pose they fit together (see match_consistency.hpp).
 */
#include "trn/vision/match_consistency.hpp"

#include "trn/vision/pose_geometry.hpp"

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>

namespace trn::vision {
namespace {

using Vec3 = Eigen::Vector3d;
using Mat3 = Eigen::Matrix3d;
using Mat6 = Eigen::Matrix<double, 6, 6>;
using Vec6 = Eigen::Matrix<double, 6, 1>;

/** sqrt(2 ln 2): the median norm of a 2D Gaussian residual in per-axis sigmas. */
constexpr double kMedianNormPerSigma = 1.1774100225154747;
/** Flops of one match in one Gauss-Newton step (projection, Jacobian 2x6, normal equations). */
constexpr std::uint64_t kFlopsPerMatchStep = 22U + 60U + 84U;

struct Pose {
  Vec3 c;
  Mat3 r;  ///< camera to map
};

/**
 * Solves a x = b for a symmetric positive definite 6x6 @p a by LDL^T, in
 * fixed loops on the stack's 6x6 (Eigen's pivoting solvers work on blocks of
 * run-time size, which puts a variable-size buffer on the stack). False when
 * a pivot is not positive and finite (not positive definite, or not finite).
 */
bool solve_spd6(const Mat6& a, const Vec6& b, Vec6& x) noexcept {
  Mat6 l = Mat6::Identity();
  Vec6 d = Vec6::Zero();
  for (int j = 0; j < 6; ++j) {
    double dj = a(j, j);
    for (int k = 0; k < j; ++k) {
      dj -= l(j, k) * l(j, k) * d(k);
    }
    if (!(dj > 0.0) || !std::isfinite(dj)) {
      return false;
    }
    d(j) = dj;
    for (int i = j + 1; i < 6; ++i) {
      double v = a(i, j);
      for (int k = 0; k < j; ++k) {
        v -= l(i, k) * l(j, k) * d(k);
      }
      l(i, j) = v / dj;
    }
  }
  Vec6 y;
  for (int i = 0; i < 6; ++i) {  // L y = b
    double v = b(i);
    for (int k = 0; k < i; ++k) {
      v -= l(i, k) * y(k);
    }
    y(i) = v;
  }
  for (int i = 5; i >= 0; --i) {  // D L^T x = y
    double v = y(i) / d(i);
    for (int k = i + 1; k < 6; ++k) {
      v -= l(k, i) * x(k);
    }
    x(i) = v;
  }
  return true;
}

/** Residual (observed minus predicted pixel) of @p m at @p pose; false when it is not in front of the camera. */
bool residual(const bsp::CameraModel& cam, const Pose& pose, const Match& m, Eigen::Vector2d& r, Vec3& d,
              Vec3& pc) noexcept {
  d = Vec3(m.p_m[0], m.p_m[1], m.p_m[2]) - pose.c;
  pc.noalias() = pose.r.transpose() * d;
  if (!(pc.z() > 1e-3)) {
    return false;
  }
  r.x() = m.u_px - (cam.cx_px + cam.fx_px * pc.x() / pc.z());
  r.y() = m.v_px - (cam.cy_px + cam.fy_px * pc.y() / pc.z());
  return std::isfinite(r.x()) && std::isfinite(r.y());
}

/** One Gauss-Newton step over the matches in the fit; false when the normal equations cannot be solved. */
bool gauss_newton_step(const bsp::CameraModel& cam, Pose& pose, const Match* matches, std::uint32_t n,
                       const ConsistencyWork& ws, bsp::Work& work) noexcept {
  Mat6 jtj = Mat6::Zero();
  Vec6 jtr = Vec6::Zero();
  std::uint32_t used = 0U;
  for (std::uint32_t i = 0; i < n; ++i) {
    Eigen::Vector2d r;
    Vec3 d;
    Vec3 pc;
    if (!ws.in_fit[i] || !residual(cam, pose, matches[i], r, d, pc)) {
      continue;
    }
    const double iz = 1.0 / pc.z();
    Eigen::Matrix<double, 2, 3> jpi;
    jpi << cam.fx_px * iz, 0.0, -cam.fx_px * pc.x() * iz * iz, 0.0, cam.fy_px * iz, -cam.fy_px * pc.y() * iz * iz;
    Mat3 dx;
    dx << 0.0, -d.z(), d.y(), d.z(), 0.0, -d.x(), -d.y(), d.x(), 0.0;
    Eigen::Matrix<double, 2, 6> j;
    j.leftCols<3>().noalias() = -jpi * pose.r.transpose();
    j.rightCols<3>().noalias() = jpi * (pose.r.transpose() * dx);
    jtj.noalias() += j.transpose() * j;
    jtr.noalias() += j.transpose() * r;
    ++used;
  }
  work.flops += kFlopsPerMatchStep * used;
  work.fdivs += used;
  if (used < 4U) {
    return false;
  }
  // The depth-scale direction is weak for a flat scene: a little damping keeps the step finite.
  jtj.diagonal().array() += 1e-9 * jtj.trace();
  Vec6 step;
  work.flops += 6ULL * 6ULL * 6ULL;
  if (!solve_spd6(jtj, jtr, step) || !step.allFinite()) {
    return false;
  }
  pose.c += step.head<3>();
  const Vec3 dphi = step.tail<3>();
  const double angle = dphi.norm();
  if (angle > 0.0) {
    pose.r = Eigen::AngleAxisd(angle, dphi / angle).toRotationMatrix() * pose.r;
  }
  return true;
}

/** Residuals of every match at @p pose, signed and their norms (a match behind the camera: norm infinite, 0 signed). */
void residual_norms(const bsp::CameraModel& cam, const Pose& pose, const Match* matches, std::uint32_t n,
                    ConsistencyWork& ws, bsp::Work& work) noexcept {
  for (std::uint32_t i = 0; i < n; ++i) {
    Eigen::Vector2d r;
    Vec3 d;
    Vec3 pc;
    const bool seen = residual(cam, pose, matches[i], r, d, pc);
    ws.norm[i] = seen ? r.norm() : HUGE_VAL;
    ws.du[i] = seen ? r.x() : 0.0;
    ws.dv[i] = seen ? r.y() : 0.0;
  }
  work.flops += 30ULL * n;
}

/** Robust per-axis sigma of the norms of the matches in the fit; 0 when none. */
double robust_scale(std::uint32_t n, ConsistencyWork& ws, bsp::Work& work) noexcept {
  std::uint32_t k = 0U;
  for (std::uint32_t i = 0; i < n; ++i) {
    if (ws.in_fit[i] && std::isfinite(ws.norm[i])) {
      ws.sorted[k] = ws.norm[i];
      ++k;
    }
  }
  if (k == 0U) {
    return 0.0;
  }
  const auto mid = ws.sorted.begin() + k / 2U;
  std::nth_element(ws.sorted.begin(), mid, ws.sorted.begin() + k);
  work.flops += 4ULL * k;
  return *mid / kMedianNormPerSigma;
}

/** Gauss-Newton from @p pose over the matches in the fit, then their norms and scale; false on a failed fit. */
bool fit(const bsp::CameraModel& cam, Pose& pose, const Match* matches, std::uint32_t n,
         const ConsistencyParams& params, ConsistencyWork& ws, double& scale, bsp::Work& work) noexcept {
  for (std::uint32_t it = 0; it < params.iterations; ++it) {
    if (!gauss_newton_step(cam, pose, matches, n, ws, work)) {
      return false;
    }
  }
  residual_norms(cam, pose, matches, n, ws, work);
  scale = robust_scale(n, ws, work);
  return std::isfinite(scale);
}

bool params_ok(const ConsistencyParams& p) noexcept {
  return p.iterations >= 1U && p.iterations <= 10U && p.min_matches >= 7U && p.trim_k > 0.0 && p.k_sigma > 0.0 &&
         p.floor_px >= 0.0;
}

}  // namespace

Status check_match_consistency(const bsp::CameraModel& cam, const PosePrior& prior, const Match* matches,
                               std::uint32_t n, const ConsistencyParams& params, bool* failed,
                               ConsistencyWork& ws, ConsistencyResult& out, bsp::Work& work) noexcept {
  out = ConsistencyResult{};
  if (matches == nullptr || failed == nullptr || n > kMaxConsistencyMatches || !params_ok(params)) {
    return Status::kBadInput;
  }
  for (std::uint32_t i = 0; i < n; ++i) {
    failed[i] = false;
    ws.in_fit[i] = true;
  }
  PoseGeometry g{};
  if (n < params.min_matches || !make_pose(prior.p_m, prior.q_mb, cam, g, work)) {
    return Status::kOk;
  }
  Pose pose{Vec3(g.c_m[0], g.c_m[1], g.c_m[2]), Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(g.r_mc)};
  double scale = 0.0;
  if (!fit(cam, pose, matches, n, params, ws, scale, work)) {
    return Status::kOk;
  }
  // The refit leaves out what the first fit could not explain.
  const double trim = std::max(params.trim_k * scale, params.floor_px);
  std::uint32_t kept = 0U;
  for (std::uint32_t i = 0; i < n; ++i) {
    ws.in_fit[i] = ws.norm[i] <= trim;
    kept += ws.in_fit[i] ? 1U : 0U;
  }
  if (kept < params.min_matches || !fit(cam, pose, matches, n, params, ws, scale, work)) {
    return Status::kOk;
  }
  out.checked = true;
  out.fitted = kept;
  out.scale_px = scale;
  out.threshold_px = std::max(params.k_sigma * scale, params.floor_px);
  for (std::uint32_t i = 0; i < n; ++i) {
    failed[i] = !(ws.norm[i] <= out.threshold_px);
    out.failed += failed[i] ? 1U : 0U;
  }
  return Status::kOk;
}

}  // namespace trn::vision
