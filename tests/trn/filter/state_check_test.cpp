/**
 * @file state_check_test.cpp
 * @brief The filter state's plausibility check: a healthy step passes, and each check refuses what
 *        it is for (trn/filter/state_check.hpp).
 */
#include "trn/filter/state_check.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

namespace {

using trn::filter::FilterState;
using trn::filter::StateBefore;
using trn::filter::StateCheck;
using trn::filter::StateEnvelope;

// Static: a FilterState holds its pose history (about 16 KB).
FilterState g_before;
FilterState g_after;

/** A descent at 3 km, 60 m/s down and 20 east, converged to about a metre. */
void healthy(FilterState& s, double t_s) {
  trn::filter::clear_state(s);
  s.initialized = 1;
  s.t_s = t_s;
  s.x.p_m = trn::filter::Vec3(1200.0, -800.0, 3000.0);
  s.x.v_mps = trn::filter::Vec3(20.0, 0.0, -60.0);
  s.x.q_mb = trn::filter::Quat(Eigen::AngleAxisd(0.3, trn::filter::Vec3::UnitZ()));
  s.x.bg_rads = trn::filter::Vec3::Constant(1e-6);
  s.x.ba_mps2 = trn::filter::Vec3::Constant(1e-4);
  s.p.setZero();
  for (int i = 0; i < 3; ++i) {
    s.p(trn::filter::kIdxP + i, trn::filter::kIdxP + i) = 1.0;
    s.p(trn::filter::kIdxV + i, trn::filter::kIdxV + i) = 0.01;
    s.p(trn::filter::kIdxTh + i, trn::filter::kIdxTh + i) = 1e-6;
    s.p(trn::filter::kIdxBg + i, trn::filter::kIdxBg + i) = 1e-12;
    s.p(trn::filter::kIdxBa + i, trn::filter::kIdxBa + i) = 1e-8;
  }
}

/** g_after is g_before 10 ms on, propagated, with a small correction. */
void step_on() {
  healthy(g_before, 10.0);
  healthy(g_after, 10.01);
  g_after.x.p_m = g_before.x.p_m + g_before.x.v_mps * 0.01 + trn::filter::Vec3(0.3, -0.2, 0.1);
  g_after.x.v_mps = g_before.x.v_mps + trn::filter::Vec3(0.0, 0.0, -0.037);
}

StateCheck check() {
  bsp::Work w{};
  const StateBefore b = trn::filter::state_before(g_before, w);
  return trn::filter::check_state(b, g_after, StateEnvelope{}, w).what;
}

// FDIR-FS-01: each check refuses what it is for, and nothing else.
TEST(StateCheck, AHealthyStepPasses) {
  step_on();
  bsp::Work w{};
  const StateBefore b = trn::filter::state_before(g_before, w);
  EXPECT_TRUE(b.valid);
  EXPECT_NEAR(b.sigma_p_m, std::sqrt(3.0), 1e-12);
  EXPECT_EQ(trn::filter::check_state(b, g_after, StateEnvelope{}, w).what, StateCheck::kOk);
  EXPECT_GT(w.flops, 0U) << "the check's work is charged";
}

TEST(StateCheck, ANumberNotFiniteOrANegativeVarianceIsRefused) {
  step_on();
  g_after.x.v_mps.y() = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(check(), StateCheck::kNotFinite);
  step_on();
  g_after.x.bg_rads.x() = std::numeric_limits<double>::infinity();
  EXPECT_EQ(check(), StateCheck::kNotFinite);
  step_on();
  g_after.p(4, 4) = -1e-3;
  EXPECT_EQ(check(), StateCheck::kNotFinite);
}

TEST(StateCheck, AQuaternionOffTheUnitSphereIsRefused) {
  step_on();
  g_after.x.q_mb.coeffs() *= 1.0 + 1e-5;
  EXPECT_EQ(check(), StateCheck::kAttitudeNorm);
  step_on();
  g_after.x.q_mb.coeffs() *= 1.0 + 1e-9;  // round-off: the filter normalises every step
  EXPECT_EQ(check(), StateCheck::kOk);
}

TEST(StateCheck, TheEnvelopeRefusesSpeedRangeAndBiases) {
  // Each from a state before that is just as far out, so only the envelope can refuse it.
  step_on();
  g_before.x.v_mps.z() = -1600.0;
  g_after.x.v_mps.z() = -1600.0;
  g_after.x.p_m = g_before.x.p_m + g_before.x.v_mps * 0.01;
  EXPECT_EQ(check(), StateCheck::kSpeed);
  step_on();
  g_before.x.p_m.x() = 2e6;
  g_after.x.p_m = g_before.x.p_m + g_before.x.v_mps * 0.01;
  EXPECT_EQ(check(), StateCheck::kRange);
  step_on();
  g_before.x.bg_rads.y() = 0.06;
  g_after.x.bg_rads.y() = 0.06;
  EXPECT_EQ(check(), StateCheck::kBias);
  step_on();
  g_before.x.ba_mps2.z() = -2.5;
  g_after.x.ba_mps2.z() = -2.5;
  EXPECT_EQ(check(), StateCheck::kBias);
}

TEST(StateCheck, AStepBeyondItsSigmasIsRefused) {
  // 8 sigma of the state before plus the floor and the propagation's allowance: sqrt(3) m x 8 + 1 m.
  step_on();
  g_after.x.p_m.x() += 16.0;
  EXPECT_EQ(check(), StateCheck::kStepPosition);
  step_on();
  g_after.x.p_m.x() += 12.0;
  EXPECT_EQ(check(), StateCheck::kOk) << "within 8 sigma: a gated correction may do this";
  step_on();
  g_after.x.v_mps.x() += 4.0;
  EXPECT_EQ(check(), StateCheck::kStepVelocity);
  step_on();
  g_after.x.q_mb = g_before.x.q_mb * trn::filter::Quat(Eigen::AngleAxisd(0.1, trn::filter::Vec3::UnitX()));
  EXPECT_EQ(check(), StateCheck::kStepAttitude);
  step_on();
  g_after.x.bg_rads.z() += 1e-4;
  EXPECT_EQ(check(), StateCheck::kStepBias);
  step_on();
  g_after.x.ba_mps2.x() += 0.05;
  EXPECT_EQ(check(), StateCheck::kStepBias);
}

TEST(StateCheck, ACoarseFixALongStepOrNoStateBeforeIsNotJudgedAsAStep) {
  step_on();
  g_after.x.p_m.x() += 2500.0;  // the coarse stage corrects kilometres
  g_after.c.coarse_accepted = g_before.c.coarse_accepted + 1U;
  EXPECT_EQ(check(), StateCheck::kOk);
  step_on();
  g_after.t_s = g_before.t_s + 2.0;  // a catch-up longer than the envelope judges
  g_after.x.p_m.x() += 500.0;
  EXPECT_EQ(check(), StateCheck::kOk);
  step_on();
  g_before.initialized = 0;
  g_after.x.p_m.x() += 500.0;
  EXPECT_EQ(check(), StateCheck::kOk);
  g_after.x.v_mps.x() = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(check(), StateCheck::kNotFinite) << "the state alone is still judged";
}

TEST(StateCheck, EveryCheckHasAName) {
  for (std::uint32_t c = 0; c <= static_cast<std::uint32_t>(StateCheck::kStepBias); ++c) {
    EXPECT_STRNE(trn::filter::state_check_name(static_cast<StateCheck>(c)), "?") << c;
  }
}

}  // namespace
