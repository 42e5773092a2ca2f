/**
 * @file imu.cpp
 * @brief IMU increments: quadrature of the truth, then LN-200 class errors.
 */
#include "bsp_tile64/emu/devices/imu.hpp"

#include <cmath>

namespace bsp {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kDeg = kPi / 180.0;
constexpr double kG0 = 9.80665;
constexpr double kDt = 1.0 / static_cast<double>(kImuRateHz);
constexpr int kSubSteps = 2;

bool in(double v, double lo, double hi) noexcept { return v >= lo && v <= hi; }

bool config_valid(const ImuErrorConfig& c) noexcept {
  return in(c.gyro_bias_turn_on_dph, 0, 1000) && in(c.gyro_bias_in_run_dph, 0, 1000) &&
         in(c.gyro_bias_tau_s, 1, 1e5) && in(c.gyro_arw_dpsh, 0, 100) && in(c.gyro_scale_ppm, 0, 1e5) &&
         in(c.accel_bias_turn_on_ug, 0, 1e5) && in(c.accel_bias_in_run_ug, 0, 1e5) &&
         in(c.accel_bias_tau_s, 1, 1e5) && in(c.accel_vrw_mpsph, 0, 100) && in(c.accel_scale_ppm, 0, 1e5);
}

/** One first-order Gauss-Markov step over kDt: exact discretisation, stationary sigma kept. */
double gauss_markov(double b, double sigma, double tau_s, Rng& rng) noexcept {
  const double phi = std::exp(-kDt / tau_s);
  return phi * b + sigma * std::sqrt(1.0 - phi * phi) * rng.normal();
}

}  // namespace

void ImuModel::true_increments(const world::Trajectory& truth, std::uint32_t seq, double dtheta_rad[3],
                               double dv_mps[3]) noexcept {
  // 3-point Gauss-Legendre on each sub-interval: exact for degree-5 polynomials.
  constexpr double kNode = 0.7745966692414834;  // sqrt(3/5)
  constexpr double kW[3] = {5.0 / 9.0, 8.0 / 9.0, 5.0 / 9.0};
  const double t0 = static_cast<double>(seq) * kDt;
  const double h = kDt / kSubSteps;
  Eigen::Vector3d dth = Eigen::Vector3d::Zero();
  Eigen::Vector3d dv = Eigen::Vector3d::Zero();
  for (int k = 0; k < kSubSteps; ++k) {
    const double mid = t0 + (static_cast<double>(k) + 0.5) * h;
    const double nodes[3] = {mid - 0.5 * h * kNode, mid, mid + 0.5 * h * kNode};
    for (int i = 0; i < 3; ++i) {
      dth += (0.5 * h * kW[i]) * truth.rate_b(nodes[i]);
      dv += (0.5 * h * kW[i]) * truth.specific_force_b(nodes[i]);
    }
  }
  for (int i = 0; i < 3; ++i) {
    dtheta_rad[i] = dth[i];
    dv_mps[i] = dv[i];
  }
}

ImuError ImuModel::init(const world::Trajectory* truth, const ImuErrorConfig& cfg, std::uint64_t seed) noexcept {
  if (truth == nullptr) {
    return ImuError::kNoTruth;
  }
  if (!config_valid(cfg)) {
    return ImuError::kBadConfig;
  }
  truth_ = truth;
  cfg_ = cfg;
  rng_ = Rng(seed, StreamId::kSensor, kImuStreamIndex);
  next_seq_ = 0;
  err_ = ImuErrorState{};
  if (!cfg.enabled) {
    return ImuError::kOk;
  }
  for (int i = 0; i < 3; ++i) {
    err_.gyro_bias_rps[i] = rng_.normal() * cfg.gyro_bias_turn_on_dph * kDeg / 3600.0;
    err_.gyro_gm_rps[i] = rng_.normal() * cfg.gyro_bias_in_run_dph * kDeg / 3600.0;
    err_.gyro_scale[i] = rng_.normal() * cfg.gyro_scale_ppm * 1e-6;
    err_.accel_bias_mps2[i] = rng_.normal() * cfg.accel_bias_turn_on_ug * 1e-6 * kG0;
    err_.accel_gm_mps2[i] = rng_.normal() * cfg.accel_bias_in_run_ug * 1e-6 * kG0;
    err_.accel_scale[i] = rng_.normal() * cfg.accel_scale_ppm * 1e-6;
  }
  return ImuError::kOk;
}

void ImuModel::apply_errors(ImuSample& s) noexcept {
  // Random walk densities to per-sample sigmas: ARW [rad/sqrt(s)] * sqrt(dt).
  const double arw = cfg_.gyro_arw_dpsh * kDeg / 60.0 * std::sqrt(kDt);
  const double vrw = cfg_.accel_vrw_mpsph / 60.0 * std::sqrt(kDt);
  const double gyro_gm_sigma = cfg_.gyro_bias_in_run_dph * kDeg / 3600.0;
  const double accel_gm_sigma = cfg_.accel_bias_in_run_ug * 1e-6 * kG0;
  for (int i = 0; i < 3; ++i) {
    // The bias over the interval is taken at its start, then the process steps.
    s.dtheta_rad[i] = (1.0 + err_.gyro_scale[i]) * s.dtheta_rad[i] +
                      (err_.gyro_bias_rps[i] + err_.gyro_gm_rps[i]) * kDt + arw * rng_.normal();
    s.dv_mps[i] = (1.0 + err_.accel_scale[i]) * s.dv_mps[i] +
                  (err_.accel_bias_mps2[i] + err_.accel_gm_mps2[i]) * kDt + vrw * rng_.normal();
    err_.gyro_gm_rps[i] = gauss_markov(err_.gyro_gm_rps[i], gyro_gm_sigma, cfg_.gyro_bias_tau_s, rng_);
    err_.accel_gm_mps2[i] = gauss_markov(err_.accel_gm_mps2[i], accel_gm_sigma, cfg_.accel_bias_tau_s, rng_);
  }
}

ImuSample ImuModel::sample(std::uint32_t seq) noexcept {
  ImuSample s{};
  s.seq = seq;
  s.t_s = static_cast<double>(seq + 1U) * kDt;
  if (truth_ == nullptr || seq != next_seq_) {
    s.status = kImuStatusSequence;
    return s;
  }
  s.status = kImuStatusOk;
  true_increments(*truth_, seq, s.dtheta_rad, s.dv_mps);
  if (cfg_.enabled) {
    apply_errors(s);
  }
  ++next_seq_;
  return s;
}

}  // namespace bsp
