/**
 * @file covariance.cpp
 * @brief Process noise, covariance propagation, Joseph update with a sparse H, attitude reset.
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
  // is checked against the full checksums of the dense product it computes.
  w.last_fp = fdir::abft_product(
      f, p, w.fp, fdir::AbftSite{kAbftSiteFp, kFilterProductChannel},
      [](const Mat15& ff, const Mat15& pp, Mat15& out) noexcept { left_multiply(ff, pp, out); }, w.abft, work);
  w.last_fpft = fdir::abft_product(
      w.fp, f.transpose(), p, fdir::AbftSite{kAbftSiteFpft, kFilterProductChannel},
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

/** P <- P + sign D (the position-velocity cross terms on both sides). */
void add_lag_noise(Mat15& p, const LagNoise& d, double sign) noexcept {
  for (int i = 0; i < 3; ++i) {
    p(kIdxP + i, kIdxP + i) += sign * d.q_pp;
    p(kIdxP + i, kIdxV + i) += sign * d.q_pv;
    p(kIdxV + i, kIdxP + i) += sign * d.q_pv;
    p(kIdxV + i, kIdxV + i) += sign * d.q_vv;
    p(kIdxTh + i, kIdxTh + i) += sign * d.q_th;
  }
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
 * The checked products of an accepted update after P H^T: K, K (P H^T)^T,
 * M = (P - D) - K (P H^T)^T (into w.fp), M H^T, the Joseph term, and P
 * written from them (upper triangle, mirrored). P is read only until every
 * product has passed; false (P untouched) when one is still wrong.
 */
bool checked_joseph(Mat15& p, const Meas2& m, const Mat2& s_inv, bool noise, CovWork& w, bsp::Work& work) noexcept {
  if (!passed(w, kAbftSiteGain,
              fdir::abft_product(w.pht, s_inv, w.k, update_site(w, kAbftSiteGain), fdir::AbftDense{}, w.abft_gain,
                                 work))) {
    return false;
  }
  if (!passed(w, kAbftSiteKpht,
              fdir::abft_product(w.k, w.pht.transpose(), w.kx, update_site(w, kAbftSiteKpht), fdir::AbftDense{},
                                 w.abft_kt, work))) {
    return false;
  }
  // (I - K H) P = P - K (P H^T)^T, exact Joseph congruence applied in two sparse steps.
  w.fp = p;
  if (noise) {
    add_lag_noise(w.fp, m.d, -1.0);
  }
  w.fp -= w.kx;
  const auto mht = [&m, &w](const auto& /*mh*/, const auto& /*ht*/, Mat15x2& out) noexcept { times_ht(w.fp, m, out); };
  if (!passed(w, kAbftSiteMht,
              fdir::abft_product(w.fp.leftCols<kHtRows>(), w.ht, w.mht, update_site(w, kAbftSiteMht), mht, w.abft_ht,
                                 work))) {
    return false;
  }
  // (I-KH)P(I-KH)^T + K R K^T = M - (M H^T - K R) K^T with M = (I-KH)P: one
  // 15x2x15 product instead of two, whole (its row checksums need every
  // row), then its upper triangle off M, mirrored: P exactly symmetric.
  w.mht -= w.k * m.r_var.asDiagonal();
  if (!passed(w, kAbftSiteJoseph,
              fdir::abft_product(w.mht, w.k.transpose(), w.kx, update_site(w, kAbftSiteJoseph), fdir::AbftDense{},
                                 w.abft_kt, work))) {
    return false;
  }
  for (int j = 0; j < kErrDim; ++j) {
    for (int i = 0; i <= j; ++i) {
      const double v = w.fp(i, j) - w.kx(i, j);
      p(i, j) = v;
      p(j, i) = v;
    }
  }
  return true;
}

}  // namespace

GateResult joseph_update(Mat15& p, const Meas2& m, double gate_chi2, Vec15& dx, CovWork& w,
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
  Mat2 s_inv;
  s_inv << s(1, 1) / det, -s(0, 1) / det, -s(1, 0) / det, s(0, 0) / det;
  g.d2 = m.r.dot(s_inv * m.r);
  if (!(g.d2 <= gate_chi2)) {
    return g;  // NaN residuals fail here too
  }
  // Charged before the products: a failed check did (at least) this work.
  work.flops += kFlopsJoseph - kFlopsGate + (lagged ? kFlopsLagJoseph - kFlopsLagGate : 0U);
  work.fdivs += 4;
  work.mem_words += 6ULL * kErrDim * kErrDim * 2;
  if (!checked_joseph(p, m, s_inv, noise, w, work)) {
    g.check_failed = true;
    return g;  // a product still wrong: the measurement is dropped, P and dx untouched
  }
  g.accepted = true;
  if (noise) {
    add_lag_noise(p, m.d, 1.0);
  }
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
