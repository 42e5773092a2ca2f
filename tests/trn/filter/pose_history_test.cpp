/**
 * @file pose_history_test.cpp
 * @brief The pose history: a ring of the last 256 propagations, whose past poses (between
 *        samples too) follow the truth, and which moves with a correction of the present.
 */
#include "tests/trn/filter/truth_sim.hpp"
#include "trn/filter/ekf.hpp"
#include "trn/filter/pose_history.hpp"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdio>

namespace {

using filter_test::Quat;
using filter_test::TruthSim;
using filter_test::Vec3;
using trn::filter::HistoryStatus;
using trn::filter::PastPose;

trn::filter::Ekf g_ekf;
trn::filter::FilterState g_state;
std::array<Quat, 400> g_nom_q;
std::array<Vec3, 400> g_nom_p;

/** A filter started exactly on a perfect-IMU truth and run for @p n samples; its pose kept per sample. */
void run_exact(TruthSim& truth, int n) {
  ASSERT_EQ(g_ekf.configure(trn::filter::FilterConfig{}, bsp::CameraModel{}), trn::filter::FilterStatus::kOk);
  trn::filter::InitialEstimate e;
  e.t_s = truth.t();
  e.x.p_m = truth.p();
  e.x.v_mps = truth.v();
  e.x.q_mb = truth.q();
  ASSERT_EQ(g_ekf.init(e), trn::filter::FilterStatus::kOk);
  g_nom_q[0] = g_ekf.state().x.q_mb;
  g_nom_p[0] = g_ekf.state().x.p_m;
  for (int k = 1; k <= n; ++k) {
    ASSERT_EQ(g_ekf.propagate(truth.next_imu()), trn::filter::FilterStatus::kOk);
    g_nom_q[static_cast<std::size_t>(k)] = g_ekf.state().x.q_mb;
    g_nom_p[static_cast<std::size_t>(k)] = g_ekf.state().x.p_m;
  }
}

TEST(PoseHistory, RingKeepsTheLast256PropagationsInTimeOrder) {
  TruthSim truth(1, false, trn::filter::FilterConfig{}.imu);
  run_exact(truth, 300);
  const trn::filter::PoseHistory& h = g_ekf.state().hist;
  ASSERT_EQ(h.count, trn::filter::kHistoryLen);
  EXPECT_NEAR(trn::filter::history_entry(h, 0).t_s, 3.00 - 2.55, 1e-9);
  EXPECT_EQ(trn::filter::history_entry(h, h.count - 1U).t_s, g_ekf.state().t_s);
  EXPECT_TRUE(trn::filter::history_valid(h, g_ekf.state().t_s, true));
  bsp::Work w;
  PastPose p;
  EXPECT_EQ(trn::filter::history_pose(h, 3.0 - 2.551, g_ekf.state().x, 0.05, p, w), HistoryStatus::kTooOld);
  EXPECT_EQ(trn::filter::history_pose(h, 3.0 - 2.55, g_ekf.state().x, 0.05, p, w), HistoryStatus::kOk);
  EXPECT_EQ(trn::filter::history_pose(h, 3.0, g_ekf.state().x, 0.05, p, w), HistoryStatus::kCurrent);
  EXPECT_EQ(trn::filter::history_pose(h, 3.001, g_ekf.state().x, 0.05, p, w), HistoryStatus::kFuture);
}

TEST(PoseHistory, PastPosesFollowTheTruthOnAndBetweenSamples) {
  TruthSim truth(1, false, trn::filter::FilterConfig{}.imu);
  run_exact(truth, 300);
  const filter_test::Motion motion{};  // the truth's analytic translation
  double worst_p = 0.0;
  double worst_nom_p = 0.0;
  double worst_nom_th = 0.0;
  for (int i = 0; i < 250; ++i) {
    const double t = 0.5 + 0.01 * i + 0.0037 * (i % 3);  // on samples and between them
    PastPose pp;
    bsp::Work w;
    ASSERT_EQ(trn::filter::history_pose(g_ekf.state().hist, t, g_ekf.state().x, 0.05, pp, w), HistoryStatus::kOk)
        << t;
    EXPECT_NEAR(pp.lag_s, 3.0 - t, 1e-9);
    worst_p = std::max(worst_p, (pp.p_m - motion.pos(t)).norm());
    if (i % 3 == 0) {  // on a sample: the nominal the filter had then is known
      const auto k = static_cast<std::size_t>(std::lround(t * 100.0));
      worst_nom_p = std::max(worst_nom_p, (pp.p_m - g_nom_p[k]).norm());
      worst_nom_th = std::max(worst_nom_th, trn::filter::quat_log(g_nom_q[k].conjugate() * pp.q_mb).norm());
    }
  }
  std::printf("past poses over 2.5 s: vs truth %.2e m; vs the nominal then %.2e m, %.2e rad\n", worst_p,
              worst_nom_p, worst_nom_th);
  // The strapdown's own error after 3 s (~1 mm) plus interpolation (a h^2 / 8 ~ 5e-5 m).
  EXPECT_LT(worst_p, 5e-3);
  // Without corrections the past pose is the nominal of that time, to rounding.
  EXPECT_LT(worst_nom_p, 1e-9);
  EXPECT_LT(worst_nom_th, 1e-12);
}

TEST(PoseHistory, ACorrectionOfThePresentMovesThePastByTheBackPropagation) {
  TruthSim truth(2, false, trn::filter::FilterConfig{}.imu);
  run_exact(truth, 150);
  bsp::Work w;
  PastPose before;
  ASSERT_EQ(trn::filter::history_pose(g_ekf.state().hist, 0.8, g_ekf.state().x, 0.05, before, w), HistoryStatus::kOk);
  // Correct the present by dp, dv, dtheta (as an update would) and ask again.
  g_state = g_ekf.state();
  const Vec3 dp(3.0, -2.0, 1.0);
  const Vec3 dv(0.2, 0.1, -0.3);
  const Vec3 dth(1e-3, -2e-3, 5e-4);
  g_state.x.p_m += dp;
  g_state.x.v_mps += dv;
  g_state.x.q_mb = (g_state.x.q_mb * trn::filter::quat_exp(dth)).normalized();
  ASSERT_EQ(g_ekf.restore(g_state), trn::filter::FilterStatus::kOk);
  PastPose after;
  ASSERT_EQ(trn::filter::history_pose(g_ekf.state().hist, 0.8, g_ekf.state().x, 0.05, after, w), HistoryStatus::kOk);
  EXPECT_NEAR(after.lag_s, 0.7, 1e-9);
  EXPECT_LT((after.p_m - (before.p_m + dp - after.lag_s * dv)).norm(), 1e-9);
  // The attitude error is the same rotation in the map frame then and now.
  const Vec3 phi_now = g_ekf.state().x.q_mb.toRotationMatrix() * dth;
  const Vec3 phi_then = trn::filter::quat_log(after.q_mb * before.q_mb.conjugate());
  EXPECT_LT((phi_then - phi_now).norm(), 1e-8);
}

}  // namespace
