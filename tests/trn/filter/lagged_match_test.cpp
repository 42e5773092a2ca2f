/**
 * @file lagged_match_test.cpp
 * @brief Matches measured at the image time and applied 0.3 to 0.9 s later: the lagged Jacobian
 *        matches finite differences, the filter converges and stays consistent (NEES over 20
 *        seeded runs), applying the same matches as if measured now is clearly worse, stale and
 *        future matches are refused without touching the state, and a 3 km initial error is
 *        removed by a coarse match followed by fine ones.
 */
#include "tests/trn/filter/truth_sim.hpp"
#include "trn/filter/ekf.hpp"
#include "trn/filter/state_block.hpp"

#include <gtest/gtest.h>

#include <array>
#include <bit>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <numbers>

namespace {

using filter_test::TruthSim;
using filter_test::Vec3;
using trn::filter::Ekf;
using trn::filter::FilterStatus;
using trn::filter::MatchCheck;
using trn::filter::UpdateReport;

Ekf g_ekf;
trn::filter::FilterState g_s0;
trn::filter::FilterState g_s1;
std::array<trn::Match, trn::kMaxMatchesPerFrame> g_matches{};

constexpr int kRuns = 20;
/** Seeds kSeedBase .. kSeedBase+19; TRN_FILTER_SEED_BASE reruns the test on another set. */
const std::uint64_t kSeedBase =
    std::getenv("TRN_FILTER_SEED_BASE") != nullptr ? std::strtoull(std::getenv("TRN_FILTER_SEED_BASE"), nullptr, 10)
                                                   : 2000U;
constexpr int kSeconds = 30;
constexpr int kMatchesPerFrame = 20;
/** Matches applied per propagation, as the 100 Hz task spreads a batch. */
constexpr std::uint32_t kPerPeriod = 15;
constexpr double kPixelSigma = 0.5;

/** How the batch is handed over: at its image time (the design), or claiming to be measured now. */
enum class Mode { kLagged, kAsIfNow };

struct RunResult {
  std::array<filter_test::Nees3, kSeconds> nees{};
  double final_err_m = 0.0;
  std::uint32_t accepted = 0;
  std::uint32_t rejected_gate = 0;
};

/** Applies the next chunk of the pending frame (at most kPerPeriod); true when the frame is done. */
bool apply_chunk(Mode mode, int& next, UpdateReport& total) {
  const auto n = static_cast<std::uint32_t>(std::min<int>(static_cast<int>(kPerPeriod), kMatchesPerFrame - next));
  trn::Match* chunk = g_matches.data() + next;
  if (mode == Mode::kAsIfNow) {
    for (std::uint32_t i = 0; i < n; ++i) {
      chunk[i].t_s = g_ekf.state().t_s;
    }
  }
  UpdateReport rep;
  EXPECT_EQ(g_ekf.update(chunk, n, rep), FilterStatus::kOk);
  EXPECT_EQ(rep.rejected_stale, 0U);
  EXPECT_EQ(rep.rejected_invalid, 0U);
  total.accepted += rep.accepted;
  total.rejected_gate += rep.rejected_gate;
  next += static_cast<int>(n);
  return next >= kMatchesPerFrame;
}

/**
 * One seeded run: an image at the end of every second; its batch is applied,
 * kPerPeriod matches per propagation, from a lag of 0.30..0.90 s on. NEES is
 * taken when a frame's batch is done (before the next image).
 */
void run_once(std::uint64_t seed, Mode mode, RunResult& out) {
  SCOPED_TRACE(testing::Message() << "seed " << seed << " (base " << kSeedBase << ")");
  trn::filter::FilterConfig cfg;
  const bsp::CameraModel cam{};
  ASSERT_EQ(g_ekf.configure(cfg, cam), FilterStatus::kOk);
  TruthSim truth(seed, true, cfg.imu);
  bsp::Rng rng(seed, bsp::StreamId::kTest, 2);
  bsp::Rng lag_rng(seed, bsp::StreamId::kTest, 12);
  ASSERT_EQ(g_ekf.init(filter_test::perturbed_estimate(truth, rng, 50.0, 0.5, 2e-3)), FilterStatus::kOk);
  int step = 0;
  int apply_at = -1;  // step from which the pending frame is applied; -1: none pending
  int next = 0;
  int frame = 0;
  UpdateReport total;
  for (int sec = 0; sec <= kSeconds; ++sec) {
    for (int k = 0; k < 100; ++k) {
      ASSERT_EQ(g_ekf.propagate(truth.next_imu()), FilterStatus::kOk);
      ++step;
      if (apply_at >= 0 && step >= apply_at && apply_chunk(mode, next, total)) {
        apply_at = -1;
        out.nees[static_cast<std::size_t>(frame)] = filter_test::nees(truth, g_ekf.state());
        ++frame;
      }
    }
    ASSERT_LT(apply_at, 0) << "the previous frame is applied before the next image";
    if (sec < kSeconds) {
      truth.make_matches(rng, cam, kMatchesPerFrame, kPixelSigma, g_matches.data());
      apply_at = step + 30 + static_cast<int>(lag_rng.below(61));
      next = 0;
    }
  }
  ASSERT_EQ(frame, kSeconds);
  out.final_err_m = (truth.p() - g_ekf.state().x.p_m).norm();
  out.accepted = total.accepted;
  out.rejected_gate = total.rejected_gate;
}

struct Summary {
  double mean[3] = {0.0, 0.0, 0.0};
  int inside[3] = {0, 0, 0};
  double worst_err_m = 0.0;
  double mean_err_m = 0.0;
  std::uint32_t accepted = 0;
  std::uint32_t rejected_gate = 0;
};

Summary run_all(Mode mode, double lo, double hi) {
  std::array<filter_test::Nees3, kSeconds> sum{};
  Summary s;
  for (int run = 0; run < kRuns; ++run) {
    RunResult r;
    run_once(kSeedBase + static_cast<std::uint64_t>(run), mode, r);
    if (testing::Test::HasFatalFailure()) {
      return s;
    }
    for (int f = 0; f < kSeconds; ++f) {
      sum[static_cast<std::size_t>(f)].p += r.nees[static_cast<std::size_t>(f)].p;
      sum[static_cast<std::size_t>(f)].v += r.nees[static_cast<std::size_t>(f)].v;
      sum[static_cast<std::size_t>(f)].th += r.nees[static_cast<std::size_t>(f)].th;
    }
    s.worst_err_m = std::max(s.worst_err_m, r.final_err_m);
    s.mean_err_m += r.final_err_m / kRuns;
    s.accepted += r.accepted;
    s.rejected_gate += r.rejected_gate;
  }
  for (const filter_test::Nees3& n : sum) {
    const double a[3] = {n.p / kRuns, n.v / kRuns, n.th / kRuns};
    for (int b = 0; b < 3; ++b) {
      s.inside[b] += (a[b] > lo && a[b] < hi) ? 1 : 0;
      s.mean[b] += a[b] / kSeconds;
    }
  }
  return s;
}

TEST(FilterLagged, MatchesAppliedUpTo09SecondsLateConvergeAndStayConsistent) {
  const double lo = filter_test::chi2_quantile(0.025, 3.0 * kRuns) / kRuns;
  const double hi = filter_test::chi2_quantile(0.975, 3.0 * kRuns) / kRuns;
  const Summary s = run_all(Mode::kLagged, lo, hi);
  ASSERT_FALSE(HasFatalFailure());
  std::printf("lagged 0.3-0.9 s, seeds %llu+: NEES mean p %.2f v %.2f th %.2f; inside [%.3f, %.3f]: %d %d %d of %d;"
              " final |dp| mean %.2f worst %.2f m; accepted %u, gated %u\n",
              static_cast<unsigned long long>(kSeedBase), s.mean[0], s.mean[1], s.mean[2], lo, hi, s.inside[0],
              s.inside[1], s.inside[2], kSeconds, s.mean_err_m, s.worst_err_m, s.accepted, s.rejected_gate);
  // The same criterion as the consistency test of matches applied at once.
  for (int b = 0; b < 3; ++b) {
    EXPECT_GE(s.inside[b], kSeconds * 3 / 4) << "block " << b;
    EXPECT_GT(s.mean[b], lo) << "block " << b;
    EXPECT_LT(s.mean[b], hi) << "block " << b;
  }
  EXPECT_LT(s.worst_err_m, 10.0);
  EXPECT_GE(s.accepted, static_cast<std::uint32_t>(kRuns * kSeconds * kMatchesPerFrame * 99 / 100));
}

TEST(FilterLagged, TheSameMatchesAppliedAsIfMeasuredNowAreClearlyWorse) {
  const double lo = filter_test::chi2_quantile(0.025, 3.0 * kRuns) / kRuns;
  const double hi = filter_test::chi2_quantile(0.975, 3.0 * kRuns) / kRuns;
  const Summary lagged = run_all(Mode::kLagged, lo, hi);
  const Summary now = run_all(Mode::kAsIfNow, lo, hi);
  ASSERT_FALSE(HasFatalFailure());
  std::printf("as if measured now: NEES mean p %.1f v %.1f th %.1f; final |dp| mean %.2f m (lagged %.2f m);"
              " gated %u of %u (lagged %u)\n",
              now.mean[0], now.mean[1], now.mean[2], now.mean_err_m, lagged.mean_err_m, now.rejected_gate,
              now.accepted + now.rejected_gate, lagged.rejected_gate);
  // The vehicle moves 20 to 65 m between image and update: a bearing taken
  // for one from the current pose is off by several sigma.
  EXPECT_GT(now.mean_err_m, 5.0 * lagged.mean_err_m);
  EXPECT_GT(now.mean[0], 10.0 * hi) << "position NEES far outside the bound";
  EXPECT_GT(now.rejected_gate, 10U * (lagged.rejected_gate + 1U));
}

/** A filter started from the truth's current time, then @p samples propagations. */
void start_filter(TruthSim& truth, bsp::Rng& rng, int samples) {
  ASSERT_EQ(g_ekf.configure(trn::filter::FilterConfig{}, bsp::CameraModel{}), FilterStatus::kOk);
  ASSERT_EQ(g_ekf.init(filter_test::perturbed_estimate(truth, rng, 20.0, 0.2, 1e-3)), FilterStatus::kOk);
  for (int k = 0; k < samples; ++k) {
    ASSERT_EQ(g_ekf.propagate(truth.next_imu()), FilterStatus::kOk);
  }
}

/** True if the filter's state, counters aside, is what was written into @p before (with counters @p c). */
bool state_unchanged(const trn::filter::StateBlock& before, const trn::filter::FilterCounters& c) {
  static trn::filter::StateBlock now;
  static trn::filter::FilterState s;
  s = g_ekf.state();
  s.c = c;  // counters may move; everything else must not
  EXPECT_EQ(trn::filter::write_state_block(s, now), trn::filter::BlockError::kOk);
  return now == before;
}

TEST(FilterLagged, StaleFutureAndGapMatchesAreRefusedCountedAndNotApplied) {
  constexpr std::uint64_t kSeed = 91;
  SCOPED_TRACE(testing::Message() << "seed " << kSeed);
  TruthSim truth(kSeed, true, trn::filter::FilterConfig{}.imu);
  bsp::Rng rng(kSeed, bsp::StreamId::kTest, 14);
  for (int k = 0; k < 40; ++k) {
    (void)truth.next_imu();
  }
  truth.make_matches(rng, bsp::CameraModel{}, 4, kPixelSigma, g_matches.data());  // image at t = 0.40 s
  const double t_img = truth.t();
  (void)truth.next_imu();
  ASSERT_NO_FATAL_FAILURE(start_filter(truth, rng, 0));
  // A filter started after the image time has no history of it: refused.
  UpdateReport rep;
  ASSERT_EQ(g_ekf.update(g_matches.data(), 1, rep), FilterStatus::kOk);
  EXPECT_EQ(rep.rejected_stale, 1U);
  for (int k = 0; k < 300; ++k) {
    ASSERT_EQ(g_ekf.propagate(truth.next_imu()), FilterStatus::kOk);
  }
  // 3 s later: the image is 3.0 s old, beyond the 2.56 s history.
  static trn::filter::StateBlock before;
  const trn::filter::FilterCounters c = g_ekf.state().c;
  ASSERT_EQ(trn::filter::write_state_block(g_ekf.state(), before), trn::filter::BlockError::kOk);
  EXPECT_LT(t_img, g_ekf.state().t_s - 0.01 * trn::filter::kHistoryLen);
  ASSERT_EQ(g_ekf.update(g_matches.data(), 4, rep), FilterStatus::kOk);
  EXPECT_EQ(rep.rejected_stale, 4U);
  EXPECT_EQ(rep.accepted + rep.rejected_gate + rep.rejected_invalid, 0U);
  EXPECT_EQ(g_ekf.state().c.rejected_stale, c.rejected_stale + 4U);
  EXPECT_EQ(g_ekf.state().c.last_rejected, 4U);
  EXPECT_TRUE(state_unchanged(before, c)) << "a refused match changes nothing but counters";

  // Ahead of the state (a clock error upstream, or a filter that fell behind): refused.
  truth.make_matches(rng, bsp::CameraModel{}, 4, kPixelSigma, g_matches.data());
  g_matches[0].t_s = g_ekf.state().t_s + 0.02;
  g_matches[1].t_s = g_ekf.state().t_s + 5e-6;
  g_matches[2].t_s = std::numeric_limits<double>::quiet_NaN();  // not a time: invalid
  ASSERT_EQ(g_ekf.update(g_matches.data(), 3, rep), FilterStatus::kOk);
  EXPECT_EQ(rep.rejected_stale, 2U);
  EXPECT_EQ(rep.rejected_invalid, 1U);
  EXPECT_TRUE(state_unchanged(before, c));
  // Within a microsecond of the state's time: the state itself, applied.
  g_matches[3].t_s = g_ekf.state().t_s + 5e-7;
  ASSERT_EQ(g_ekf.update(&g_matches[3], 1, rep), FilterStatus::kOk);
  EXPECT_EQ(rep.accepted, 1U);

  // IMU samples lost for 0.2 s: the last kMaxBridgedSamples (0.1 s) are bridged, the 0.1 s before
  // them is not; an image there cannot be placed, one beside the gap can.
  static_assert(trn::filter::kMaxBridgedSamples == 10U);
  const double t_before_gap = g_ekf.state().t_s;
  truth.make_matches(rng, bsp::CameraModel{}, 2, kPixelSigma, g_matches.data());  // at t_before_gap
  for (int k = 0; k < 20; ++k) {
    bsp::ImuSample s = truth.next_imu();
    s.status = 1;  // device error: not integrated
    EXPECT_EQ(g_ekf.propagate(s), FilterStatus::kImuInvalid);
  }
  trn::Match in_gap = g_matches[1];
  in_gap.t_s = t_before_gap + 0.05;
  for (int k = 0; k < 30; ++k) {
    ASSERT_EQ(g_ekf.propagate(truth.next_imu()), FilterStatus::kOk);
  }
  ASSERT_EQ(g_ekf.update(&in_gap, 1, rep), FilterStatus::kOk);
  EXPECT_EQ(rep.rejected_stale, 1U) << "between entries 0.11 s apart";
  ASSERT_EQ(g_ekf.update(g_matches.data(), 1, rep), FilterStatus::kOk);
  EXPECT_EQ(rep.accepted, 1U) << "at an entry before the gap";

  // Time going backwards restarts the history: nothing before the restart is placed.
  bsp::ImuSample back = truth.next_imu();
  back.t_s = g_ekf.state().t_s - 1.0;
  ASSERT_EQ(g_ekf.propagate(back), FilterStatus::kOk);
  EXPECT_EQ(g_ekf.state().hist.count, 1U);
  g_matches[1].t_s = back.t_s - 0.2;
  ASSERT_EQ(g_ekf.update(&g_matches[1], 1, rep), FilterStatus::kOk);
  EXPECT_EQ(rep.rejected_stale, 1U);
}

/** x (+) d on the current nominal: p, v additive, q <- q Exp(dth). */
void perturb(trn::filter::FilterState& s, int j, double eps) {
  const int blk = j / 3;
  const int axis = j % 3;
  if (blk == 0) {
    s.x.p_m(axis) += eps;
  } else if (blk == 1) {
    s.x.v_mps(axis) += eps;
  } else if (blk == 2) {
    Vec3 d = Vec3::Zero();
    d(axis) = eps;
    s.x.q_mb = (s.x.q_mb * trn::filter::quat_exp(d)).normalized();
  } else if (blk == 3) {
    s.x.bg_rads(axis) += eps;
  } else {
    s.x.ba_mps2(axis) += eps;
  }
}

TEST(FilterLagged, LaggedJacobianMatchesFiniteDifferencesOfTheBackPropagatedPrediction) {
  constexpr std::uint64_t kSeed = 93;
  SCOPED_TRACE(testing::Message() << "seed " << kSeed);
  TruthSim truth(kSeed, true, trn::filter::FilterConfig{}.imu);
  bsp::Rng rng(kSeed, bsp::StreamId::kTest, 15);
  ASSERT_NO_FATAL_FAILURE(start_filter(truth, rng, 100));
  truth.make_matches(rng, bsp::CameraModel{}, 3, kPixelSigma, g_matches.data());
  for (int k = 0; k < 70; ++k) {
    ASSERT_EQ(g_ekf.propagate(truth.next_imu()), FilterStatus::kOk);
  }
  // Corrections after the image must move the past pose with the present one.
  UpdateReport rep;
  ASSERT_EQ(g_ekf.update(&g_matches[2], 1, rep), FilterStatus::kOk);
  ASSERT_EQ(rep.accepted, 1U);
  for (int k = 0; k < 3; ++k) {
    ASSERT_EQ(g_ekf.propagate(truth.next_imu()), FilterStatus::kOk);
  }
  g_s0 = g_ekf.state();
  for (int mi = 0; mi < 2; ++mi) {
    trn::filter::Meas2 m0;
    ASSERT_EQ(g_ekf.measure(g_matches[static_cast<std::size_t>(mi)], m0), MatchCheck::kOk);
    EXPECT_NEAR(m0.lag_s, 0.73, 1e-9);
    for (int j = 0; j < 15; ++j) {
      const double eps = j < 3 ? 1e-2 : (j < 6 ? 1e-4 : 1e-6);
      trn::filter::Meas2 mp;
      trn::filter::Meas2 mm;
      g_s1 = g_s0;
      perturb(g_s1, j, eps);
      ASSERT_EQ(g_ekf.restore(g_s1), FilterStatus::kOk);
      ASSERT_EQ(g_ekf.measure(g_matches[static_cast<std::size_t>(mi)], mp), MatchCheck::kOk);
      g_s1 = g_s0;
      perturb(g_s1, j, -eps);
      ASSERT_EQ(g_ekf.restore(g_s1), FilterStatus::kOk);
      ASSERT_EQ(g_ekf.measure(g_matches[static_cast<std::size_t>(mi)], mm), MatchCheck::kOk);
      const trn::filter::Vec2 col = -(mp.r - mm.r) / (2.0 * eps);  // r = z - h(x): H = -dr/dx
      trn::filter::Vec2 h = trn::filter::Vec2::Zero();
      if (j < 3) {
        h = m0.hp.col(j);
      } else if (j < 6) {
        h = -m0.lag_s * m0.hp.col(j - 3);
      } else if (j < 9) {
        h = m0.hth.col(j - 6);
      }
      EXPECT_NEAR(col(0), h(0), 1e-7 * (1.0 + std::abs(h(0)))) << "match " << mi << " H(0," << j << ")";
      EXPECT_NEAR(col(1), h(1), 1e-7 * (1.0 + std::abs(h(1)))) << "match " << mi << " H(1," << j << ")";
    }
    ASSERT_EQ(g_ekf.restore(g_s0), FilterStatus::kOk);
  }
}

/** A coarse-stage match now: the image centre and its ground point at z = 0 (camera = body axes here). */
trn::Match centre_coarse_match(const TruthSim& truth, const bsp::CameraModel& cam, double sigma_px) {
  trn::Match coarse{};
  const Vec3 axis = truth.q().toRotationMatrix() * Vec3::UnitZ();
  const Vec3 ground = truth.p() + (-truth.p().z() / axis.z()) * axis;
  for (int k = 0; k < 3; ++k) {
    coarse.w_c[k] = k == 2 ? 1.0 : 0.0;
    coarse.p_m[k] = ground(k);
  }
  coarse.u_px = cam.cx_px;
  coarse.v_px = cam.cy_px;
  coarse.sigma_px = sigma_px;
  coarse.landmark = trn::kCoarseLandmark;
  coarse.t_s = truth.t();
  return coarse;
}

TEST(FilterLagged, CoarseMatchRemovesAThreeKilometreErrorAndFineMatchesConverge) {
  constexpr std::uint64_t kSeed = 95;
  SCOPED_TRACE(testing::Message() << "seed " << kSeed);
  trn::filter::FilterConfig cfg;
  const bsp::CameraModel cam{};
  ASSERT_EQ(g_ekf.configure(cfg, cam), FilterStatus::kOk);
  TruthSim truth(kSeed, true, cfg.imu);
  bsp::Rng rng(kSeed, bsp::StreamId::kTest, 16);
  // 3 km horizontal error, and a covariance that says so.
  trn::filter::InitialEstimate est = filter_test::perturbed_estimate(truth, rng, 1.0, 0.5, 2e-3);
  est.x.p_m = truth.p() + Vec3(2400.0, -1800.0, 150.0);
  est.sigma_p_m = Vec3(3000.0, 3000.0, 200.0);
  ASSERT_EQ(g_ekf.init(est), FilterStatus::kOk);
  for (int k = 0; k < 50; ++k) {
    ASSERT_EQ(g_ekf.propagate(truth.next_imu()), FilterStatus::kOk);
  }
  // Coarse stage: the image centre found in the map, its ground point, a sigma of 16 px (~130 m).
  const trn::Match coarse = centre_coarse_match(truth, cam, 16.0);
  for (int k = 0; k < 50; ++k) {  // the coarse result arrives 0.5 s after the image
    ASSERT_EQ(g_ekf.propagate(truth.next_imu()), FilterStatus::kOk);
  }
  // The gate weighs the residual against the covariance: 3 km predicted, 3 km seen.
  trn::filter::Meas2 m;
  ASSERT_EQ(g_ekf.measure(coarse, m), MatchCheck::kOk);
  const trn::filter::Mat15& p = g_ekf.state().p;
  trn::filter::Mat2x15 h = trn::filter::Mat2x15::Zero();
  h.middleCols<3>(trn::filter::kIdxP) = m.hp;
  h.middleCols<3>(trn::filter::kIdxV) = -m.lag_s * m.hp;
  h.middleCols<3>(trn::filter::kIdxTh) = m.hth;
  trn::filter::Mat2 s = h * p * h.transpose();
  s(0, 0) += m.r_var(0);
  s(1, 1) += m.r_var(1);
  const double d2 = m.r.dot(s.inverse() * m.r);
  std::printf("coarse match: residual %.3f %.3f (normalized), d2 %.2f (gate %.2f)\n", m.r(0), m.r(1), d2,
              cfg.gate_chi2);
  EXPECT_GT(m.r.norm(), 0.5) << "a 3 km error seen from 4.2 km";
  EXPECT_LT(d2, cfg.gate_chi2);
  UpdateReport rep;
  ASSERT_EQ(g_ekf.update(&coarse, 1, rep), FilterStatus::kOk);
  EXPECT_EQ(rep.accepted, 1U);
  EXPECT_EQ(rep.coarse_accepted, 1U);
  EXPECT_EQ(g_ekf.state().c.coarse_accepted, 1U);
  const Vec3 after_coarse = truth.p() - g_ekf.state().x.p_m;
  std::printf("after the coarse match: horizontal error %.1f m (sigma %.1f, %.1f m)\n", after_coarse.head<2>().norm(),
              std::sqrt(g_ekf.state().p(0, 0)), std::sqrt(g_ekf.state().p(1, 1)));
  EXPECT_LT(after_coarse.head<2>().norm(), 400.0);
  // Fine stage: 1 Hz frames of 20 bearings at 0.5 px, applied 0.5 s late.
  for (int frame = 0; frame < 10; ++frame) {
    truth.make_matches(rng, cam, kMatchesPerFrame, kPixelSigma, g_matches.data());
    for (int k = 0; k < 50; ++k) {
      ASSERT_EQ(g_ekf.propagate(truth.next_imu()), FilterStatus::kOk);
    }
    ASSERT_EQ(g_ekf.update(g_matches.data(), kMatchesPerFrame, rep), FilterStatus::kOk);
    EXPECT_GE(rep.accepted, static_cast<std::uint32_t>(kMatchesPerFrame - 1)) << "frame " << frame;
    for (int k = 0; k < 50; ++k) {
      ASSERT_EQ(g_ekf.propagate(truth.next_imu()), FilterStatus::kOk);
    }
  }
  const Vec3 err = truth.p() - g_ekf.state().x.p_m;
  std::printf("after 10 fine frames: error %.2f m, 3-sigma %.2f m\n", err.norm(),
              3.0 * std::sqrt(g_ekf.state().p.block<3, 3>(0, 0).trace()));
  EXPECT_LT(err.norm(), 5.0);
  EXPECT_LT(filter_test::nees(truth, g_ekf.state()).p, 16.27) << "inside the 99.9 % bound of 3 dof";
}

/**
 * The coarse stage's bearing as trn_mission's default scenario meets it: a prior
 * 3 km off horizontally (sigma 2 km), 150 m too high (sigma 100 m), attitude
 * sigma 0.5 deg per axis, the image 0.89 s old. The state after it stays inside
 * its covariance. (This nadir scene does not show the attitude error a single
 * linearization left on the mission's seed 11; the mission test
 * ACoarseFixWithAnAltitudeErrorConvergesInItsOwnFrame flies that case.)
 */
TEST(FilterLagged, ACoarseMatchFromKilometresOffKeepsTheAttitudeAndItsCovarianceTrue) {
  constexpr std::uint64_t kSeed = 96;
  trn::filter::FilterConfig cfg;
  const bsp::CameraModel cam{};
  ASSERT_EQ(g_ekf.configure(cfg, cam), FilterStatus::kOk);
  TruthSim truth(kSeed, true, cfg.imu);
  bsp::Rng rng(kSeed, bsp::StreamId::kTest, 18);
  trn::filter::InitialEstimate est = filter_test::perturbed_estimate(truth, rng, 1.0, 2.0, 0.5 * std::numbers::pi / 180.0);
  est.x.p_m = truth.p() + Vec3(2400.0, -1800.0, 150.0);
  est.sigma_p_m = Vec3(2000.0, 2000.0, 100.0);
  ASSERT_EQ(g_ekf.init(est), FilterStatus::kOk);
  for (int k = 0; k < 20; ++k) {
    ASSERT_EQ(g_ekf.propagate(truth.next_imu()), FilterStatus::kOk);
  }
  const trn::Match coarse = centre_coarse_match(truth, cam, 6.0);
  for (int k = 0; k < 89; ++k) {
    ASSERT_EQ(g_ekf.propagate(truth.next_imu()), FilterStatus::kOk);
  }
  const filter_test::Nees3 before = filter_test::nees(truth, g_ekf.state());
  UpdateReport rep;
  ASSERT_EQ(g_ekf.update(&coarse, 1, rep), FilterStatus::kOk);
  ASSERT_EQ(rep.coarse_accepted, 1U);
  const Vec3 err = truth.p() - g_ekf.state().x.p_m;
  const filter_test::Nees3 after = filter_test::nees(truth, g_ekf.state());
  std::printf("coarse match from 3 km: error %.1f %.1f %.1f m, sigma %.1f %.1f %.1f m; NEES p %.2f -> %.2f, th %.2f -> %.2f\n",
              err.x(), err.y(), err.z(), std::sqrt(g_ekf.state().p(0, 0)), std::sqrt(g_ekf.state().p(1, 1)),
              std::sqrt(g_ekf.state().p(2, 2)), before.p, after.p, before.th, after.th);
  EXPECT_LT(after.p, 16.27) << "inside the 99.9 % bound of 3 dof";
  EXPECT_LT(after.th, 16.27) << "inside the 99.9 % bound of 3 dof";
}

TEST(FilterLagged, ACoarseMatchAgainstACovarianceThatDeniesTheErrorIsGated) {
  constexpr std::uint64_t kSeed = 97;
  trn::filter::FilterConfig cfg;
  const bsp::CameraModel cam{};
  ASSERT_EQ(g_ekf.configure(cfg, cam), FilterStatus::kOk);
  TruthSim truth(kSeed, true, cfg.imu);
  bsp::Rng rng(kSeed, bsp::StreamId::kTest, 17);
  trn::filter::InitialEstimate est = filter_test::perturbed_estimate(truth, rng, 1.0, 0.5, 2e-3);
  est.x.p_m = truth.p() + Vec3(2400.0, -1800.0, 150.0);
  est.sigma_p_m = Vec3(100.0, 100.0, 100.0);  // claims 100 m, is 3 km off
  ASSERT_EQ(g_ekf.init(est), FilterStatus::kOk);
  trn::Match coarse{};
  const Vec3 axis = truth.q().toRotationMatrix() * Vec3::UnitZ();
  const Vec3 ground = truth.p() + (-truth.p().z() / axis.z()) * axis;
  for (int k = 0; k < 3; ++k) {
    coarse.w_c[k] = k == 2 ? 1.0 : 0.0;
    coarse.p_m[k] = ground(k);
  }
  coarse.sigma_px = 16.0;
  coarse.landmark = trn::kCoarseLandmark;
  coarse.t_s = truth.t();
  UpdateReport rep;
  ASSERT_EQ(g_ekf.update(&coarse, 1, rep), FilterStatus::kOk);
  EXPECT_EQ(rep.rejected_gate, 1U);
  EXPECT_EQ(rep.coarse_accepted, 0U);
}

}  // namespace
