/**
 * @file filter_config.cpp
 * @brief Range checks of the filter configuration.
 */
#include "trn/filter/filter_config.hpp"

#include <cmath>

namespace trn::filter {

namespace {

bool non_negative(double v) noexcept { return std::isfinite(v) && v >= 0.0; }
bool positive(double v) noexcept { return std::isfinite(v) && v > 0.0; }

}  // namespace

ConfigError check_config(const FilterConfig& c) noexcept {
  const ImuSpec& s = c.imu;
  if (!non_negative(s.gyro_arw_rad_sqrts) || !non_negative(s.gyro_bias_on_rads) ||
      !non_negative(s.gyro_bias_run_rads) || !non_negative(s.accel_vrw_mps_sqrts) ||
      !non_negative(s.accel_bias_on_mps2) || !non_negative(s.accel_bias_run_mps2)) {
    return ConfigError::kBadNoise;
  }
  if (!positive(s.gyro_bias_tau_s) || !positive(s.accel_bias_tau_s)) {
    return ConfigError::kBadTau;
  }
  if (!positive(c.imu_dt_s) || c.imu_dt_s > 1.0) {
    return ConfigError::kBadDt;
  }
  if (!positive(c.gate_chi2)) {
    return ConfigError::kBadGate;
  }
  if (!positive(c.min_depth) || c.min_depth >= 1.0 || !positive(c.pixel_sigma_floor_px) ||
      !positive(c.max_sigma_pos_m) || !positive(c.stale_update_s) || !positive(c.max_history_gap_s) ||
      !non_negative(c.map_tie_sigma_m[0]) || !non_negative(c.map_tie_sigma_m[1]) ||
      !non_negative(c.map_tie_sigma_m[2])) {
    return ConfigError::kBadLimit;
  }
  return ConfigError::kOk;
}

}  // namespace trn::filter
