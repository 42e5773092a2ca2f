/**
 * @file linalg.hpp
 * @brief Fixed-size Eigen types, error-state indices and small rotation helpers of the filter.
 *
 * Every translation unit is built with EIGEN_RUNTIME_NO_MALLOC (the Makefile's
 * flags), so the filter's code carries Eigen's allocation check: a test that
 * calls Eigen::internal::set_is_malloc_allowed(false) then trips on any
 * allocation made inside the filter code itself, not only in its own code.
 */
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <cmath>
#include <cstdint>

namespace trn::filter {

inline constexpr int kErrDim = 15;  ///< error states [dp, dv, dtheta, db_g, db_a]
inline constexpr int kIdxP = 0;     ///< position error, map frame, m
inline constexpr int kIdxV = 3;     ///< velocity error, map frame, m/s
inline constexpr int kIdxTh = 6;    ///< attitude error, body frame (right perturbation), rad
inline constexpr int kIdxBg = 9;    ///< gyro bias error, rad/s
inline constexpr int kIdxBa = 12;   ///< accelerometer bias error, m/s^2

using Vec2 = Eigen::Matrix<double, 2, 1>;
using Vec3 = Eigen::Matrix<double, 3, 1>;
using Mat2 = Eigen::Matrix<double, 2, 2>;
using Mat3 = Eigen::Matrix<double, 3, 3>;
using Mat23 = Eigen::Matrix<double, 2, 3>;
using Vec15 = Eigen::Matrix<double, kErrDim, 1>;
using Mat15 = Eigen::Matrix<double, kErrDim, kErrDim>;
using Mat15x2 = Eigen::Matrix<double, kErrDim, 2>;
using Mat2x15 = Eigen::Matrix<double, 2, kErrDim>;
using Quat = Eigen::Quaterniond;

/** Cross-product matrix: skew(a) * b == a x b. */
inline Mat3 skew(const Vec3& a) noexcept {
  Mat3 s;
  s << 0.0, -a.z(), a.y(), a.z(), 0.0, -a.x(), -a.y(), a.x(), 0.0;
  return s;
}

/**
 * Quaternion of the rotation vector @p th (rad): exp map, exact for any angle.
 * Below 1e-8 rad the first-order form is used (its error is below 1e-24).
 */
inline Quat quat_exp(const Vec3& th) noexcept {
  const double a = th.norm();
  if (a < 1e-8) {
    return Quat(1.0, 0.5 * th.x(), 0.5 * th.y(), 0.5 * th.z()).normalized();
  }
  const double s = std::sin(0.5 * a) / a;
  return Quat(std::cos(0.5 * a), s * th.x(), s * th.y(), s * th.z());
}

/** Rotation vector of the unit quaternion @p q (log map), angle in [0, pi]. */
inline Vec3 quat_log(const Quat& q) noexcept {
  const Quat qp = q.w() < 0.0 ? Quat(-q.w(), -q.x(), -q.y(), -q.z()) : q;
  const Vec3 v(qp.x(), qp.y(), qp.z());
  const double n = v.norm();
  if (n < 1e-12) {
    return 2.0 * v;
  }
  return (2.0 * std::atan2(n, qp.w()) / n) * v;
}

}  // namespace trn::filter
