/**
 * @file ekf.cpp
 * @brief The error-state EKF: configuration, initialization, propagation, landmark updates.
 */
#include "trn/filter/ekf.hpp"

#include "trn/filter/strapdown.hpp"
#include "udn/crc32c.hpp"

#include <cmath>
#include <span>

namespace trn::filter {

FilterStatus Ekf::configure(const FilterConfig& cfg, const bsp::CameraModel& cam) noexcept {
  const FilterStatus st = reload_settings(cfg, cam);
  if (st != FilterStatus::kOk) {
    return st;
  }
  clear_state(s_);
  work_ = bsp::Work{};
  return FilterStatus::kOk;
}

FilterStatus Ekf::reload_settings(const FilterConfig& cfg, const bsp::CameraModel& cam) noexcept {
  if (check_config(cfg) != ConfigError::kOk) {
    return FilterStatus::kBadConfig;
  }
  const CameraGeometry g = camera_geometry(cam);
  const double ortho_err = (g.r_bc * g.r_bc.transpose() - Mat3::Identity()).cwiseAbs().maxCoeff();
  if (!(ortho_err < 1e-9) || !(g.fx_px > 0.0) || !(g.fy_px > 0.0)) {
    return FilterStatus::kBadConfig;
  }
  cfg_ = cfg;
  cam_ = g;
  q_diag_ = process_noise_diag(cfg.imu, cfg.imu_dt_s);
  return FilterStatus::kOk;
}

FilterStatus Ekf::init(const InitialEstimate& est) noexcept {
  const ImuSpec& imu = cfg_.imu;
  const double bg0 = std::sqrt(imu.gyro_bias_on_rads * imu.gyro_bias_on_rads +
                               imu.gyro_bias_run_rads * imu.gyro_bias_run_rads);
  const double ba0 = std::sqrt(imu.accel_bias_on_mps2 * imu.accel_bias_on_mps2 +
                               imu.accel_bias_run_mps2 * imu.accel_bias_run_mps2);
  Vec15 sig;
  sig << est.sigma_p_m, est.sigma_v_mps, est.sigma_th_rad,
      (est.sigma_bg_rads.array() > 0.0).select(est.sigma_bg_rads, Vec3::Constant(bg0)),
      (est.sigma_ba_mps2.array() > 0.0).select(est.sigma_ba_mps2, Vec3::Constant(ba0));
  const double qn = est.x.q_mb.norm();
  if (!sig.allFinite() || !(sig.minCoeff() > 0.0) || !std::isfinite(est.t_s) || !(qn > 0.5) ||
      !est.x.p_m.allFinite() || !est.x.v_mps.allFinite() || !est.x.q_mb.coeffs().allFinite() ||
      !est.x.bg_rads.allFinite() || !est.x.ba_mps2.allFinite()) {
    return FilterStatus::kBadInput;
  }
  clear_state(s_);
  s_.initialized = 1;
  s_.t_s = est.t_s;
  s_.t_last_update_s = est.t_s;
  s_.x = est.x;
  s_.x.q_mb.normalize();
  s_.p = sig.cwiseProduct(sig).asDiagonal();
  history_start(s_.hist, s_.t_s, s_.x);
  return FilterStatus::kOk;
}

bool finite_state(const FilterState& s) noexcept {
  return s.x.p_m.allFinite() && s.x.v_mps.allFinite() && s.x.q_mb.coeffs().allFinite() &&
         s.x.bg_rads.allFinite() && s.x.ba_mps2.allFinite() && s.p.allFinite() && std::isfinite(s.t_s) &&
         std::isfinite(s.t_last_update_s);
}

bool Ekf::state_finite() const noexcept { return finite_state(s_); }

FilterStatus Ekf::integrate(const ImuIncrement& inc, double t_s) noexcept {
  const Vec3 v_before = s_.x.v_mps;
  const Quat dq = strapdown_step(s_.x, inc, f_, work_);
  propagate_covariance(s_.p, f_, q_diag_, w_, work_);
  history_record(s_.hist, t_s, inc.dt_s, s_.x.v_mps - v_before, dq, s_.x, work_);
  ++s_.c.propagations;
  s_.t_s = t_s;
  if (!state_finite()) {
    ++s_.c.numeric_faults;
    return FilterStatus::kNumericalFault;
  }
  return FilterStatus::kOk;
}

FilterStatus Ekf::propagate(const bsp::ImuSample& imu) noexcept {
  if (s_.initialized == 0U) {
    return FilterStatus::kNotInitialized;
  }
  ImuIncrement inc;
  inc.dtheta_rad = Vec3(imu.dtheta_rad[0], imu.dtheta_rad[1], imu.dtheta_rad[2]);
  inc.dv_mps = Vec3(imu.dv_mps[0], imu.dv_mps[1], imu.dv_mps[2]);
  inc.dt_s = cfg_.imu_dt_s;
  if (imu.status != 0U || !inc.dtheta_rad.allFinite() || !inc.dv_mps.allFinite() || !std::isfinite(imu.t_s)) {
    ++s_.c.imu_rejected;
    s_.last_imu_ok = 0;
    return FilterStatus::kImuInvalid;
  }
  if (s_.c.propagations > 0U && imu.seq != s_.c.last_imu_seq + 1U) {
    ++s_.c.imu_gaps;
    // The samples lost moved the vehicle too: their intervals are integrated with this sample's
    // increments, the nearest measured, so the state does not fall behind the samples' time.
    const std::uint32_t missing = imu.seq > s_.c.last_imu_seq ? imu.seq - s_.c.last_imu_seq - 1U : 0U;
    const std::uint32_t bridged = missing < kMaxBridgedSamples ? missing : kMaxBridgedSamples;
    for (std::uint32_t k = 0; k < bridged; ++k) {
      const double t = imu.t_s - static_cast<double>(bridged - k) * inc.dt_s;
      if (integrate(inc, t) != FilterStatus::kOk) {
        return FilterStatus::kNumericalFault;
      }
    }
  }
  const FilterStatus st = integrate(inc, imu.t_s);
  s_.c.last_imu_seq = imu.seq;
  s_.last_imu_ok = 1;
  return st;
}

namespace {

/** @p x0 with error-state correction @p dx injected, into @p out (which may be @p x0). */
void inject(const NominalState& x0, const Vec15& dx, NominalState& out) noexcept {
  out.p_m = x0.p_m + dx.segment<3>(kIdxP);
  out.v_mps = x0.v_mps + dx.segment<3>(kIdxV);
  out.q_mb = (x0.q_mb * quat_exp(dx.segment<3>(kIdxTh))).normalized();
  out.bg_rads = x0.bg_rads + dx.segment<3>(kIdxBg);
  out.ba_mps2 = x0.ba_mps2 + dx.segment<3>(kIdxBa);
}

}  // namespace

void Ekf::apply_correction(const Vec15& dx) noexcept {
  inject(s_.x, dx, s_.x);
  reset_attitude(s_.p, dx.segment<3>(kIdxTh), work_);
  work_.flops += 60;
  work_.fdivs += 4;
  pose_valid_ = false;  // the poses of the image times move with the nominal
}

void Ekf::flush_pending() noexcept {
  if (pending_) {
    apply_correction(dx_acc_);
    dx_acc_.setZero();
    pending_ = false;
  }
}

bool Ekf::position_loose() const noexcept {
  constexpr double kLooseVar = kLooseSigmaM * kLooseSigmaM;
  return s_.p(kIdxP, kIdxP) > kLooseVar || s_.p(kIdxP + 1, kIdxP + 1) > kLooseVar ||
         s_.p(kIdxP + 2, kIdxP + 2) > kLooseVar;
}

GateResult Ekf::iterated_update(const Match& m) noexcept {
  x0_ = s_.x;
  p0_ = s_.p;
  const GateResult first = kalman_update(s_.p, meas_, cfg_.gate_chi2, dx_, w_, work_);
  if (!first.accepted || first.check_failed || first.variance_lost) {
    return first;
  }
  for (std::uint32_t it = 1; it < kCoarseIterations; ++it) {
    // Relinearize at x0 + dx_ (the nominal state only: P is reset once, by the caller).
    inject(x0_, dx_, s_.x);
    work_.flops += 60;
    work_.fdivs += 4;
    const MatchCheck mc = measure(m, meas_);
    if (mc != MatchCheck::kOk) {
      break;  // the last iteration that passed stands
    }
    // The residual about x0: r(x) + H (x - x0), with x - x0 = dx_ in error-state terms.
    meas_.r.noalias() += meas_.hp * (dx_.segment<3>(kIdxP) - meas_.lag_s * dx_.segment<3>(kIdxV));
    meas_.r.noalias() += meas_.hth * dx_.segment<3>(kIdxTh);
    work_.flops += 36;
    p_iter_ = p0_;
    const GateResult g = kalman_update(p_iter_, meas_, cfg_.gate_chi2, dx_iter_, w_, work_);
    if (!g.accepted || g.check_failed || g.variance_lost) {
      break;
    }
    const double moved = (dx_iter_.segment<3>(kIdxP) - dx_.segment<3>(kIdxP)).norm();
    s_.p = p_iter_;
    dx_ = dx_iter_;
    work_.flops += 12;
    work_.fdivs += 1;
    if (!(moved >= kCoarseConvergedM)) {
      break;
    }
  }
  s_.x = x0_;
  pose_valid_ = false;  // the iterations measured at x0 + dx_, not at the nominal left here
  return first;
}

MatchCheck Ekf::measure(const Match& m, Meas2& out) noexcept {
  pose_valid_ = false;
  return measure_cached(m, out);
}

MatchCheck Ekf::image_pose(double t_s) noexcept {
  if (pose_valid_ && t_s == pose_t_s_) {
    return MatchCheck::kOk;  // the same image, the same nominal: the same pose
  }
  pose_valid_ = false;
  const HistoryStatus hs = history_pose(s_.hist, t_s, s_.x, cfg_.max_history_gap_s, past_, work_);
  if (hs == HistoryStatus::kCurrent) {
    bearing_pose(s_.x.p_m, s_.x.q_mb, nullptr, cam_, pose_, work_);
    pose_lag_s_ = 0.0;
    pose_d_ = LagNoise{};
  } else if (hs == HistoryStatus::kOk) {
    // dp(t) = dp - lag dv; dtheta(t) = R(q_rel) dtheta (pose_history.hpp): the
    // velocity columns are -lag Hp (kept as lag_s), the attitude ones rotate (pose_.r_cth).
    bearing_pose(past_.p_m, past_.q_mb, &past_.q_rel, cam_, pose_, work_);
    pose_lag_s_ = past_.lag_s;
    pose_d_ = lag_noise(cfg_.imu, past_.lag_s);
    work_.flops += kFlopsLagNoise;
  } else {
    return MatchCheck::kStale;
  }
  pose_t_s_ = t_s;
  pose_valid_ = true;
  return MatchCheck::kOk;
}

MatchCheck Ekf::measure_cached(const Match& m, Meas2& out) noexcept {
  if (!std::isfinite(m.t_s)) {
    return MatchCheck::kInvalid;
  }
  const MatchCheck pc = image_pose(m.t_s);
  if (pc != MatchCheck::kOk) {
    return pc;
  }
  if (bearing_measurement(pose_, cam_, m, cfg_.min_depth, cfg_.pixel_sigma_floor_px, out, work_) !=
      BearingStatus::kOk) {
    return MatchCheck::kInvalid;
  }
  out.lag_s = pose_lag_s_;
  out.d = pose_d_;
  return MatchCheck::kOk;
}

void Ekf::apply_match(const Match& m, UpdateReport& rep) noexcept {
  const bool iterate = m.landmark == kCoarseLandmark || position_loose();
  if (iterate) {
    flush_pending();  // an iterated update linearizes at the corrected nominal
  }
  const MatchCheck mc = iterate ? measure(m, meas_) : measure_cached(m, meas_);
  if (mc != MatchCheck::kOk) {
    ++(mc == MatchCheck::kStale ? rep.rejected_stale : rep.rejected_invalid);
    return;
  }
  if (!iterate && pending_) {
    // The batch's corrections so far are not injected yet: the innovation is r - H dx_acc.
    meas_.r.noalias() -= meas_.hp * (dx_acc_.segment<3>(kIdxP) - meas_.lag_s * dx_acc_.segment<3>(kIdxV));
    meas_.r.noalias() -= meas_.hth * dx_acc_.segment<3>(kIdxTh);
    work_.flops += 36;
  }
  const GateResult g = iterate ? iterated_update(m) : kalman_update(s_.p, meas_, cfg_.gate_chi2, dx_, w_, work_);
  if (g.check_failed) {
    ++rep.rejected_check;  // reported abft_failed by the check; the match is dropped, the state untouched
    return;
  }
  if (g.variance_lost) {
    ++rep.rejected_invalid;  // it would leave a variance <= 0: it cannot be applied
    return;
  }
  rep.nis_sum += g.d2 < cfg_.gate_chi2 ? g.d2 : cfg_.gate_chi2;  // a non-finite d2 counts as the gate
  work_.flops += 2;
  if (!g.accepted) {
    ++rep.rejected_gate;
    return;
  }
  if (iterate) {
    apply_correction(dx_);
  } else {
    dx_acc_ += dx_;
    pending_ = true;
    work_.flops += 15;
  }
  ++rep.accepted;
  rep.coarse_accepted += m.landmark == kCoarseLandmark ? 1U : 0U;
  if (m.t_s > s_.t_last_update_s) {
    s_.t_last_update_s = m.t_s;
  }
}

std::uint32_t Ekf::state_crc(bsp::Work& work) const noexcept {
  const std::uint64_t words = (sizeof(FilterState) + 3U) / 4U;
  work.int_ops += 8U * words;
  work.mem_words += words;
  return udn::crc32c_bytes(
      std::span<const std::uint8_t>(reinterpret_cast<const std::uint8_t*>(&s_), sizeof(FilterState)));  // NOLINT(cppcoreguidelines-pro-type-reinterpret-cast): the state's bytes as stored
}

void Ekf::widen(const Vec15& var) noexcept {
  for (int i = 0; i < kErrDim; ++i) {
    const double v = var(i);
    s_.p(i, i) += std::isfinite(v) && v > 0.0 ? v : 0.0;
  }
  work_.flops += kErrDim;
}

FilterStatus Ekf::update(const Match* matches, std::uint32_t n, UpdateReport& rep) noexcept {
  rep = UpdateReport{};
  if (s_.initialized == 0U) {
    return FilterStatus::kNotInitialized;
  }
  if ((matches == nullptr && n > 0U) || n > kMaxMatchesPerFrame) {
    return FilterStatus::kBadInput;
  }
  pose_valid_ = false;
  dx_acc_.setZero();
  pending_ = false;
  for (std::uint32_t i = 0; i < n; ++i) {
    apply_match(matches[i], rep);
  }
  flush_pending();  // one injection and one attitude reset for the batch
  if (n > 0U) {
    ++s_.c.batches;
    s_.c.accepted += rep.accepted;
    s_.c.rejected_gate += rep.rejected_gate;
    s_.c.rejected_invalid += rep.rejected_invalid;
    s_.c.rejected_stale += rep.rejected_stale;
    s_.c.coarse_accepted += rep.coarse_accepted;
  }
  s_.c.last_accepted = rep.accepted;
  s_.c.last_rejected = rep.rejected_gate + rep.rejected_invalid + rep.rejected_stale + rep.rejected_check;
  if (!state_finite()) {
    ++s_.c.numeric_faults;
    return FilterStatus::kNumericalFault;
  }
  return FilterStatus::kOk;
}

FilterStatus Ekf::step(const StepInput& in, UpdateReport& rep) noexcept {
  rep = UpdateReport{};
  if (in.imu == nullptr) {
    return FilterStatus::kBadInput;
  }
  const FilterStatus st = propagate(*in.imu);
  if (st != FilterStatus::kOk || in.match_count == 0U) {
    return st;
  }
  return update(in.matches, in.match_count, rep);
}

FilterStatus Ekf::restore(const FilterState& s) noexcept {
  // Checked before the copy, so a refused state leaves the filter as it was.
  if (!finite_state(s) || !(s.x.q_mb.norm() > 0.5) || !history_valid(s.hist, s.t_s, s.initialized != 0U)) {
    return FilterStatus::kBadInput;
  }
  s_ = s;
  return FilterStatus::kOk;
}

bsp::Work Ekf::take_work() noexcept {
  const bsp::Work w = work_;
  work_ = bsp::Work{};
  return w;
}

}  // namespace trn::filter
