/**
 * @file state_check.hpp
 * @brief Plausibility of the filter's state after a job: finite, inside the vehicle's envelope, and
 *        moved no further than its propagation and its uncertainty allow.
 *
 * A filter running alone (simplex) has nothing to compare its state with: a
 * corrupted update (a flipped exponent, a sign, a high mantissa bit) would be
 * carried to the end of the descent, its reported 3-sigma still small. The
 * task checks the state after every job against the state before it:
 *
 *  1. every number of the nominal state and of P's diagonal is finite, and
 *     P's diagonal is not negative;
 *  2. the attitude quaternion has unit norm (the filter normalises it);
 *  3. the envelope: speed, distance from the map's origin, the IMU biases;
 *  4. the step: the position moved by its velocity times the time step, up
 *     to jump_sigmas of the position's 1-sigma before the job (the updates'
 *     corrections are gated innovations: a few sigma at most) plus a floor;
 *     the velocity by at most the envelope's acceleration times the step plus
 *     as many sigmas; the attitude, the biases likewise. A job that applied a
 *     coarse-stage match (a correction of kilometres, by design) skips the step.
 *
 * Pure function of two states and an envelope: flight code, no allocation.
 */
#pragma once

#include "bsp_tile64/api/work.hpp"
#include "trn/filter/filter_state.hpp"

#include <cstdint>

namespace trn::filter {

/** What the check found; the numbers are the event's cause field. */
enum class StateCheck : std::uint32_t {
  kOk = 0,
  kNotFinite = 1,     ///< a state number or a variance not finite, or a variance negative
  kAttitudeNorm = 2,  ///< the quaternion's norm is not 1
  kSpeed = 3,         ///< faster than the envelope
  kRange = 4,         ///< further from the map's origin than the envelope
  kBias = 5,          ///< an IMU bias beyond the envelope
  kStepPosition = 6,  ///< the position moved further than its propagation and sigmas allow
  kStepVelocity = 7,
  kStepAttitude = 8,
  kStepBias = 9,
};

/** The envelope and the step's allowance. */
struct StateEnvelope {
  double max_speed_mps = 1500.0;         ///< a lander under its parachute or powered descent: far below
  double max_range_m = 1.0e6;            ///< from the map's origin
  double max_gyro_bias_rads = 0.05;      ///< about 10^4 deg/h: no working gyro
  double max_accel_bias_mps2 = 2.0;      ///< 0.2 g
  double quat_norm_tol = 1e-6;           ///< the filter keeps it within round-off
  double max_accel_mps2 = 100.0;         ///< specific force plus gravity, for the velocity's step
  double max_rate_rads = 3.0;            ///< body rate, for the attitude's step
  double step_sigmas = 8.0;              ///< sigmas of the state before the job a step may add
  double step_floor_p_m = 1.0;           ///< and these floors (round-off, a near-zero sigma)
  double step_floor_v_mps = 0.1;
  double step_floor_th_rad = 1e-3;
  double step_floor_bg_rads = 1e-5;
  double step_floor_ba_mps2 = 1e-3;
  double max_step_s = 1.0;               ///< a longer step (a catch-up from a checkpoint) is not judged
};

/** The verdict: which check failed first, the value it measured and its limit (the norm's: its distance from 1). */
struct StateCheckResult {
  StateCheck what = StateCheck::kOk;
  double value = 0.0;
  double limit = 0.0;
};

/** What the step check needs of the state before the job (small: kept by the task every job). */
struct StateBefore {
  bool valid = false;             ///< an initialised state was recorded
  double t_s = 0.0;
  NominalState x{};
  double sigma_p_m = 0.0;         ///< root of the trace of each 3x3 block of P
  double sigma_v_mps = 0.0;
  double sigma_th_rad = 0.0;
  double sigma_bg_rads = 0.0;
  double sigma_ba_mps2 = 0.0;
  std::uint32_t coarse_accepted = 0;
};

/** Records what the step check needs of @p s; charges @p work. */
StateBefore state_before(const FilterState& s, bsp::Work& work) noexcept;

/**
 * Checks @p after (the state after a job) alone, and against @p before when it
 * is valid and the step is judged. Charges @p work.
 */
StateCheckResult check_state(const StateBefore& before, const FilterState& after, const StateEnvelope& env,
                             bsp::Work& work) noexcept;

/** The name of a check, for logs and tests. */
const char* state_check_name(StateCheck c) noexcept;

/**
 * A check's value or limit as an event field (filter_state_bad): thousandths of the check's unit,
 * the attitude norm's distance from 1 in millionths; rounded, saturated.
 */
std::uint32_t state_check_field(double v, StateCheck c) noexcept;

}  // namespace trn::filter
