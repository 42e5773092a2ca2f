/**
 * @file ekf.hpp
 * @brief The navigation filter: an error-state EKF stepped by IMU samples and landmark matches.
 *
 * Usage by the 100 Hz filter task (one object in static storage per replica):
 *   configure() once; init() from the initial estimate; then every period
 *   step({&imu, matches, n}) or propagate() and update() separately; publish
 *   output(); charge take_work() with the cost model.
 * Matches are applied at the filter's current time: the task hands a batch
 * over in the period whose IMU time is the image time (or splits a big batch
 * over several periods to bound the work per period, see docs/FILTER.md).
 * Repeatable: the result depends only on the state and the inputs.
 */
#pragma once

#include "bsp_tile64/devices/camera_model.hpp"
#include "bsp_tile64/devices/imu_sample.hpp"
#include "bsp_tile64/work.hpp"
#include "trn/filter/bearing_model.hpp"
#include "trn/filter/covariance.hpp"
#include "trn/filter/filter_config.hpp"
#include "trn/filter/filter_state.hpp"
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
  std::uint32_t rejected_invalid = 0;
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

  /** Starts from @p est (covariance diagonal from its sigmas). Errors: kBadInput. */
  FilterStatus init(const InitialEstimate& est) noexcept;

  /**
   * Integrates one IMU sample (increments over cfg.imu_dt_s). A sample with a
   * non-zero status is counted and skipped (kImuInvalid); a seq jump is counted as a gap.
   */
  FilterStatus propagate(const bsp::ImuSample& imu) noexcept;

  /**
   * Applies up to kMaxMatchesPerFrame matches one by one (gate, Joseph update,
   * injection, reset). Errors: kNotInitialized, kBadInput (null with n > 0, n too big).
   */
  FilterStatus update(const Match* matches, std::uint32_t n, UpdateReport& rep) noexcept;

  /** propagate() then, if the propagation succeeded, update(). */
  FilterStatus step(const StepInput& in, UpdateReport& rep) noexcept;

  /** Replaces the whole state (TMR transfer). Errors: kBadInput if not finite. */
  FilterStatus restore(const FilterState& s) noexcept;

  [[nodiscard]] const FilterState& state() const noexcept { return s_; }
  [[nodiscard]] const FilterConfig& config() const noexcept { return cfg_; }
  /** Work counted since the last take_work(); the task charges it. */
  bsp::Work take_work() noexcept;

 private:
  void apply_correction(const Vec15& dx) noexcept;
  bool state_finite() const noexcept;

  FilterConfig cfg_{};
  CameraGeometry cam_{};
  Vec15 q_diag_ = Vec15::Zero();
  FilterState s_{};
  Mat15 f_ = Mat15::Identity();
  CovWork w_{};
  Meas2 meas_{};
  Vec15 dx_ = Vec15::Zero();
  bsp::Work work_{};
};

/** Flops of one propagate() (strapdown and covariance); a task budgets its period with these. */
inline constexpr std::uint64_t kFlopsPerPropagation = kFlopsStrapdown + kFlopsCovPropagate;
/** Flops of one accepted match: measurement, gate, Joseph update, injection, reset. */
inline constexpr std::uint64_t kFlopsPerMatch = kFlopsBearing + kFlopsJoseph + 60 + kFlopsReset;

}  // namespace trn::filter
