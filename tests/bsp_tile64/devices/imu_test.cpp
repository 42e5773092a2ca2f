/**
 * @file imu_test.cpp
 * @brief The IMU model: noise-free increments integrate back to the truth; errors have the LN-200 statistics.
 */
#include "bsp_tile64/emu/devices/imu.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <vector>

namespace {

constexpr double kDt = 0.01;
constexpr double kPi = 3.14159265358979323846;
constexpr double kDeg = kPi / 180.0;

Eigen::Quaterniond rotvec_to_q(const Eigen::Vector3d& v) {
  const double a = v.norm();
  if (a < 1e-15) {
    return Eigen::Quaterniond::Identity();
  }
  return Eigen::Quaterniond(Eigen::AngleAxisd(a, v / a));
}

/** A plain strapdown integrator: attitude by rotation vector, velocity at mid-interval attitude, trapezoid position. */
struct Strapdown {
  Eigen::Quaterniond q;
  Eigen::Vector3d v;
  Eigen::Vector3d r;

  void step(const bsp::ImuSample& s) {
    const Eigen::Vector3d dth(s.dtheta_rad[0], s.dtheta_rad[1], s.dtheta_rad[2]);
    const Eigen::Vector3d dv(s.dv_mps[0], s.dv_mps[1], s.dv_mps[2]);
    const Eigen::Quaterniond q_mid = q * rotvec_to_q(0.5 * dth);
    const Eigen::Vector3d v_new = v + q_mid * dv + bsp::world::gravity_m(r.z() + 0.5 * kDt * v.z()) * kDt;
    r += 0.5 * (v + v_new) * kDt;
    v = v_new;
    q = (q * rotvec_to_q(dth)).normalized();
  }
};

double angle_between(const Eigen::Quaterniond& a, const Eigen::Quaterniond& b) {
  return Eigen::AngleAxisd(a.conjugate() * b).angle();
}

TEST(ImuModel, NoiseFreeIncrementsIntegrateBackToTheTruthOverTheWholeDescent) {
  bsp::world::Trajectory traj;
  ASSERT_EQ(traj.init(bsp::world::TrajectoryConfig{}), bsp::world::WorldError::kOk);
  bsp::ImuErrorConfig cfg;
  cfg.enabled = false;
  bsp::ImuModel imu;
  ASSERT_EQ(imu.init(&traj, cfg, 7), bsp::ImuError::kOk);
  const bsp::world::TruthState s0 = traj.at(0.0);
  Strapdown sd{s0.q_mb, s0.v_mps, s0.r_m};
  const auto n = static_cast<std::uint32_t>(std::ceil(traj.duration_s() / kDt));
  double max_r = 0.0;
  double max_v = 0.0;
  double max_q = 0.0;
  for (std::uint32_t k = 0; k < n; ++k) {
    const bsp::ImuSample s = imu.sample(k);
    ASSERT_EQ(s.status, bsp::kImuStatusOk);
    ASSERT_DOUBLE_EQ(s.t_s, (k + 1) * kDt);
    sd.step(s);
    const bsp::world::TruthState t = traj.at(s.t_s);
    max_r = std::max(max_r, (sd.r - t.r_m).norm());
    max_v = std::max(max_v, (sd.v - t.v_mps).norm());
    max_q = std::max(max_q, angle_between(sd.q, t.q_mb));
  }
  std::printf("descent %.1f s, %u samples: max |dr| %.3g m, |dv| %.3g m/s, attitude %.3g rad\n", traj.duration_s(), n,
              max_r, max_v, max_q);
  // Measured: 0.7 mm, 4e-5 m/s, 3e-7 rad (the integrator's own coning and sculling residue).
  EXPECT_LT(max_r, 0.005);
  EXPECT_LT(max_v, 2e-4);
  EXPECT_LT(max_q, 1e-6);
}

TEST(ImuModel, OutOfSequenceRequestsAreFlaggedAndDoNotAdvance) {
  bsp::world::Trajectory traj;
  ASSERT_EQ(traj.init(bsp::world::TrajectoryConfig{}), bsp::world::WorldError::kOk);
  bsp::ImuModel imu;
  ASSERT_EQ(imu.init(&traj, bsp::ImuErrorConfig{}, 1), bsp::ImuError::kOk);
  EXPECT_EQ(imu.sample(1).status, bsp::kImuStatusSequence);
  EXPECT_EQ(imu.sample(0).status, bsp::kImuStatusOk);
  EXPECT_EQ(imu.sample(0).status, bsp::kImuStatusSequence);
  EXPECT_EQ(imu.sample(1).status, bsp::kImuStatusOk);
}

TEST(ImuModel, BadConfigurationAndMissingTruthAreRejected) {
  bsp::world::Trajectory traj;
  ASSERT_EQ(traj.init(bsp::world::TrajectoryConfig{}), bsp::world::WorldError::kOk);
  bsp::ImuModel imu;
  EXPECT_EQ(imu.init(nullptr, bsp::ImuErrorConfig{}, 1), bsp::ImuError::kNoTruth);
  bsp::ImuErrorConfig cfg;
  cfg.gyro_bias_tau_s = 0.0;
  EXPECT_EQ(imu.init(&traj, cfg, 1), bsp::ImuError::kBadConfig);
  cfg = bsp::ImuErrorConfig{};
  cfg.accel_vrw_mpsph = -1.0;
  EXPECT_EQ(imu.init(&traj, cfg, 1), bsp::ImuError::kBadConfig);
}

TEST(ImuModel, SameSeedGivesTheSameBitsAndAnotherSeedDiffers) {
  bsp::world::Trajectory traj;
  ASSERT_EQ(traj.init(bsp::world::TrajectoryConfig{}), bsp::world::WorldError::kOk);
  bsp::ImuModel a;
  bsp::ImuModel b;
  bsp::ImuModel c;
  ASSERT_EQ(a.init(&traj, bsp::ImuErrorConfig{}, 11), bsp::ImuError::kOk);
  ASSERT_EQ(b.init(&traj, bsp::ImuErrorConfig{}, 11), bsp::ImuError::kOk);
  ASSERT_EQ(c.init(&traj, bsp::ImuErrorConfig{}, 12), bsp::ImuError::kOk);
  bool differs = false;
  for (std::uint32_t k = 0; k < 200; ++k) {
    const bsp::ImuSample sa = a.sample(k);
    const bsp::ImuSample sb = b.sample(k);
    const bsp::ImuSample sc = c.sample(k);
    for (int i = 0; i < 3; ++i) {
      ASSERT_EQ(sa.dtheta_rad[i], sb.dtheta_rad[i]) << "sample " << k;
      ASSERT_EQ(sa.dv_mps[i], sb.dv_mps[i]) << "sample " << k;
      differs = differs || sa.dtheta_rad[i] != sc.dtheta_rad[i];
    }
  }
  EXPECT_TRUE(differs);
}

/** Error of each sample (measured minus truth) over @p n samples, for one seed and one error configuration. */
struct ErrorRun {
  std::vector<Eigen::Vector3d> gyro;   // rad per sample
  std::vector<Eigen::Vector3d> accel;  // m/s per sample
};

ErrorRun run_errors(const bsp::world::Trajectory& traj, const bsp::ImuErrorConfig& cfg, std::uint64_t seed,
                    std::uint32_t n) {
  bsp::ImuModel imu;
  EXPECT_EQ(imu.init(&traj, cfg, seed), bsp::ImuError::kOk);
  ErrorRun out;
  for (std::uint32_t k = 0; k < n; ++k) {
    const bsp::ImuSample s = imu.sample(k);
    double dth[3];
    double dv[3];
    bsp::ImuModel::true_increments(traj, k, dth, dv);
    out.gyro.emplace_back(s.dtheta_rad[0] - dth[0], s.dtheta_rad[1] - dth[1], s.dtheta_rad[2] - dth[2]);
    out.accel.emplace_back(s.dv_mps[0] - dv[0], s.dv_mps[1] - dv[1], s.dv_mps[2] - dv[2]);
  }
  return out;
}

bsp::ImuErrorConfig only(double bsp::ImuErrorConfig::*field, double value) {
  bsp::ImuErrorConfig c;
  c.gyro_bias_turn_on_dph = c.gyro_bias_in_run_dph = c.gyro_arw_dpsh = c.gyro_scale_ppm = 0.0;
  c.accel_bias_turn_on_ug = c.accel_bias_in_run_ug = c.accel_vrw_mpsph = c.accel_scale_ppm = 0.0;
  c.*field = value;
  return c;
}

/** Sample standard deviation over seeds of a scalar statistic, all axes pooled (mean known zero). */
template <class Fn>
double rms_over_seeds(const bsp::world::Trajectory& traj, const bsp::ImuErrorConfig& cfg, std::uint32_t n,
                      std::uint32_t seeds, Fn&& stat) {
  double sum2 = 0.0;
  for (std::uint32_t s = 0; s < seeds; ++s) {
    const ErrorRun run = run_errors(traj, cfg, 1000U + s, n);
    for (int axis = 0; axis < 3; ++axis) {
      const double x = stat(run, axis);
      sum2 += x * x;
    }
  }
  return std::sqrt(sum2 / (3.0 * seeds));
}

class ImuStatistics : public ::testing::Test {
 protected:
  void SetUp() override { ASSERT_EQ(traj_.init(bsp::world::TrajectoryConfig{}), bsp::world::WorldError::kOk); }
  bsp::world::Trajectory traj_;
  static constexpr std::uint32_t kSeeds = 60;  // 180 axis draws: sigma estimate within ~+-15% at 3 sigma
};

TEST_F(ImuStatistics, AngleRandomWalkGrowsAsArwTimesRootT) {
  constexpr std::uint32_t kN = 3000;  // 30 s
  const double arw = 0.07 * kDeg / 60.0;
  const double sigma = rms_over_seeds(traj_, only(&bsp::ImuErrorConfig::gyro_arw_dpsh, 0.07), kN, kSeeds,
                                      [](const ErrorRun& r, int a) {
                                        double s = 0.0;
                                        for (const auto& e : r.gyro) s += e[a];
                                        return s;
                                      });
  const double expected = arw * std::sqrt(kN * kDt);
  std::printf("angle after 30 s: %.3g rad, expected %.3g rad (seeds 1000..%u)\n", sigma, expected, 999U + kSeeds);
  EXPECT_NEAR(sigma / expected, 1.0, 0.15);
}

TEST_F(ImuStatistics, VelocityRandomWalkGrowsAsVrwTimesRootT) {
  constexpr std::uint32_t kN = 3000;
  const double sigma = rms_over_seeds(traj_, only(&bsp::ImuErrorConfig::accel_vrw_mpsph, 0.03), kN, kSeeds,
                                      [](const ErrorRun& r, int a) {
                                        double s = 0.0;
                                        for (const auto& e : r.accel) s += e[a];
                                        return s;
                                      });
  const double expected = 0.03 / 60.0 * std::sqrt(kN * kDt);
  std::printf("velocity after 30 s: %.3g m/s, expected %.3g m/s\n", sigma, expected);
  EXPECT_NEAR(sigma / expected, 1.0, 0.15);
}

TEST_F(ImuStatistics, TurnOnBiasesHaveTheirDataSheetSigma) {
  constexpr std::uint32_t kN = 10;
  const double g_sigma = rms_over_seeds(traj_, only(&bsp::ImuErrorConfig::gyro_bias_turn_on_dph, 1.0), kN, kSeeds,
                                        [](const ErrorRun& r, int a) { return r.gyro[0][a] / kDt; });
  const double a_sigma = rms_over_seeds(traj_, only(&bsp::ImuErrorConfig::accel_bias_turn_on_ug, 200.0), kN,
                                        kSeeds, [](const ErrorRun& r, int a) { return r.accel[0][a] / kDt; });
  EXPECT_NEAR(g_sigma / (1.0 * kDeg / 3600.0), 1.0, 0.15);
  EXPECT_NEAR(a_sigma / (200e-6 * 9.80665), 1.0, 0.15);
}

TEST_F(ImuStatistics, InRunBiasIsStationaryWithItsCorrelationTime) {
  // Gauss-Markov: stationary sigma at any time, correlation exp(-1) one correlation time apart.
  constexpr std::uint32_t kLag = 6000;  // 60 s: the accelerometer's correlation time
  const bsp::ImuErrorConfig cfg = only(&bsp::ImuErrorConfig::accel_bias_in_run_ug, 50.0);
  double s00 = 0.0;
  double s11 = 0.0;
  double s01 = 0.0;
  for (std::uint32_t s = 0; s < 2U * kSeeds; ++s) {
    const ErrorRun r = run_errors(traj_, cfg, 5000U + s, kLag + 1U);
    for (int a = 0; a < 3; ++a) {
      const double b0 = r.accel[0][a] / kDt;
      const double b1 = r.accel[kLag][a] / kDt;
      s00 += b0 * b0;
      s11 += b1 * b1;
      s01 += b0 * b1;
    }
  }
  const double sigma = 50e-6 * 9.80665;
  const double draws = 6.0 * kSeeds;
  std::printf("GM: sigma(0) %.3g, sigma(60 s) %.3g, corr %.3f (expected %.3g, %.3f)\n", std::sqrt(s00 / draws),
              std::sqrt(s11 / draws), s01 / std::sqrt(s00 * s11), sigma, std::exp(-1.0));
  // 360 draws: sigma estimates within ~4%, the correlation within ~0.045 (1 sigma); 3 sigma bounds.
  EXPECT_NEAR(std::sqrt(s00 / draws) / sigma, 1.0, 0.12);
  EXPECT_NEAR(std::sqrt(s11 / draws) / sigma, 1.0, 0.12);
  EXPECT_NEAR(s01 / std::sqrt(s00 * s11), std::exp(-1.0), 0.14);
}

TEST_F(ImuStatistics, ScaleFactorErrorIsProportionalToTheTrueIncrement) {
  // Specific force along body z is ~3.7 m/s^2 all descent: the z error over the truth is the scale factor.
  const bsp::ImuErrorConfig cfg = only(&bsp::ImuErrorConfig::accel_scale_ppm, 300.0);
  double sum2 = 0.0;
  for (std::uint32_t s = 0; s < kSeeds; ++s) {
    bsp::ImuModel imu;
    ASSERT_EQ(imu.init(&traj_, cfg, 7000U + s), bsp::ImuError::kOk);
    const bsp::ImuSample m = imu.sample(0);
    double dth[3];
    double dv[3];
    bsp::ImuModel::true_increments(traj_, 0, dth, dv);
    const double sf = (m.dv_mps[2] - dv[2]) / dv[2];
    EXPECT_NEAR(sf, imu.errors().accel_scale[2], 1e-9);
    sum2 += sf * sf;
  }
  EXPECT_NEAR(std::sqrt(sum2 / kSeeds) / 300e-6, 1.0, 0.3);
}

TEST_F(ImuStatistics, FullErrorModelAttitudeDriftMatchesTheLn200Budget) {
  // Over 30 s the attitude error from gyro errors is dominated by ARW and turn-on bias:
  // sigma^2 = ARW^2 T + (b T)^2 + (b_GM T)^2 (GM nearly constant over T << tau).
  constexpr std::uint32_t kN = 3000;
  const double t = kN * kDt;
  const double arw = 0.07 * kDeg / 60.0;
  const double b = 1.0 * kDeg / 3600.0;
  const double bgm = 0.35 * kDeg / 3600.0;
  bsp::ImuErrorConfig cfg;
  cfg.gyro_scale_ppm = 0.0;  // scale error depends on the trajectory's rates; checked on its own
  const double sigma = rms_over_seeds(traj_, cfg, kN, kSeeds, [](const ErrorRun& r, int a) {
    double s = 0.0;
    for (const auto& e : r.gyro) s += e[a];
    return s;
  });
  const double expected = std::sqrt(arw * arw * t + b * b * t * t + bgm * bgm * t * t);
  std::printf("attitude drift over 30 s: %.3g rad, budget %.3g rad\n", sigma, expected);
  EXPECT_NEAR(sigma / expected, 1.0, 0.2);
}

}  // namespace
