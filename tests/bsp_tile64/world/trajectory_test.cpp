/**
 * @file trajectory_test.cpp
 * @brief The descent truth: kinematic consistency, profile, attitude oscillation, configuration checks.
 */
#include "bsp_tile64/world/trajectory.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace {

constexpr double kPi = 3.14159265358979323846;

TEST(Trajectory, VelocityAndAccelerationAreTheDerivativesOfPosition) {
  bsp::world::Trajectory tr;
  ASSERT_EQ(tr.init(bsp::world::TrajectoryConfig{}), bsp::world::WorldError::kOk);
  constexpr double kH = 1e-3;
  for (double t = 0.5; t < tr.duration_s(); t += 1.7) {
    const bsp::world::TruthState a = tr.at(t - kH);
    const bsp::world::TruthState b = tr.at(t);
    const bsp::world::TruthState c = tr.at(t + kH);
    EXPECT_LT(((c.r_m - a.r_m) / (2 * kH) - b.v_mps).norm(), 1e-5) << "t " << t;
    EXPECT_LT(((c.v_mps - a.v_mps) / (2 * kH) - b.a_mps2).norm(), 1e-5) << "t " << t;
  }
}

TEST(Trajectory, BodyRateIsTheDerivativeOfTheAttitude) {
  bsp::world::Trajectory tr;
  ASSERT_EQ(tr.init(bsp::world::TrajectoryConfig{}), bsp::world::WorldError::kOk);
  constexpr double kH = 1e-4;
  for (double t = 0.3; t < tr.duration_s(); t += 2.3) {
    // q(t+h) = q(t-h) * exp(w h2): the rotation vector over 2h is w * 2h to second order.
    const Eigen::AngleAxisd d(tr.attitude(t - kH).conjugate() * tr.attitude(t + kH));
    const Eigen::Vector3d w = d.axis() * d.angle() / (2 * kH);
    EXPECT_LT((w - tr.rate_b(t)).norm(), 1e-6) << "t " << t;
  }
}

TEST(Trajectory, DescendsFromStartToEndAltitudeAtParachuteRates) {
  bsp::world::Trajectory tr;
  const bsp::world::TrajectoryConfig cfg;
  ASSERT_EQ(tr.init(cfg), bsp::world::WorldError::kOk);
  EXPECT_NEAR(tr.at(0.0).r_m.z(), 4200.0, 1e-9);
  EXPECT_NEAR(tr.at(tr.duration_s()).r_m.z(), 1000.0, 1e-6);
  EXPECT_GT(tr.duration_s(), 35.0);
  EXPECT_LT(tr.duration_s(), 60.0);
  double prev_rate = 1e9;
  for (double t = 0.0; t <= tr.duration_s(); t += 1.0) {
    const double rate = -tr.at(t).v_mps.z();
    EXPECT_LE(rate, prev_rate);
    EXPECT_GE(rate, 60.0);
    EXPECT_LE(rate, 80.0);
    prev_rate = rate;
  }
  const Eigen::Vector3d drift = tr.at(tr.duration_s()).r_m - tr.at(0.0).r_m;
  EXPECT_GT(std::hypot(drift.x(), drift.y()), 100.0);  // the wind carries it
}

TEST(Trajectory, AttitudeOscillatesAFewDegreesAboutNadir) {
  bsp::world::Trajectory tr;
  ASSERT_EQ(tr.init(bsp::world::TrajectoryConfig{}), bsp::world::WorldError::kOk);
  double max_tilt = 0.0;
  for (double t = 0.0; t <= tr.duration_s(); t += 0.05) {
    const Eigen::Vector3d down = tr.attitude(t) * Eigen::Vector3d::UnitZ();  // body z in the map frame
    max_tilt = std::max(max_tilt, std::acos(-down.z()) * 180.0 / kPi);
  }
  EXPECT_GT(max_tilt, 2.0);
  EXPECT_LT(max_tilt, 6.0);
}

TEST(Trajectory, OutOfRangeConfigurationsAreRejected) {
  bsp::world::Trajectory tr;
  bsp::world::TrajectoryConfig c;
  c.end_altitude_m = 5000.0;
  EXPECT_EQ(tr.init(c), bsp::world::WorldError::kBadConfig);
  c = bsp::world::TrajectoryConfig{};
  c.rate_tau_s = 0.0;
  EXPECT_EQ(tr.init(c), bsp::world::WorldError::kBadConfig);
  c = bsp::world::TrajectoryConfig{};
  c.oscillation_deg = 45.0;
  EXPECT_EQ(tr.init(c), bsp::world::WorldError::kBadConfig);
}

TEST(Trajectory, GravityFollowsTheFramesModel) {
  EXPECT_NEAR(bsp::world::gravity_m(0.0).z(), -3.7278, 1e-3);
  EXPECT_GT(bsp::world::gravity_m(4200.0).z(), bsp::world::gravity_m(0.0).z());
}

}  // namespace
