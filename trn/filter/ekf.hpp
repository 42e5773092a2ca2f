/**
 * @file ekf.hpp
 * @brief The navigation filter: an error-state EKF stepped by IMU samples and landmark matches.
 *
 * Usage by the 100 Hz filter task (one object in static storage per replica):
 *   configure() once; init() from the initial estimate; then every period
 *   step({&imu, matches, n}) or propagate() and update() separately; publish
 *   output(); charge take_work() with the cost model.
 * A match is measured at its image time Match::t_s, which may lie up to the
 * pose history's span (kHistoryLen propagations, 2.56 s) behind the state: its
 * residual is formed from the pose at that time and its Jacobian mapped onto
 * the current error state (pose_history.hpp, docs/FILTER.md). So a frame's
 * batch can arrive late and be spread over several periods. A match older
 * than the history or ahead of the state is refused and counted, never applied.
 * Repeatable: the result depends only on the state and the inputs.
 */
#pragma once

#include "bsp_tile64/api/camera_model.hpp"
#include "bsp_tile64/api/imu_sample.hpp"
#include "bsp_tile64/api/work.hpp"
#include "trn/filter/bearing_model.hpp"
#include "trn/filter/covariance.hpp"
#include "trn/filter/filter_config.hpp"
#include "trn/filter/filter_state.hpp"
#include "trn/filter/pose_history.hpp"
#include "trn/filter/strapdown.hpp"
#include "trn/match.hpp"

#include <cstdint>

namespace trn::filter {

enum class FilterStatus : std::uint8_t {
  kOk,
  kBadConfig,       ///< configure() refused the configuration
  kNotInitialized,  ///< propagate/update before init()
  kBadInput,        ///< null pointer, too many matches, non-finite estimate or increments
  kImuInvalid,      ///< the sample carries a device error; not integrated
  kNumericalFault,  ///< state or covariance not finite after the step
};

/** What one update call did. */
struct UpdateReport {
  std::uint32_t accepted = 0;
  std::uint32_t rejected_gate = 0;
  std::uint32_t rejected_invalid = 0;  ///< not finite, geometrically invalid, or an update that would leave a variance <= 0
  std::uint32_t rejected_stale = 0;   ///< image time before the history or after the state
  std::uint32_t coarse_accepted = 0;  ///< of accepted: coarse-stage matches (landmark kCoarseLandmark)
  std::uint32_t rejected_check = 0;   ///< an update product still wrong after its recomputations (abft_failed)
  /// Over the matches that reached the gate (accepted and rejected_gate): the sum of their
  /// normalised innovations squared, each clipped at the gate (min(d2, gate_chi2)). For a filter
  /// whose covariance is right, d2 is chi-square with 2 degrees of freedom (the innovation monitor).
  double nis_sum = 0.0;
};

/** Whether a match can be formed against the state, and why not. */
enum class MatchCheck : std::uint8_t {
  kOk,
  kStale,    ///< image time outside the pose history, ahead of the state, or across an IMU gap
  kInvalid,  ///< not finite, behind the camera, or a bad sigma
};

/** One period's inputs. matches may be null when match_count is 0. */
struct StepInput {
  const bsp::ImuSample* imu = nullptr;
  const Match* matches = nullptr;
  std::uint32_t match_count = 0;
};

class Ekf {
 public:
  /** Sets configuration and camera; resets the state. Errors: kBadConfig. */
  FilterStatus configure(const FilterConfig& cfg, const bsp::CameraModel& cam) noexcept;

  /**
   * Sets configuration and camera again and keeps the state: the settings
   * rebuilt from their source after an upset changed them in RAM (the task's
   * settings check). Errors: kBadConfig (the settings are left as they were).
   */
  FilterStatus reload_settings(const FilterConfig& cfg, const bsp::CameraModel& cam) noexcept;

  /** Starts from @p est (covariance diagonal from its sigmas). Errors: kBadInput. */
  FilterStatus init(const InitialEstimate& est) noexcept;

  /**
   * Integrates one IMU sample (increments over cfg.imu_dt_s). A sample with a
   * non-zero status is counted and skipped (kImuInvalid); a seq jump is counted
   * as a gap and bridged: the missing samples (up to kMaxBridgedSamples) are
   * integrated with this sample's increments first (a zero-order hold), so the
   * state keeps time with the samples instead of falling one interval behind
   * per sample lost (about 1 m of position at the descent's speed).
   */
  FilterStatus propagate(const bsp::ImuSample& imu) noexcept;

  /**
   * Applies up to kMaxMatchesPerFrame matches one by one, each at its image
   * time (measure, gate, Kalman update). The batch's corrections are
   * accumulated on the error state and injected into the nominal once, with
   * one attitude reset, at the end of the batch (a later match's innovation is
   * r - H dx_acc: every match of the batch is linearized at the same nominal,
   * so the poses of its image times are computed once). A coarse-stage match,
   * and any match while the position is loose (position_loose()), is applied as
   * an iterated update (at most kCoarseIterations linearizations, see
   * iterated_update()); the batch's accumulated correction is injected before
   * it. Errors: kNotInitialized, kBadInput (null with n > 0, n too big).
   */
  FilterStatus update(const Match* matches, std::uint32_t n, UpdateReport& rep) noexcept;

  /**
   * Forms residual, noise and Jacobian (on the current error state) of @p m
   * at the nominal state without applying it: what update() weighs (before
   * the batch's earlier corrections are taken off the residual). @p out is
   * written for kOk only. Pre: initialized.
   */
  MatchCheck measure(const Match& m, Meas2& out) noexcept;

  /** propagate() then, if the propagation succeeded, update(). */
  FilterStatus step(const StepInput& in, UpdateReport& rep) noexcept;

  /** Replaces the whole state, history included (TMR transfer). Errors: kBadInput if not finite or malformed. */
  FilterStatus restore(const FilterState& s) noexcept;

  /**
   * Replaces the nominal state only, unchecked: how a corrupted result (an
   * injected sdc on the filter's state) comes back into the filter, which
   * then meets it as it would meet any wrong value.
   */
  void set_nominal(const NominalState& x) noexcept { s_.x = x; }

  /**
   * Some position sigma is above kLooseSigmaM: one bearing's single
   * linearization is then not the bearing's. Right after the coarse fix the
   * altitude is still known to ~100 m and the attitude to ~0.5 deg, and one
   * fine bearing, weighed once, moved trn_mission's seed 22 by 210 m in z and
   * its attitude by tenths of a degree; the frame's other bearings then failed
   * the gate against the state it left (60 m off, 0.75 deg, against a 3-sigma
   * of 19 m). Iterated, the frame's matches leave it 8 m off (3-sigma 7 m).
   */
  [[nodiscard]] bool position_loose() const noexcept;

  /**
   * Adds @p var to the covariance's diagonal (a variance per error state, each >= 0 and finite;
   * others are taken as 0): what the filter does when its measurements keep disagreeing with its
   * covariance (the innovation monitor), so that they are weighed again and bring the state back.
   * The queue's batch in progress is not touched (called between jobs).
   */
  void widen(const Vec15& var) noexcept;

  [[nodiscard]] const FilterState& state() const noexcept { return s_; }
  /**
   * CRC-32C of the state's bytes in RAM (nominal state, covariance, counters, pose history): taken
   * at the end of a job and checked at the start of the next, it finds what changed the state
   * between them, where nothing of the filter's runs (an upset). Charges @p work.
   */
  [[nodiscard]] std::uint32_t state_crc(bsp::Work& work) const noexcept;
  [[nodiscard]] const FilterConfig& config() const noexcept { return cfg_; }
  /** The camera as the filter uses it (configure()). */
  [[nodiscard]] const CameraGeometry& camera() const noexcept { return cam_; }
  /** The process noise per error state and IMU interval, derived from the configuration. */
  [[nodiscard]] const Vec15& process_noise() const noexcept { return q_diag_; }
  /** Work counted since the last take_work(); the task charges it. */
  bsp::Work take_work() noexcept;

 private:
  void apply_correction(const Vec15& dx) noexcept;
  /** One strapdown and covariance step with @p inc, ending at @p t_s (propagate()'s body). */
  FilterStatus integrate(const ImuIncrement& inc, double t_s) noexcept;
  /** Injects the batch's accumulated correction dx_acc_, if any (apply_correction()), and clears it. */
  void flush_pending() noexcept;
  /**
   * The camera pose of image time @p t_s into pose_ (history, bearing pose,
   * lag and its noise), kept for the next match of the same time until the
   * nominal changes (apply_correction()). kStale if the history has no pose there.
   */
  MatchCheck image_pose(double t_s) noexcept;
  /** One match of update()'s batch: measured, weighed, accumulated (or iterated and injected); counted in @p rep. */
  void apply_match(const Match& m, UpdateReport& rep) noexcept;
  /** measure() with the pose of the previous match's image kept when its time is the same. */
  MatchCheck measure_cached(const Match& m, Meas2& out) noexcept;
  /**
   * The update of coarse match @p m (measured at the current state into meas_)
   * as an iterated EKF: the correction dx_ from the prior x0 is found, the
   * bearing measured again at x0 + dx_, and the update done again from x0 and
   * P0 with the residual taken about x0 (r + H dx_), up to kCoarseIterations
   * times or until dx_ moves less than kCoarseConvergedM. A coarse match
   * corrects kilometres, and one linearization at a prior kilometres off is
   * not the bearing's: on trn_mission's seed 11 (a 247 m altitude error) it
   * left the attitude 1.4 deg off (from 0.81) and a covariance the true fine
   * matches after it failed the gate against. Leaves s_.x at x0, s_.p and dx_
   * those of the last iteration that passed (the caller applies dx_); the
   * result is the first iteration's gate.
   */
  GateResult iterated_update(const Match& m) noexcept;
  bool state_finite() const noexcept;

  FilterConfig cfg_{};
  CameraGeometry cam_{};
  Vec15 q_diag_ = Vec15::Zero();
  FilterState s_{};
  Mat15 f_ = Mat15::Identity();
  CovWork w_{};
  Meas2 meas_{};
  PastPose past_{};
  BearingPose pose_{};            ///< image_pose(): the pose of image time pose_t_s_
  LagNoise pose_d_{};
  double pose_t_s_ = 0.0;
  double pose_lag_s_ = 0.0;
  bool pose_valid_ = false;       ///< pose_ is that of the current nominal
  bool pending_ = false;          ///< dx_acc_ holds corrections not yet injected
  Vec15 dx_acc_ = Vec15::Zero();  ///< update(): the batch's correction so far
  Vec15 dx_ = Vec15::Zero();
  NominalState x0_{};             ///< iterated_update(): the prior
  Mat15 p0_ = Mat15::Zero();      ///< iterated_update(): the prior covariance
  Mat15 p_iter_ = Mat15::Zero();  ///< iterated_update(): an iteration's covariance
  Vec15 dx_iter_ = Vec15::Zero(); ///< iterated_update(): an iteration's correction
  bsp::Work work_{};
};

/** Linearizations of a coarse match at most (Ekf::iterated_update()); a job's match budget counts it this many times. */
inline constexpr std::uint32_t kCoarseIterations = 4;
/** A coarse match's iterations stop when the correction's position moves less than this, m. */
inline constexpr double kCoarseConvergedM = 0.01;
/** Above this position sigma (any axis), every match is an iterated update (Ekf::position_loose()), m. */
inline constexpr double kLooseSigmaM = 5.0;

/** Missing samples a propagate() bridges at most; a longer gap leaves the rest of its time unintegrated. */
inline constexpr std::uint32_t kMaxBridgedSamples = 10U;

/** Flops of one propagate() (strapdown, covariance, history); a task budgets its period with these. */
/** The checks of the propagation's two products, when they pass (rows first, fdir/abft.hpp). */
inline constexpr std::uint64_t kFlopsCovChecks = 2U * fdir::abft_rows_first_flops(kErrDim, kErrDim, kErrDim);
inline constexpr std::uint64_t kFlopsPerPropagation =
    kFlopsStrapdown + kFlopsCovPropagate + kFlopsCovChecks + kFlopsHistoryRecord;
/** The row check of P H^T when it passes (every measurement that reaches the gate pays it). */
inline constexpr std::uint64_t kFlopsCheckPht = fdir::abft_rows_flops(kErrDim, kHtRows, 2);
/** The row checks of an accepted update's three products when they pass (P H^T, K, K (P H^T)^T). */
inline constexpr std::uint64_t kFlopsUpdateChecks =
    kFlopsCheckPht + fdir::abft_rows_flops(kErrDim, 2, 2) + fdir::abft_upper_flops(kErrDim, 2);
/**
 * Flops of one accepted match at the state's time, alone in its batch: the
 * camera pose, measurement, gate, Kalman update and its checks, the
 * correction's accumulation, injection, reset. A check whose residual passes
 * the free lower bound of its tolerance costs this; one above it
 * (cancellation in a row sum) adds its row's exact tolerance, at most
 * kFlopsUpdateTolerances.
 */
inline constexpr std::uint64_t kFlopsPerMatch =
    kFlopsBearingPose + kFlopsBearing + kFlopsUpdate + kFlopsUpdateChecks + 15 + 60 + kFlopsReset;
/**
 * Flops of each further accepted match of the same image in the batch: the
 * measurement from the kept pose, the batch's correction taken off the
 * residual, gate, update, checks, accumulation (the injection and the reset
 * are the batch's, once).
 */
inline constexpr std::uint64_t kFlopsPerFurtherMatch = kFlopsBearing + 36 + kFlopsUpdate + kFlopsUpdateChecks + 15;
/** The most a clean update's checks add to kFlopsPerMatch: every row's exact tolerance, at each site. */
inline constexpr std::uint64_t kFlopsUpdateTolerances = fdir::abft_rows_tolerance_flops(kErrDim, kHtRows, 2) +
                                                        fdir::abft_rows_tolerance_flops(kErrDim, 2, 2) +
                                                        fdir::abft_upper_tolerance_flops(kErrDim, 2);
/** Flops of one accepted match measured in the past, alone in its batch. */
inline constexpr std::uint64_t kFlopsPerLaggedMatch =
    kFlopsPerMatch + kFlopsHistoryPose + kFlopsBearingPoseLag + kFlopsLagNoise + kFlopsLagGate;
/** Flops of each further accepted match of the same past image in the batch (the usual case in flight). */
inline constexpr std::uint64_t kFlopsPerFurtherLaggedMatch = kFlopsPerFurtherMatch + kFlopsLagGate;

}  // namespace trn::filter
