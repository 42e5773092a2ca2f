/**
 * @file filter_config.hpp
 * @brief Filter configuration: IMU error specification (LN-200 defaults), gating, limits.
 *
 * One place for every tunable of the filter, with its default and a check
 * (check_config) that rejects out-of-range values before the filter runs.
 */
#pragma once

#include <cstdint>

namespace trn::filter {

/** Seconds per hour, for the datasheet units below. */
inline constexpr double kSecPerHour = 3600.0;
inline constexpr double kRadPerDeg = 3.14159265358979323846 / 180.0;
inline constexpr double kMicroG = 9.80665e-6;  ///< 1 micro-g in m/s^2

/**
 * IMU error figures in SI units. Defaults: the LN-200 class of FACTS.md.
 * Bias model: a random turn-on constant plus an in-run first-order
 * Gauss-Markov process (sigma, correlation time).
 */
struct ImuSpec {
  double gyro_arw_rad_sqrts = 0.07 * kRadPerDeg / 60.0;          ///< 0.07 deg/sqrt(h)
  double gyro_bias_on_rads = 1.0 * kRadPerDeg / kSecPerHour;      ///< 1 deg/h turn-on
  double gyro_bias_run_rads = 0.35 * kRadPerDeg / kSecPerHour;    ///< 0.35 deg/h in-run
  double gyro_bias_tau_s = 100.0;                                 ///< in-run correlation time
  double accel_vrw_mps_sqrts = 0.03 / 60.0;                       ///< 0.03 m/s/sqrt(h)
  double accel_bias_on_mps2 = 200.0 * kMicroG;                    ///< 200 ug turn-on
  double accel_bias_run_mps2 = 50.0 * kMicroG;                    ///< 50 ug in-run
  double accel_bias_tau_s = 60.0;                                 ///< in-run correlation time
};

struct FilterConfig {
  ImuSpec imu{};
  double imu_dt_s = 0.01;         ///< IMU increment interval (100 Hz)
  double gate_chi2 = 13.815510558;///< chi-square 2 dof gate; default 99.9 %
  double min_depth = 1e-3;        ///< smallest accepted optical-axis component of a bearing
  double pixel_sigma_floor_px = 0.05;  ///< a match never claims better than this
  double max_sigma_pos_m = 5000.0;///< beyond this the solution is flagged not valid
  double stale_update_s = 3.0;    ///< no image with an accepted landmark for this long: flagged stale
  /// A lagged match between two history entries further apart than this (IMU
  /// samples lost there) is refused as stale: interpolating across the gap would guess.
  double max_history_gap_s = 0.05;
  /// 1-sigma error of the map itself against the world, per map axis (east, north, up): how far the
  /// landmarks the matches lock on sit, as a body, from where the map puts them. The filter's
  /// covariance is relative to the map (every landmark shares this error, so no match reveals it);
  /// the solution reports its position variance against the world with it added
  /// (NavOutput::pos_var_world). 0: a map taken as exact.
  double map_tie_sigma_m[3] = {0.0, 0.0, 0.0};
};

enum class ConfigError : std::uint8_t { kOk, kBadNoise, kBadTau, kBadDt, kBadGate, kBadLimit };

/** Checks every field's range. Returns kOk or the first field family out of range. */
ConfigError check_config(const FilterConfig& c) noexcept;

}  // namespace trn::filter
