/**
 * @file jacobian_test.cpp
 * @brief The analytic error transition F and bearing Jacobian H match central finite differences
 *        of the nonlinear models (signs and attitude conventions included).
 */
#include "tests/trn/filter/truth_sim.hpp"
#include "trn/filter/bearing_model.hpp"
#include "trn/filter/strapdown.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace {

using trn::filter::Mat15;
using trn::filter::NominalState;
using trn::filter::Vec15;
using Vec3 = filter_test::Vec3;

/** x (+) dx: additive except the attitude, q <- q Exp(dth). */
NominalState boxplus(const NominalState& x, const Vec15& dx) {
  NominalState y = x;
  y.p_m += dx.segment<3>(0);
  y.v_mps += dx.segment<3>(3);
  y.q_mb = (x.q_mb * trn::filter::quat_exp(dx.segment<3>(6))).normalized();
  y.bg_rads += dx.segment<3>(9);
  y.ba_mps2 += dx.segment<3>(12);
  return y;
}

/** y (-) x, the inverse of boxplus. */
Vec15 boxminus(const NominalState& y, const NominalState& x) {
  Vec15 d;
  d << y.p_m - x.p_m, y.v_mps - x.v_mps, trn::filter::quat_log(x.q_mb.conjugate() * y.q_mb), y.bg_rads - x.bg_rads,
      y.ba_mps2 - x.ba_mps2;
  return d;
}

NominalState sample_state() {
  NominalState x;
  x.p_m = Vec3(100.0, -50.0, 3000.0);
  x.v_mps = Vec3(20.0, -5.0, -60.0);
  x.q_mb = (filter_test::initial_attitude() * trn::filter::quat_exp(Vec3(0.05, -0.03, 0.2))).normalized();
  x.bg_rads = Vec3(2e-6, -1e-6, 3e-6);
  x.ba_mps2 = Vec3(1e-3, -2e-3, 5e-4);
  return x;
}

TEST(FilterJacobian, TransitionMatchesFiniteDifferencesOfTheStrapdown) {
  const NominalState x0 = sample_state();
  trn::filter::ImuIncrement inc;
  inc.dtheta_rad = Vec3(0.0006, -0.0004, 0.0002);
  inc.dv_mps = Vec3(0.01, 0.02, -0.037);
  inc.dt_s = 0.01;
  bsp::Work work;
  static Mat15 f;
  static Mat15 scratch;
  NominalState x1 = x0;
  (void)trn::filter::strapdown_step(x1, inc, f, work);
  // F neglects two terms first order in the increment, in the bias columns:
  // d(rotation compensation)/d(b_g) = dt/2 [dvc]x (v and p rows), and the
  // right Jacobian of Exp in d(dtheta)/d(b_g) = -dt J_r ~ -dt (I - [dth/2]x);
  // both allowed for, nothing else.
  const double neglected_bg_v = 0.5 * inc.dt_s * inc.dv_mps.norm();
  const double neglected_rot = inc.dt_s * inc.dtheta_rad.norm();
  // Steps large enough that rounding of p (~3 km) stays far below the tolerance.
  const double eps[5] = {1e-2, 1e-3, 1e-3, 1e-5, 1e-3};
  for (int j = 0; j < 15; ++j) {
    Vec15 d = Vec15::Zero();
    d(j) = eps[j / 3];
    NominalState xp = boxplus(x0, d);
    NominalState xm = boxplus(x0, -d);
    (void)trn::filter::strapdown_step(xp, inc, scratch, work);
    (void)trn::filter::strapdown_step(xm, inc, scratch, work);
    const Vec15 col = (boxminus(xp, x1) - boxminus(xm, x1)) / (2.0 * eps[j / 3]);
    for (int i = 0; i < 15; ++i) {
      const bool bg_col = j >= 9 && j < 12 && i < 6;
      const bool bias_col = j >= 9;
      const double tol =
          1e-7 * (1.0 + std::abs(f(i, j))) + (bg_col ? neglected_bg_v : 0.0) + (bias_col ? neglected_rot : 0.0);
      EXPECT_NEAR(col(i), f(i, j), tol) << "F(" << i << "," << j << ")";
    }
  }
}

TEST(FilterJacobian, BearingJacobianMatchesFiniteDifferencesOfThePrediction) {
  const NominalState x0 = sample_state();
  bsp::CameraModel cam;
  // A tilted mounting, so the camera rotation is exercised too.
  const filter_test::Mat3 r_bc = Eigen::AngleAxisd(0.3, Vec3(1.0, 2.0, 0.5).normalized()).toRotationMatrix();
  for (int i = 0; i < 9; ++i) {
    cam.r_bc[i] = r_bc(i / 3, i % 3);
  }
  const trn::filter::CameraGeometry geo = trn::filter::camera_geometry(cam);
  trn::Match m{};
  const Vec3 dir_c = Vec3(0.3, -0.2, 1.0).normalized();
  const Vec3 lm = x0.p_m + 3500.0 * (x0.q_mb.toRotationMatrix() * r_bc * dir_c);
  for (int k = 0; k < 3; ++k) {
    m.p_m[k] = lm(k);
    m.w_c[k] = dir_c(k);
  }
  m.sigma_px = 0.5;
  bsp::Work work;
  trn::filter::Meas2 m0;
  ASSERT_EQ(trn::filter::bearing_measurement(x0, geo, m, 1e-3, 0.05, m0, work), trn::filter::BearingStatus::kOk);
  EXPECT_LT(m0.r.norm(), 1e-12);  // the landmark was placed on the bearing
  for (int j = 0; j < 15; ++j) {
    Vec15 d = Vec15::Zero();
    d(j) = j < 3 ? 1e-2 : 1e-6;
    trn::filter::Meas2 mp;
    trn::filter::Meas2 mm;
    ASSERT_EQ(trn::filter::bearing_measurement(boxplus(x0, d), geo, m, 1e-3, 0.05, mp, work),
              trn::filter::BearingStatus::kOk);
    ASSERT_EQ(trn::filter::bearing_measurement(boxplus(x0, -d), geo, m, 1e-3, 0.05, mm, work),
              trn::filter::BearingStatus::kOk);
    // r = z - h(x), so H = -dr/dx.
    const trn::filter::Vec2 col = -(mp.r - mm.r) / (2.0 * d(j));
    trn::filter::Vec2 h = trn::filter::Vec2::Zero();
    if (j < 3) {
      h = m0.hp.col(j);
    } else if (j >= 6 && j < 9) {
      h = m0.hth.col(j - 6);
    }
    EXPECT_NEAR(col(0), h(0), 1e-8 * (1.0 + std::abs(h(0)))) << "H(0," << j << ")";
    EXPECT_NEAR(col(1), h(1), 1e-8 * (1.0 + std::abs(h(1)))) << "H(1," << j << ")";
  }
}

}  // namespace
