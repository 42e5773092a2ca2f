/**
 * @file reference_test.cpp
 * @brief The fixed-size filter equals a plain dynamic-size (Eigen::MatrixXd) reference of the same
 *        equations, written here with dense F, H, I-KH and G, to 1e-12 over propagation + updates
 *        (a batch linearized at one nominal, its correction injected once).
 */
#include "tests/trn/filter/truth_sim.hpp"
#include "trn/filter/ekf.hpp"
#include "trn/filter/strapdown.hpp"

#include <Eigen/Dense>
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdio>

namespace {

using Eigen::MatrixXd;
using filter_test::Mat3;
using filter_test::Quat;
using filter_test::Vec3;

/** The same model, the textbook way: dense dynamic matrices, explicit Joseph form. */
struct RefFilter {
  Vec3 p, v, bg, ba;
  Quat q;
  MatrixXd cov;
  std::uint32_t accepted = 0;
  std::uint32_t rejected = 0;

  void propagate(const bsp::ImuSample& s, const trn::filter::FilterConfig& cfg) {
    const double dt = cfg.imu_dt_s;
    const Vec3 dth = Vec3(s.dtheta_rad[0], s.dtheta_rad[1], s.dtheta_rad[2]) - bg * dt;
    const Vec3 dvc = Vec3(s.dv_mps[0], s.dv_mps[1], s.dv_mps[2]) - ba * dt;
    const Vec3 u = dvc + 0.5 * dth.cross(dvc);
    const Mat3 r = q.toRotationMatrix();
    const double rr = bsp::frames::kRadiusMars + p.z();
    const double dgdh = 2.0 * bsp::frames::kGmMars / (rr * rr * rr);
    MatrixXd f = MatrixXd::Identity(15, 15);
    f.block(0, 3, 3, 3) = dt * Mat3::Identity();
    f.block(3, 6, 3, 3) = -r * trn::filter::skew(u);
    f.block(3, 12, 3, 3) = -dt * r;
    f(5, 2) = dgdh * dt;
    f.block(0, 6, 3, 3) = 0.5 * dt * f.block(3, 6, 3, 3);
    f.block(0, 12, 3, 3) = 0.5 * dt * f.block(3, 12, 3, 3);
    f(2, 2) = 1.0 + 0.5 * dt * dgdh * dt;
    f.block(6, 6, 3, 3) = trn::filter::quat_exp(dth).toRotationMatrix().transpose();
    f.block(6, 9, 3, 3) = -dt * Mat3::Identity();
    const Vec3 g(0.0, 0.0, -bsp::frames::gravity_mps2(p.z()));
    const Vec3 v_new = v + r * u + g * dt;
    p += 0.5 * dt * (v + v_new);
    v = v_new;
    q = (q * trn::filter::quat_exp(dth)).normalized();
    const trn::filter::ImuSpec& m = cfg.imu;
    MatrixXd qd = MatrixXd::Zero(15, 15);
    for (int i = 0; i < 3; ++i) {
      qd(3 + i, 3 + i) = m.accel_vrw_mps_sqrts * m.accel_vrw_mps_sqrts * dt;
      qd(6 + i, 6 + i) = m.gyro_arw_rad_sqrts * m.gyro_arw_rad_sqrts * dt;
      qd(9 + i, 9 + i) = m.gyro_bias_run_rads * m.gyro_bias_run_rads * (1.0 - std::exp(-2.0 * dt / m.gyro_bias_tau_s));
      qd(12 + i, 12 + i) =
          m.accel_bias_run_mps2 * m.accel_bias_run_mps2 * (1.0 - std::exp(-2.0 * dt / m.accel_bias_tau_s));
    }
    const MatrixXd next = f * cov * f.transpose() + qd;
    cov = 0.5 * (next + next.transpose());
  }

  /**
   * One match of a batch: linearized at the batch's nominal (which has not
   * moved yet), its innovation r - H dx (dx: the batch's correction so far).
   */
  void update(const trn::Match& mt, const bsp::CameraModel& cam, double gate, Eigen::VectorXd& dx) {
    const Mat3 r_mb = q.toRotationMatrix();
    Mat3 r_bc;
    for (int i = 0; i < 9; ++i) {
      r_bc(i / 3, i % 3) = cam.r_bc[i];
    }
    const Vec3 p_b = r_mb.transpose() * (Vec3(mt.p_m[0], mt.p_m[1], mt.p_m[2]) - p);
    const Vec3 p_c = r_bc.transpose() * p_b;
    MatrixXd jpi(2, 3);
    jpi << 1.0 / p_c.z(), 0.0, -p_c.x() / (p_c.z() * p_c.z()), 0.0, 1.0 / p_c.z(), -p_c.y() / (p_c.z() * p_c.z());
    MatrixXd h = MatrixXd::Zero(2, 15);
    h.block(0, 0, 2, 3) = -jpi * r_bc.transpose() * r_mb.transpose();
    h.block(0, 6, 2, 3) = jpi * r_bc.transpose() * trn::filter::skew(p_b);
    Eigen::VectorXd res(2);
    res << mt.w_c[0] / mt.w_c[2] - p_c.x() / p_c.z(), mt.w_c[1] / mt.w_c[2] - p_c.y() / p_c.z();
    res -= h * dx;
    MatrixXd rm = MatrixXd::Zero(2, 2);
    rm(0, 0) = (mt.sigma_px / cam.fx_px) * (mt.sigma_px / cam.fx_px);
    rm(1, 1) = (mt.sigma_px / cam.fy_px) * (mt.sigma_px / cam.fy_px);
    const MatrixXd s = h * cov * h.transpose() + rm;
    const MatrixXd s_inv = s.inverse();
    if (res.dot(s_inv * res) > gate) {
      ++rejected;
      return;
    }
    ++accepted;
    const MatrixXd k = cov * h.transpose() * s_inv;
    const MatrixXd a = MatrixXd::Identity(15, 15) - k * h;
    const MatrixXd next = a * cov * a.transpose() + k * rm * k.transpose();
    cov = 0.5 * (next + next.transpose());
    dx += k * res;
  }

  /** A batch: its matches one by one, then the correction injected and the attitude reset, once. */
  void update_batch(const trn::Match* mt, int n, const bsp::CameraModel& cam, double gate) {
    Eigen::VectorXd dx = Eigen::VectorXd::Zero(15);
    for (int i = 0; i < n; ++i) {
      update(mt[i], cam, gate, dx);
    }
    p += dx.segment(0, 3);
    v += dx.segment(3, 3);
    const Vec3 dth = dx.segment(6, 3);
    q = (q * trn::filter::quat_exp(dth)).normalized();
    bg += dx.segment(9, 3);
    ba += dx.segment(12, 3);
    MatrixXd gm = MatrixXd::Identity(15, 15);
    gm.block(6, 6, 3, 3) -= trn::filter::skew(0.5 * dth);
    const MatrixXd next = gm * cov * gm.transpose();
    cov = 0.5 * (next + next.transpose());
  }
};

trn::filter::Ekf g_ekf;
std::array<trn::Match, 40> g_matches{};

double worst_rel_diff(const RefFilter& ref, const trn::filter::FilterState& s) {
  double worst = 0.0;
  for (int i = 0; i < 15; ++i) {
    for (int j = 0; j < 15; ++j) {
      // Scale by the standard deviations: correlations, not raw magnitudes, are compared.
      const double scale = std::sqrt(ref.cov(i, i) * ref.cov(j, j));
      worst = std::max(worst, std::abs(ref.cov(i, j) - s.p(i, j)) / scale);
    }
  }
  auto rel = [](const Vec3& a, const Vec3& b) { return (a - b).norm() / std::max(1.0, a.norm()); };
  worst = std::max(worst, rel(ref.p, s.x.p_m));
  worst = std::max(worst, rel(ref.v, s.x.v_mps));
  worst = std::max(worst, (ref.q.coeffs() - s.x.q_mb.coeffs()).norm());
  // Biases against their own scale (gyro ~5e-6 rad/s, accel ~2e-3 m/s^2).
  worst = std::max(worst, (ref.bg - s.x.bg_rads).norm() / 1e-6);
  worst = std::max(worst, (ref.ba - s.x.ba_mps2).norm() / 1e-3);
  return worst;
}

TEST(FilterReference, FixedSizeFilterEqualsDynamicReferenceTo1e12) {
  constexpr std::uint64_t kSeed = 31;
  SCOPED_TRACE(testing::Message() << "seed " << kSeed);
  trn::filter::FilterConfig cfg;
  const bsp::CameraModel cam = bsp::make_camera(1024, 1024, 90.0);
  ASSERT_EQ(g_ekf.configure(cfg, cam), trn::filter::FilterStatus::kOk);
  filter_test::TruthSim truth(kSeed, true, cfg.imu);
  bsp::Rng rng(kSeed, bsp::StreamId::kTest, 5);
  // A position known to 4 m: the reference is the one-linearization EKF, which the filter is while its
  // position is not loose (a loose one iterates each match, Ekf::position_loose()).
  ASSERT_EQ(g_ekf.init(filter_test::perturbed_estimate(truth, rng, 4.0, 0.5, 2e-3)), trn::filter::FilterStatus::kOk);
  RefFilter ref{g_ekf.state().x.p_m, g_ekf.state().x.v_mps, g_ekf.state().x.bg_rads, g_ekf.state().x.ba_mps2,
                g_ekf.state().x.q_mb, g_ekf.state().p, 0, 0};
  double worst = 0.0;
  for (int frame = 0; frame < 3; ++frame) {
    for (int k = 0; k < 150; ++k) {
      const bsp::ImuSample s = truth.next_imu();
      ASSERT_EQ(g_ekf.propagate(s), trn::filter::FilterStatus::kOk);
      ref.propagate(s, cfg);
    }
    worst = std::max(worst, worst_rel_diff(ref, g_ekf.state()));
    ASSERT_FALSE(g_ekf.position_loose()) << "frame " << frame;
    truth.make_matches(rng, cam, 40, 0.5, g_matches.data());
    g_matches[7].w_c[0] += 0.1;  // one outlier per frame: both must refuse it
    trn::filter::UpdateReport rep;
    ASSERT_EQ(g_ekf.update(g_matches.data(), 40, rep), trn::filter::FilterStatus::kOk);
    ref.update_batch(g_matches.data(), static_cast<int>(g_matches.size()), cam, cfg.gate_chi2);
    worst = std::max(worst, worst_rel_diff(ref, g_ekf.state()));
  }
  std::printf("fixed vs dynamic reference: worst scaled difference %.3e\n", worst);
  EXPECT_LT(worst, 1e-12);
  EXPECT_EQ(g_ekf.state().c.accepted, ref.accepted);
  EXPECT_EQ(g_ekf.state().c.rejected_gate, ref.rejected);
  EXPECT_EQ(ref.rejected, 3U);
}

}  // namespace
