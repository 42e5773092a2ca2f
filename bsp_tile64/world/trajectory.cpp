/**
 * @file trajectory.cpp
 * @brief Closed forms of the descent: position, its two derivatives, attitude and body rate.
 */
#include "bsp_tile64/world/trajectory.hpp"

#include "bsp_tile64/api/frames.hpp"

#include <cmath>

namespace bsp::world {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kDeg = kPi / 180.0;
constexpr double kRollPeriodFactor = 1.3;  // roll and pitch periods differ so the cone is not planar

bool config_valid(const TrajectoryConfig& c) noexcept {
  return c.start_altitude_m >= 500.0 && c.start_altitude_m <= 20000.0 && c.end_altitude_m >= 0.0 &&
         c.end_altitude_m < c.start_altitude_m && c.start_rate_mps >= 1.0 && c.start_rate_mps <= 200.0 &&
         c.end_rate_mps >= 1.0 && c.end_rate_mps <= 200.0 && c.rate_tau_s >= 1.0 && c.rate_tau_s <= 1000.0 &&
         std::fabs(c.wind_east_mps) <= 50.0 && std::fabs(c.wind_north_mps) <= 50.0 && c.sway_mps >= 0.0 &&
         c.sway_mps <= 20.0 && c.sway_period_s >= 0.5 && c.sway_period_s <= 100.0 &&
         c.oscillation_deg >= 0.0 && c.oscillation_deg <= 30.0 && c.oscillation_period_s >= 0.5 &&
         c.oscillation_period_s <= 100.0 && std::fabs(c.spin_dps) <= 90.0;
}

/** Body FRD with heading north, level: x -> north, y -> east, z -> down (NED into ENU). */
Eigen::Quaterniond nominal_q() noexcept {
  Eigen::Matrix3d r;
  r << 0.0, 1.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, -1.0;
  return Eigen::Quaterniond(r);
}

}  // namespace

Eigen::Vector3d gravity_m(double z_m) noexcept { return {0.0, 0.0, -frames::gravity_mps2(z_m)}; }

WorldError Trajectory::init(const TrajectoryConfig& cfg) noexcept {
  if (!config_valid(cfg)) {
    return WorldError::kBadConfig;
  }
  cfg_ = cfg;
  // Altitude is strictly decreasing (rate >= 1 m/s): Newton from the mean-rate guess converges.
  double t = (cfg.start_altitude_m - cfg.end_altitude_m) / cfg.end_rate_mps;
  for (int i = 0; i < 50; ++i) {
    const double f = altitude_m(t) - cfg.end_altitude_m;
    t += f / rate_mps(t);
    if (std::fabs(f) < 1e-9) {
      break;
    }
  }
  duration_s_ = t;
  return WorldError::kOk;
}

double Trajectory::rate_mps(double t_s) const noexcept {
  return cfg_.end_rate_mps + (cfg_.start_rate_mps - cfg_.end_rate_mps) * std::exp(-t_s / cfg_.rate_tau_s);
}

double Trajectory::altitude_m(double t_s) const noexcept {
  const double tau = cfg_.rate_tau_s;
  return cfg_.start_altitude_m - cfg_.end_rate_mps * t_s -
         (cfg_.start_rate_mps - cfg_.end_rate_mps) * tau * (1.0 - std::exp(-t_s / tau));
}

void Trajectory::euler(double t_s, double e[3], double de[3]) const noexcept {
  const double a = cfg_.oscillation_deg * kDeg;
  const double wp = 2.0 * kPi / cfg_.oscillation_period_s;
  const double wr = wp / kRollPeriodFactor;
  const double wy = 0.5 * wp;
  // e = (roll, pitch, yaw); phases chosen so no angle starts at an extreme.
  e[0] = a * std::sin(wr * t_s + 0.7);
  de[0] = a * wr * std::cos(wr * t_s + 0.7);
  e[1] = a * std::sin(wp * t_s);
  de[1] = a * wp * std::cos(wp * t_s);
  e[2] = cfg_.heading_deg * kDeg + cfg_.spin_dps * kDeg * t_s + 0.5 * a * std::sin(wy * t_s + 1.1);
  de[2] = cfg_.spin_dps * kDeg + 0.5 * a * wy * std::cos(wy * t_s + 1.1);
}

Eigen::Quaterniond Trajectory::attitude(double t_s) const noexcept {
  double e[3];
  double de[3];
  euler(t_s, e, de);
  // ZYX (yaw, pitch, roll) in the NED sense, applied after the NED-to-ENU turn.
  const Eigen::Quaterniond q = nominal_q() * Eigen::AngleAxisd(e[2], Eigen::Vector3d::UnitZ()) *
                               Eigen::AngleAxisd(e[1], Eigen::Vector3d::UnitY()) *
                               Eigen::AngleAxisd(e[0], Eigen::Vector3d::UnitX());
  return q.normalized();
}

Eigen::Vector3d Trajectory::rate_b(double t_s) const noexcept {
  double e[3];
  double de[3];
  euler(t_s, e, de);
  const double sr = std::sin(e[0]);
  const double cr = std::cos(e[0]);
  const double sp = std::sin(e[1]);
  const double cp = std::cos(e[1]);
  return {de[0] - de[2] * sp, de[1] * cr + de[2] * sr * cp, -de[1] * sr + de[2] * cr * cp};
}

void Trajectory::translation(double t_s, TruthState& s) const noexcept {
  const double ws = 2.0 * kPi / cfg_.sway_period_s;
  const double amp = cfg_.sway_mps;
  const double tau = cfg_.rate_tau_s;
  const double dv0 = cfg_.start_rate_mps - cfg_.end_rate_mps;
  // Sway: east ~ sin, north ~ sin(. + 1); position and acceleration are its integral and derivative.
  s.r_m = {cfg_.start_x_m + cfg_.wind_east_mps * t_s + amp / ws * (1.0 - std::cos(ws * t_s)),
           cfg_.start_y_m + cfg_.wind_north_mps * t_s + amp / ws * (std::cos(1.0) - std::cos(ws * t_s + 1.0)),
           altitude_m(t_s)};
  s.v_mps = {cfg_.wind_east_mps + amp * std::sin(ws * t_s), cfg_.wind_north_mps + amp * std::sin(ws * t_s + 1.0),
             -rate_mps(t_s)};
  s.a_mps2 = {amp * ws * std::cos(ws * t_s), amp * ws * std::cos(ws * t_s + 1.0),
              dv0 / tau * std::exp(-t_s / tau)};
}

TruthState Trajectory::at(double t_s) const noexcept {
  TruthState s;
  s.t_s = t_s;
  translation(t_s, s);
  s.q_mb = attitude(t_s);
  s.w_b_rps = rate_b(t_s);
  return s;
}

Eigen::Vector3d Trajectory::specific_force_b(double t_s) const noexcept {
  TruthState s;
  translation(t_s, s);
  s.q_mb = attitude(t_s);
  const Eigen::Vector3d f_m = s.a_mps2 - gravity_m(s.r_m.z());
  return s.q_mb.conjugate() * f_m;
}

}  // namespace bsp::world
