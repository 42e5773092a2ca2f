/**
 * @file filter_state.hpp
 * @brief Everything a filter replica holds between steps: nominal, covariance, time, counters.
 *
 * This aggregate is what state_block.hpp serializes for TMR state transfer and
 * what nav_output.hpp summarizes for voting. Configuration is not part of it:
 * replicas are built from the same static tables. The pose history is part of
 * it (about 16 KB of the 18 KB): a replica restored from a state block applies
 * a lagged match exactly as the original does.
 */
#pragma once

#include "trn/filter/linalg.hpp"
#include "trn/filter/nav_state.hpp"
#include "trn/filter/pose_history.hpp"

#include <cstdint>

namespace trn::filter {

struct FilterCounters {
  std::uint64_t propagations = 0;      ///< IMU samples integrated
  std::uint32_t last_imu_seq = 0;      ///< seq of the last integrated sample
  std::uint32_t imu_rejected = 0;      ///< samples refused (device status, not finite)
  std::uint32_t imu_gaps = 0;          ///< sequence jumps (lost samples)
  std::uint32_t batches = 0;           ///< update calls with at least one match
  std::uint32_t accepted = 0;          ///< matches applied
  std::uint32_t rejected_gate = 0;     ///< matches refused by the Mahalanobis gate
  std::uint32_t rejected_invalid = 0;  ///< matches refused as geometrically invalid
  std::uint32_t rejected_stale = 0;    ///< matches refused for their time: older than the history, or ahead of the state
  std::uint32_t coarse_accepted = 0;   ///< applied matches of the coarse stage (landmark kCoarseLandmark)
  std::uint32_t last_accepted = 0;     ///< matches applied by the last update call
  std::uint32_t last_rejected = 0;     ///< matches refused by the last update call
  std::uint32_t numeric_faults = 0;    ///< non-finite state or covariance seen
};

struct FilterState {
  std::uint32_t initialized = 0;       ///< 1 once init() succeeded
  std::uint32_t last_imu_ok = 0;       ///< 1 if the last IMU sample was integrated
  double t_s = 0.0;                    ///< time of the state, emulated s
  double t_last_update_s = 0.0;        ///< latest image time of an accepted landmark, s
  NominalState x{};
  Mat15 p = Mat15::Zero();             ///< error-state covariance
  FilterCounters c{};
  PoseHistory hist{};                  ///< past poses, one per propagation (lagged matches)
};

/** Every number of the nominal state, the covariance and the times of @p s is finite. */
bool finite_state(const FilterState& s) noexcept;

/** Puts @p s back to its default values field by field (no 18 KB temporary on the stack). */
inline void clear_state(FilterState& s) noexcept {
  s.initialized = 0;
  s.last_imu_ok = 0;
  s.t_s = 0.0;
  s.t_last_update_s = 0.0;
  s.x = NominalState{};
  s.p.setZero();
  s.c = FilterCounters{};
  history_clear(s.hist);
}

}  // namespace trn::filter
