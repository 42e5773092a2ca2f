/**
 * @file covariance.cpp
 * @brief Process noise, covariance propagation, gated Kalman update with a sparse H, attitude reset.
 */
#include "trn/filter/covariance.hpp"

#include <cmath>
#include <cstdint>

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
  // F P F^T of the reference test checks that the pattern is complete. Each
  // is checked against the row checksums of the dense product it computes,
  // and against its column checksums too once a row failed (rows first: the
  // wrong element is located, a clean product pays the rows only).
  w.last_fp = fdir::abft_product(
      f, p, w.fp, fdir::AbftSite{kAbftSiteFp, kFilterProductChannel, false, true},
      [](const Mat15& ff, const Mat15& pp, Mat15& out) noexcept { left_multiply(ff, pp, out); }, w.abft, work);
  w.last_fpft = fdir::abft_product(
      w.fp, f.transpose(), p, fdir::AbftSite{kAbftSiteFpft, kFilterProductChannel, false, true},
      [&f](const Mat15& fp, const auto& /*ft*/, Mat15& out) noexcept { right_multiply_transpose(f, fp, out); }, w.abft,
      work);
  p.diagonal() += q;
  symmetrize(p);
  work.flops += kFlopsCovPropagate;
  work.mem_words += 4ULL * kErrDim * kErrDim * 2;
}

LagNoise lag_noise(const ImuSpec& imu, double lag_s) noexcept {
  // A random walk of velocity spectral density VRW^2 integrates into position
  // as lag^3/3 (variance), lag^2/2 (position-velocity), lag (velocity).
  const double vrw2 = imu.accel_vrw_mps_sqrts * imu.accel_vrw_mps_sqrts;
  LagNoise d;
  d.q_vv = vrw2 * lag_s;
  d.q_pv = 0.5 * d.q_vv * lag_s;
  d.q_pp = (1.0 / 3.0) * d.q_vv * lag_s * lag_s;
  d.q_th = imu.gyro_arw_rad_sqrts * imu.gyro_arw_rad_sqrts * lag_s;
  return d;
}

namespace {

/**
 * X H^T for H = [Hp, -lag Hp, Hth, 0, 0]: only the position, velocity and
 * attitude columns of X are read, and the velocity ones only for lag != 0.
 */
void times_ht(const Mat15& x, const Meas2& m, Mat15x2& out) noexcept {
  if (m.lag_s != 0.0) {
    const Eigen::Matrix<double, kErrDim, 3> xp = x.middleCols<3>(kIdxP) - m.lag_s * x.middleCols<3>(kIdxV);
    out.noalias() = xp.lazyProduct(m.hp.transpose());
  } else {
    out.noalias() = x.middleCols<3>(kIdxP).lazyProduct(m.hp.transpose());
  }
  out.noalias() += x.middleCols<3>(kIdxTh).lazyProduct(m.hth.transpose());
}

/** S = H (P H^T) + R from the rows of P H^T that H reads. */
Mat2 innovation_cov(const Meas2& m, const Mat15x2& pht) noexcept {
  Mat2 s;
  if (m.lag_s != 0.0) {
    const Eigen::Matrix<double, 3, 2> rows = pht.middleRows<3>(kIdxP) - m.lag_s * pht.middleRows<3>(kIdxV);
    s.noalias() = m.hp.lazyProduct(rows);
  } else {
    s.noalias() = m.hp.lazyProduct(pht.middleRows<3>(kIdxP));
  }
  s.noalias() += m.hth.lazyProduct(pht.middleRows<3>(kIdxTh));
  s(0, 0) += m.r_var(0);
  s(1, 1) += m.r_var(1);
  return s;
}

/** True if P's position, velocity and attitude variances each exceed twice what D takes off. */
bool lag_noise_fits(const Mat15& p, const LagNoise& d) noexcept {
  bool ok = true;
  for (int i = 0; i < 3; ++i) {
    ok = ok && p(kIdxP + i, kIdxP + i) > 2.0 * d.q_pp && p(kIdxV + i, kIdxV + i) > 2.0 * d.q_vv &&
         p(kIdxTh + i, kIdxTh + i) > 2.0 * d.q_th;
  }
  return ok;
}

/** pht <- (P - D) H^T = pht - D H^T, with H_v = -lag H_p. */
void remove_lag_noise(Mat15x2& pht, const Meas2& m) noexcept {
  const LagNoise& d = m.d;
  pht.middleRows<3>(kIdxP) -= (d.q_pp - m.lag_s * d.q_pv) * m.hp.transpose();
  pht.middleRows<3>(kIdxV) -= (d.q_pv - m.lag_s * d.q_vv) * m.hp.transpose();
  pht.middleRows<3>(kIdxTh) -= d.q_th * m.hth.transpose();
}

/** H^T's position, velocity and attitude rows (the rest of H^T is zero): the dense B of X H^T's checks. */
void dense_ht(const Meas2& m, Eigen::Matrix<double, kHtRows, 2>& ht) noexcept {
  ht.middleRows<3>(kIdxP) = m.hp.transpose();
  if (m.lag_s != 0.0) {
    ht.middleRows<3>(kIdxV) = -m.lag_s * m.hp.transpose();
  } else {
    ht.middleRows<3>(kIdxV).setZero();
  }
  ht.middleRows<3>(kIdxTh) = m.hth.transpose();
}

/** The site @p id of the update: rows only, published unless the test mask closes it. */
fdir::AbftSite update_site(const CovWork& w, std::uint32_t id) noexcept {
  const bool open = ((w.update_sdc_sites >> (id - kAbftSitePht)) & 1U) != 0U;
  return fdir::AbftSite{id, open ? kFilterUpdateProductChannel : 0U, true};
}

/** Keeps @p r as site @p id's last result; false if the product is still wrong (not to be applied). */
bool passed(CovWork& w, std::uint32_t id, const fdir::AbftResult& r) noexcept {
  w.last_update[id - kAbftSitePht] = r;
  return r.verdict != fdir::AbftVerdict::kFailed;
}

/**
 * P <- P - U on U's upper triangle, mirrored (P stays exactly symmetric).
 * A lagged match weighs P - D, and D comes back after the update:
 * (P - D) - K ((P - D) H^T)^T + D, the same expression, so P itself never
 * has D taken off. False (P untouched) when a variance would not stay
 * positive (round-off against a far more precise measurement).
 */
bool subtract_update(Mat15& p, const Mat15& u) noexcept {
  for (int i = 0; i < kErrDim; ++i) {
    if (!(p(i, i) - u(i, i) > 0.0)) {
      return false;
    }
  }
  for (int j = 0; j < kErrDim; ++j) {
    for (int i = 0; i <= j; ++i) {
      const double v = p(i, j) - u(i, j);
      p(i, j) = v;
      p(j, i) = v;
    }
  }
  return true;
}

}  // namespace

GateResult kalman_update(Mat15& p, const Meas2& m, double gate_chi2, Vec15& dx, CovWork& w,
                         bsp::Work& work) noexcept {
  GateResult g;
  w.last_update.fill(fdir::AbftResult{});
  const bool lagged = m.lag_s != 0.0;
  const bool noise = lagged && lag_noise_fits(p, m.d);
  dense_ht(m, w.ht);
  const auto pht = [&m, &p](const auto& /*ph*/, const auto& /*ht*/, Mat15x2& out) noexcept { times_ht(p, m, out); };
  work.flops += kFlopsGate + (lagged ? kFlopsLagGate : 0U);
  work.fdivs += 1;
  if (!passed(w, kAbftSitePht,
              fdir::abft_product(p.leftCols<kHtRows>(), w.ht, w.pht, update_site(w, kAbftSitePht), pht, w.abft_ht,
                                 work))) {
    g.check_failed = true;
    return g;  // S and the gate would weigh a wrong P H^T
  }
  if (noise) {
    remove_lag_noise(w.pht, m);
  }
  const Mat2 s = innovation_cov(m, w.pht);
  const double det = s(0, 0) * s(1, 1) - s(0, 1) * s(1, 0);
  if (!(det > 0.0) || !std::isfinite(det)) {
    return g;  // S not positive definite: the measurement cannot be weighed
  }
  const double idet = 1.0 / det;
  Mat2 s_inv;
  s_inv << s(1, 1) * idet, -s(0, 1) * idet, -s(1, 0) * idet, s(0, 0) * idet;
  g.d2 = m.r.dot(s_inv * m.r);
  if (!(g.d2 <= gate_chi2)) {
    return g;  // NaN residuals fail here too
  }
  // Charged before the products: a failed check did (at least) this work.
  work.flops += kFlopsUpdate - kFlopsGate;
  work.mem_words += 4ULL * kErrDim * kErrDim;
  if (!passed(w, kAbftSiteGain,
              fdir::abft_product(w.pht, s_inv, w.k, update_site(w, kAbftSiteGain), fdir::AbftDense{}, w.abft_gain,
                                 work))) {
    g.check_failed = true;
    return g;
  }
  // K (P H^T)^T = P H^T S^-1 H P is symmetric: its upper triangle only,
  // checked row by row against K times suffix sums of P H^T's rows.
  if (!passed(w, kAbftSiteKpht,
              fdir::abft_upper_product(w.k, w.pht, w.kx, update_site(w, kAbftSiteKpht), w.abft_kt, work))) {
    g.check_failed = true;
    return g;  // a product still wrong: the measurement is dropped, P and dx untouched
  }
  if (!subtract_update(p, w.kx)) {
    g.variance_lost = true;
    return g;
  }
  g.accepted = true;
  dx.noalias() = w.k * m.r;
  return g;
}

void reset_attitude(Mat15& p, const Vec3& dth, bsp::Work& work) noexcept {
  const Mat3 g = Mat3::Identity() - skew(0.5 * dth);
  // G P G^T touches only the attitude rows and columns. With P symmetric the
  // new columns are the transposed new rows, except the attitude block itself,
  // which is G (rows) G^T; that block is symmetrized on its own.
  const Eigen::Matrix<double, 3, kErrDim> rows = g.lazyProduct(p.middleRows<3>(kIdxTh));
  const Mat3 blk = rows.middleCols<3>(kIdxTh).lazyProduct(g.transpose());
  p.middleRows<3>(kIdxTh) = rows;
  p.middleCols<3>(kIdxTh) = rows.transpose();
  for (int i = 0; i < 3; ++i) {
    p(kIdxTh + i, kIdxTh + i) = blk(i, i);
    for (int j = i + 1; j < 3; ++j) {
      const double m = 0.5 * (blk(i, j) + blk(j, i));
      p(kIdxTh + i, kIdxTh + j) = m;
      p(kIdxTh + j, kIdxTh + i) = m;
    }
  }
  work.flops += kFlopsReset;
  work.mem_words += 4ULL * 3 * kErrDim * 2;
}

}  // namespace trn::filter
