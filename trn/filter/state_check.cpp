/**
 * @file state_check.cpp
 * @brief Plausibility of the filter's state after a job (see state_check.hpp).
 */
#include "trn/filter/state_check.hpp"

#include <cmath>

namespace trn::filter {
namespace {

/** finite_state() (the filter's own test) and no variance negative. */
bool state_finite(const FilterState& s) noexcept {
  if (!finite_state(s)) {
    return false;
  }
  for (int i = 0; i < kErrDim; ++i) {
    if (s.p(i, i) < 0.0) {
      return false;
    }
  }
  return true;
}

/** Root of the trace of P's 3x3 block at @p at. */
double block_sigma(const Mat15& p, int at) noexcept {
  return std::sqrt(p(at, at) + p(at + 1, at + 1) + p(at + 2, at + 2));
}

StateCheckResult fail(StateCheck what, double value, double limit) noexcept { return {what, value, limit}; }

/** Checks 1-3: the state alone. */
StateCheckResult check_alone(const FilterState& s, const StateEnvelope& env) noexcept {
  if (!state_finite(s)) {
    return fail(StateCheck::kNotFinite, 0.0, 0.0);
  }
  const double qn = std::fabs(std::sqrt(s.x.q_mb.coeffs().squaredNorm()) - 1.0);
  if (qn > env.quat_norm_tol) {
    return fail(StateCheck::kAttitudeNorm, qn, env.quat_norm_tol);
  }
  const double speed = s.x.v_mps.norm();
  if (speed > env.max_speed_mps) {
    return fail(StateCheck::kSpeed, speed, env.max_speed_mps);
  }
  const double range = s.x.p_m.norm();
  if (range > env.max_range_m) {
    return fail(StateCheck::kRange, range, env.max_range_m);
  }
  const double bg = s.x.bg_rads.cwiseAbs().maxCoeff();
  if (bg > env.max_gyro_bias_rads) {
    return fail(StateCheck::kBias, bg, env.max_gyro_bias_rads);
  }
  const double ba = s.x.ba_mps2.cwiseAbs().maxCoeff();
  if (ba > env.max_accel_bias_mps2) {
    return fail(StateCheck::kBias, ba, env.max_accel_bias_mps2);
  }
  return {};
}

/** Check 4: the step from @p b to @p s over @p dt. */
StateCheckResult check_step(const StateBefore& b, const FilterState& s, double dt, const StateEnvelope& env) noexcept {
  const double k = env.step_sigmas;
  const double dp = (s.x.p_m - (b.x.p_m + b.x.v_mps * dt)).norm();
  const double lim_p = 0.5 * env.max_accel_mps2 * dt * dt + k * b.sigma_p_m + env.step_floor_p_m;
  if (dp > lim_p) {
    return fail(StateCheck::kStepPosition, dp, lim_p);
  }
  const double dv = (s.x.v_mps - b.x.v_mps).norm();
  const double lim_v = env.max_accel_mps2 * dt + k * b.sigma_v_mps + env.step_floor_v_mps;
  if (dv > lim_v) {
    return fail(StateCheck::kStepVelocity, dv, lim_v);
  }
  const Quat dq = b.x.q_mb.conjugate() * s.x.q_mb;
  const double dth = 2.0 * std::atan2(dq.vec().norm(), std::fabs(dq.w()));
  const double lim_th = env.max_rate_rads * dt + k * b.sigma_th_rad + env.step_floor_th_rad;
  if (dth > lim_th) {
    return fail(StateCheck::kStepAttitude, dth, lim_th);
  }
  const double dbg = (s.x.bg_rads - b.x.bg_rads).norm();
  const double lim_bg = k * b.sigma_bg_rads + env.step_floor_bg_rads;
  if (dbg > lim_bg) {
    return fail(StateCheck::kStepBias, dbg, lim_bg);
  }
  const double dba = (s.x.ba_mps2 - b.x.ba_mps2).norm();
  const double lim_ba = k * b.sigma_ba_mps2 + env.step_floor_ba_mps2;
  if (dba > lim_ba) {
    return fail(StateCheck::kStepBias, dba, lim_ba);
  }
  return {};
}

}  // namespace

StateBefore state_before(const FilterState& s, bsp::Work& work) noexcept {
  StateBefore b{};
  work.flops += 30U;
  work.fdivs += 5U;  // the square roots
  work.mem_words += 50U;
  if (s.initialized == 0U || !state_finite(s)) {
    return b;
  }
  b.valid = true;
  b.t_s = s.t_s;
  b.x = s.x;
  b.sigma_p_m = block_sigma(s.p, kIdxP);
  b.sigma_v_mps = block_sigma(s.p, kIdxV);
  b.sigma_th_rad = block_sigma(s.p, kIdxTh);
  b.sigma_bg_rads = block_sigma(s.p, kIdxBg);
  b.sigma_ba_mps2 = block_sigma(s.p, kIdxBa);
  b.coarse_accepted = s.c.coarse_accepted;
  return b;
}

StateCheckResult check_state(const StateBefore& before, const FilterState& after, const StateEnvelope& env,
                             bsp::Work& work) noexcept {
  // Finite and envelope: ~60 operations; the step: ~90 and an arctangent.
  work.flops += 150U;
  work.fdivs += 10U;  // square roots, the arctangent's division
  work.mem_words += 80U;
  if (after.initialized == 0U) {
    return {};
  }
  const StateCheckResult alone = check_alone(after, env);
  if (alone.what != StateCheck::kOk) {
    return alone;
  }
  const double dt = after.t_s - before.t_s;
  if (!before.valid || after.c.coarse_accepted != before.coarse_accepted || dt < 0.0 || dt > env.max_step_s) {
    return {};
  }
  return check_step(before, after, dt, env);
}

std::uint32_t state_check_field(double v, StateCheck c) noexcept {
  const double m = v * (c == StateCheck::kAttitudeNorm ? 1e6 : 1e3) + 0.5;
  return m >= 4294967295.0 ? 0xFFFF'FFFFU : m > 0.0 ? static_cast<std::uint32_t>(m) : 0U;
}

const char* state_check_name(StateCheck c) noexcept {
  switch (c) {
    case StateCheck::kOk:
      return "ok";
    case StateCheck::kNotFinite:
      return "not finite";
    case StateCheck::kAttitudeNorm:
      return "attitude norm";
    case StateCheck::kSpeed:
      return "speed";
    case StateCheck::kRange:
      return "range";
    case StateCheck::kBias:
      return "IMU bias";
    case StateCheck::kStepPosition:
      return "position step";
    case StateCheck::kStepVelocity:
      return "velocity step";
    case StateCheck::kStepAttitude:
      return "attitude step";
    case StateCheck::kStepBias:
      return "bias step";
  }
  return "?";
}

}  // namespace trn::filter
