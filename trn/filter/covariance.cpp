/**
 * @file covariance.cpp
 * @brief Process noise, covariance propagation, Joseph update with a sparse H, attitude reset.
 */
#include "trn/filter/covariance.hpp"

#include <cmath>

namespace trn::filter {

Vec15 process_noise_diag(const ImuSpec& imu, double dt_s) noexcept {
  const double q_vel = imu.accel_vrw_mps_sqrts * imu.accel_vrw_mps_sqrts * dt_s;
  const double q_att = imu.gyro_arw_rad_sqrts * imu.gyro_arw_rad_sqrts * dt_s;
  const double q_bg = imu.gyro_bias_run_rads * imu.gyro_bias_run_rads *
                      (1.0 - std::exp(-2.0 * dt_s / imu.gyro_bias_tau_s));
  const double q_ba = imu.accel_bias_run_mps2 * imu.accel_bias_run_mps2 *
                      (1.0 - std::exp(-2.0 * dt_s / imu.accel_bias_tau_s));
  Vec15 q;
  q << 0.0, 0.0, 0.0, q_vel, q_vel, q_vel, q_att, q_att, q_att, q_bg, q_bg, q_bg, q_ba, q_ba, q_ba;
  return q;
}

void symmetrize(Mat15& p) noexcept {
  for (int i = 0; i < kErrDim; ++i) {
    for (int j = i + 1; j < kErrDim; ++j) {
      const double m = 0.5 * (p(i, j) + p(j, i));
      p(i, j) = m;
      p(j, i) = m;
    }
  }
}

namespace {

/**
 * fp = F p for the transition's sparsity (strapdown.hpp): F is the identity
 * except its blocks (p: v th ba, zz), (v: th ba, z<-z) and (th: th bg).
 */
void left_multiply(const Mat15& f, const Mat15& p, Mat15& fp) noexcept {
  fp = p;
  fp.middleRows<3>(kIdxP).noalias() += f.block<3, 3>(kIdxP, kIdxV).lazyProduct(p.middleRows<3>(kIdxV));
  fp.middleRows<3>(kIdxP).noalias() += f.block<3, 3>(kIdxP, kIdxTh).lazyProduct(p.middleRows<3>(kIdxTh));
  fp.middleRows<3>(kIdxP).noalias() += f.block<3, 3>(kIdxP, kIdxBa).lazyProduct(p.middleRows<3>(kIdxBa));
  fp.row(kIdxP + 2) += (f(kIdxP + 2, kIdxP + 2) - 1.0) * p.row(kIdxP + 2);
  fp.middleRows<3>(kIdxV).noalias() += f.block<3, 3>(kIdxV, kIdxTh).lazyProduct(p.middleRows<3>(kIdxTh));
  fp.middleRows<3>(kIdxV).noalias() += f.block<3, 3>(kIdxV, kIdxBa).lazyProduct(p.middleRows<3>(kIdxBa));
  fp.row(kIdxV + 2) += f(kIdxV + 2, kIdxP + 2) * p.row(kIdxP + 2);
  fp.middleRows<3>(kIdxTh).noalias() = f.block<3, 3>(kIdxTh, kIdxTh).lazyProduct(p.middleRows<3>(kIdxTh));
  fp.middleRows<3>(kIdxTh).noalias() += f.block<3, 3>(kIdxTh, kIdxBg).lazyProduct(p.middleRows<3>(kIdxBg));
}

/** p = fp F^T, the same sparsity applied to columns. */
void right_multiply_transpose(const Mat15& f, const Mat15& fp, Mat15& p) noexcept {
  p = fp;
  p.middleCols<3>(kIdxP).noalias() += fp.middleCols<3>(kIdxV).lazyProduct(f.block<3, 3>(kIdxP, kIdxV).transpose());
  p.middleCols<3>(kIdxP).noalias() += fp.middleCols<3>(kIdxTh).lazyProduct(f.block<3, 3>(kIdxP, kIdxTh).transpose());
  p.middleCols<3>(kIdxP).noalias() += fp.middleCols<3>(kIdxBa).lazyProduct(f.block<3, 3>(kIdxP, kIdxBa).transpose());
  p.col(kIdxP + 2) += (f(kIdxP + 2, kIdxP + 2) - 1.0) * fp.col(kIdxP + 2);
  p.middleCols<3>(kIdxV).noalias() += fp.middleCols<3>(kIdxTh).lazyProduct(f.block<3, 3>(kIdxV, kIdxTh).transpose());
  p.middleCols<3>(kIdxV).noalias() += fp.middleCols<3>(kIdxBa).lazyProduct(f.block<3, 3>(kIdxV, kIdxBa).transpose());
  p.col(kIdxV + 2) += f(kIdxV + 2, kIdxP + 2) * fp.col(kIdxP + 2);
  p.middleCols<3>(kIdxTh).noalias() = fp.middleCols<3>(kIdxTh).lazyProduct(f.block<3, 3>(kIdxTh, kIdxTh).transpose());
  p.middleCols<3>(kIdxTh).noalias() += fp.middleCols<3>(kIdxBg).lazyProduct(f.block<3, 3>(kIdxTh, kIdxBg).transpose());
}

}  // namespace

void propagate_covariance(Mat15& p, const Mat15& f, const Vec15& q, CovWork& w, bsp::Work& work) noexcept {
  // Block-sparse products (about a quarter of the dense flops); the dense
  // F P F^T of the reference test checks that the pattern is complete.
  left_multiply(f, p, w.fp);
  right_multiply_transpose(f, w.fp, p);
  p.diagonal() += q;
  symmetrize(p);
  work.flops += kFlopsCovPropagate;
  work.mem_words += 4ULL * kErrDim * kErrDim * 2;
}

namespace {

/** X H^T for H = [Hp 0 Hth 0 0]: only six columns of X are read. */
void times_ht(const Mat15& x, const Meas2& m, Mat15x2& out) noexcept {
  out.noalias() = x.middleCols<3>(kIdxP).lazyProduct(m.hp.transpose());
  out.noalias() += x.middleCols<3>(kIdxTh).lazyProduct(m.hth.transpose());
}

}  // namespace

GateResult joseph_update(Mat15& p, const Meas2& m, double gate_chi2, Vec15& dx, CovWork& w,
                         bsp::Work& work) noexcept {
  GateResult g;
  times_ht(p, m, w.pht);
  Mat2 s = m.hp.lazyProduct(w.pht.middleRows<3>(kIdxP));
  s.noalias() += m.hth.lazyProduct(w.pht.middleRows<3>(kIdxTh));
  s(0, 0) += m.r_var(0);
  s(1, 1) += m.r_var(1);
  const double det = s(0, 0) * s(1, 1) - s(0, 1) * s(1, 0);
  work.flops += kFlopsGate;
  work.fdivs += 1;
  if (!(det > 0.0) || !std::isfinite(det)) {
    return g;  // S not positive definite: the measurement cannot be weighed
  }
  Mat2 s_inv;
  s_inv << s(1, 1) / det, -s(0, 1) / det, -s(1, 0) / det, s(0, 0) / det;
  g.d2 = m.r.dot(s_inv * m.r);
  if (!(g.d2 <= gate_chi2)) {
    return g;  // NaN residuals fail here too
  }
  g.accepted = true;
  w.k.noalias() = w.pht.lazyProduct(s_inv);
  // (I - K H) P = P - K (P H^T)^T, exact Joseph congruence applied in two sparse steps.
  w.fp.noalias() = p - w.k.lazyProduct(w.pht.transpose());
  times_ht(w.fp, m, w.mht);
  // (I-KH)P(I-KH)^T + K R K^T = M - (M H^T - K R) K^T with M = (I-KH)P: one
  // 15x2x15 product instead of two.
  w.mht -= w.k * m.r_var.asDiagonal();
  p.noalias() = w.fp - w.mht.lazyProduct(w.k.transpose());
  symmetrize(p);
  dx.noalias() = w.k * m.r;
  work.flops += kFlopsJoseph - kFlopsGate;
  work.fdivs += 4;
  work.mem_words += 8ULL * kErrDim * kErrDim * 2;
  return g;
}

void reset_attitude(Mat15& p, const Vec3& dth, bsp::Work& work) noexcept {
  const Mat3 g = Mat3::Identity() - skew(0.5 * dth);
  // Rows then columns of the attitude block: G P G^T touches nothing else.
  const Eigen::Matrix<double, 3, kErrDim> rows = g.lazyProduct(p.middleRows<3>(kIdxTh));
  p.middleRows<3>(kIdxTh) = rows;
  const Eigen::Matrix<double, kErrDim, 3> cols = p.middleCols<3>(kIdxTh).lazyProduct(g.transpose());
  p.middleCols<3>(kIdxTh) = cols;
  symmetrize(p);
  work.flops += kFlopsReset;
  work.mem_words += 4ULL * 3 * kErrDim * 2;
}

}  // namespace trn::filter
