/**
 * @file trajectory.hpp
 * @brief The descent (truth): a parachute-like closed-form trajectory, consistent to all orders used.
 *
 * Vertical: the descent rate relaxes exponentially from start_rate_mps to
 * end_rate_mps with time constant rate_tau_s (a parachute approaching terminal
 * velocity in thickening air). Horizontal: constant wind drift plus a
 * pendulum-like sway. Attitude: body FRD (frames.hpp) with yaw (heading from
 * north, slow spin plus a wobble), pitch and roll oscillating a few degrees.
 * Position, velocity and acceleration, attitude and body angular rate are
 * exact derivatives of one another (closed forms), so an IMU integrating this
 * truth reproduces it. Altitudes are above the datum (z of the map frame).
 */
#pragma once

#include "bsp_tile64/world/terrain.hpp"

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace bsp::world {

struct TrajectoryConfig {
  double start_altitude_m = 4200.0;  ///< z at t = 0, metres above datum, 500..20000
  double end_altitude_m = 1000.0;    ///< z at the end, metres, 0..start
  double start_x_m = 0.0;            ///< map position at t = 0, metres
  double start_y_m = 0.0;
  double start_rate_mps = 80.0;      ///< descent rate at t = 0, m/s, 1..200
  double end_rate_mps = 60.0;        ///< asymptotic descent rate, m/s, 1..200
  double rate_tau_s = 25.0;          ///< relaxation time of the descent rate, s, 1..1000
  double wind_east_mps = 8.0;        ///< horizontal drift, m/s, |.| <= 50
  double wind_north_mps = -4.0;
  double sway_mps = 1.5;             ///< amplitude of the horizontal sway velocity, m/s, 0..20
  double sway_period_s = 5.0;        ///< period of the sway, s, 0.5..100
  double oscillation_deg = 3.0;      ///< pitch and roll amplitude, deg, 0..30
  double oscillation_period_s = 4.0; ///< pitch period (roll: 1.3x), s, 0.5..100
  double heading_deg = 30.0;         ///< initial heading from north, deg
  double spin_dps = 2.0;             ///< mean yaw rate, deg/s, |.| <= 90
};

/** Truth at one instant. */
struct TruthState {
  double t_s = 0.0;
  Eigen::Vector3d r_m;       ///< position, map frame
  Eigen::Vector3d v_mps;     ///< velocity, map frame
  Eigen::Vector3d a_mps2;    ///< kinematic acceleration, map frame
  Eigen::Quaterniond q_mb;   ///< body to map
  Eigen::Vector3d w_b_rps;   ///< body angular rate relative to the map frame, body axes
};

class Trajectory {
 public:
  /** Sets the trajectory; kBadConfig (unchanged) if a parameter is out of range or the end is never reached. */
  WorldError init(const TrajectoryConfig& cfg) noexcept;

  /** Time at which the end altitude is reached, s. */
  double duration_s() const noexcept { return duration_s_; }

  /** Truth at @p t_s (any t >= 0; the closed forms continue past the end). */
  TruthState at(double t_s) const noexcept;

  /** Specific force (kinematic acceleration minus gravity) in body axes at @p t_s, m/s^2. */
  Eigen::Vector3d specific_force_b(double t_s) const noexcept;

  /** Body angular rate at @p t_s, rad/s (cheaper than at()). */
  Eigen::Vector3d rate_b(double t_s) const noexcept;

  /** Attitude at @p t_s (cheaper than at()). */
  Eigen::Quaterniond attitude(double t_s) const noexcept;

  const TrajectoryConfig& config() const noexcept { return cfg_; }

 private:
  double altitude_m(double t_s) const noexcept;
  double rate_mps(double t_s) const noexcept;
  void euler(double t_s, double e[3], double de[3]) const noexcept;
  /** Position, velocity and acceleration of @p s at @p t_s (attitude untouched). */
  void translation(double t_s, TruthState& s) const noexcept;
  TrajectoryConfig cfg_{};
  double duration_s_ = 0.0;
};

/** Gravity vector in the map frame at height @p z_m, m/s^2 (frames.hpp model). */
Eigen::Vector3d gravity_m(double z_m) noexcept;

}  // namespace bsp::world
