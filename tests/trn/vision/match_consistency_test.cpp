/**
 * @file match_consistency_test.cpp
 * @brief A frame's matches against the pose they fit (TRN-MC-xx): a pose error of the prior is
 *        absorbed, matches moved by 2 px are found, clean matches rarely fail, bad input refused.
 */
#include "trn/vision/match_consistency.hpp"

#include "trn/vision/pose_geometry.hpp"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <random>

namespace {

using trn::Match;
namespace v = trn::vision;

/** A camera 2 km over flat ground looking down (body z down = map -z: q_mb a half turn about x). */
struct Scene {
  bsp::CameraModel cam = bsp::make_camera(1024U, 1024U, 90.0);
  v::PosePrior truth{};
  std::array<Match, 120> matches{};
  std::uint32_t n = 0U;
};

Scene make_scene(std::uint64_t seed, double noise_px, std::uint32_t count) {
  Scene s;
  s.truth.p_m[0] = 100.0;
  s.truth.p_m[1] = -50.0;
  s.truth.p_m[2] = 2000.0;
  s.truth.q_mb[0] = 0.0;
  s.truth.q_mb[1] = 1.0;
  s.truth.q_mb[2] = 0.0;
  s.truth.q_mb[3] = 0.0;
  v::PoseGeometry pose{};
  bsp::Work w{};
  EXPECT_TRUE(v::make_pose(s.truth.p_m, s.truth.q_mb, s.cam, pose, w));
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> ground(-1700.0, 1700.0);
  std::uniform_real_distribution<double> relief(-60.0, 60.0);
  std::normal_distribution<double> noise(0.0, noise_px);
  while (s.n < count) {
    Match& m = s.matches[s.n];
    m.p_m[0] = s.truth.p_m[0] + ground(rng);
    m.p_m[1] = s.truth.p_m[1] + ground(rng);
    m.p_m[2] = relief(rng);
    double u = 0.0;
    double vv = 0.0;
    if (!v::project_point(s.cam, pose, m.p_m, u, vv, nullptr, w) || u < 40.0 || u > 984.0 || vv < 40.0 ||
        vv > 984.0) {
      continue;
    }
    m.u_px = u + noise(rng);
    m.v_px = vv + noise(rng);
    m.sigma_px = noise_px;
    m.tile = static_cast<std::uint16_t>(s.n % 40U);
    ++s.n;
  }
  return s;
}

/** The truth moved by 30 m and rotated by about 3 mrad: what the prior of a frame may be off by. */
v::PosePrior off_prior(const v::PosePrior& truth) {
  v::PosePrior p = truth;
  p.p_m[0] += 25.0;
  p.p_m[1] -= 15.0;
  p.p_m[2] += 8.0;
  p.q_mb[0] = 0.0015;
  p.q_mb[2] = -0.001;
  return p;
}

// TRN-MC-01: the prior's pose error is absorbed by the fit: no clean match fails.
TEST(MatchConsistency, APriorOffBy30MetresIsAbsorbedByTheFit) {
  const Scene s = make_scene(1U, 0.2, 100U);
  std::array<bool, v::kMaxConsistencyMatches> failed{};
  static v::ConsistencyWork ws{};
  v::ConsistencyResult r{};
  bsp::Work w{};
  ASSERT_EQ(v::check_match_consistency(s.cam, off_prior(s.truth), s.matches.data(), s.n, v::ConsistencyParams{},
                                       failed.data(), ws, r, w),
            v::Status::kOk);
  ASSERT_TRUE(r.checked);
  EXPECT_EQ(r.failed, 0U);
  EXPECT_NEAR(r.scale_px, 0.2, 0.06);
  EXPECT_DOUBLE_EQ(r.threshold_px, 1.0) << "4 sigma under the floor";
  EXPECT_GT(w.flops, 0U);
}

// TRN-MC-02: the matches of one tile moved by 2 px (the acceptance's wrong tile) all fail, nobody else's does.
TEST(MatchConsistency, MatchesMovedBy2PixelsFailAndTheOthersDoNot) {
  for (std::uint64_t seed = 1; seed <= 20; ++seed) {
    Scene s = make_scene(seed, 0.2, 100U);
    for (std::uint32_t i = 0; i < s.n; ++i) {
      if (s.matches[i].tile == 7U) {
        s.matches[i].u_px += 2.0;
      }
    }
    std::array<bool, v::kMaxConsistencyMatches> failed{};
    static v::ConsistencyWork ws{};
    v::ConsistencyResult r{};
    bsp::Work w{};
    ASSERT_EQ(v::check_match_consistency(s.cam, off_prior(s.truth), s.matches.data(), s.n, v::ConsistencyParams{},
                                         failed.data(), ws, r, w),
              v::Status::kOk);
    ASSERT_TRUE(r.checked) << "seed " << seed;
    for (std::uint32_t i = 0; i < s.n; ++i) {
      EXPECT_EQ(failed[i], s.matches[i].tile == 7U) << "seed " << seed << " match " << i;
    }
  }
}

// TRN-MC-03: the false-alarm side: Gaussian matches at 0.4 px over 200 frames. exp(-8) = 3.4e-4 with s known; s
// is estimated from each frame's ~100 matches (about 10 % spread), which widens the tail: 1.25e-3 measured, held
// to 2e-3 (the rate result_trust's false-alarm bound is stated for).
TEST(MatchConsistency, CleanMatchesRarelyFail) {
  std::uint64_t checked = 0U;
  std::uint64_t fails = 0U;
  for (std::uint64_t seed = 100; seed < 300; ++seed) {
    const Scene s = make_scene(seed, 0.4, 100U);
    std::array<bool, v::kMaxConsistencyMatches> failed{};
    static v::ConsistencyWork ws{};
    v::ConsistencyResult r{};
    bsp::Work w{};
    ASSERT_EQ(v::check_match_consistency(s.cam, off_prior(s.truth), s.matches.data(), s.n, v::ConsistencyParams{},
                                         failed.data(), ws, r, w),
              v::Status::kOk);
    ASSERT_TRUE(r.checked);
    checked += s.n;
    fails += r.failed;
  }
  EXPECT_EQ(checked, 20000U);
  EXPECT_LE(fails, 40U) << "rate " << static_cast<double>(fails) / static_cast<double>(checked);
}

// TRN-MC-04: too few matches are not checked; bad input is refused.
TEST(MatchConsistency, FewMatchesAreNotCheckedAndBadInputIsRefused) {
  const Scene s = make_scene(3U, 0.2, 7U);
  std::array<bool, v::kMaxConsistencyMatches> failed{};
  failed.fill(true);
  static v::ConsistencyWork ws{};
  v::ConsistencyResult r{};
  bsp::Work w{};
  ASSERT_EQ(v::check_match_consistency(s.cam, s.truth, s.matches.data(), s.n, v::ConsistencyParams{}, failed.data(),
                                       ws, r, w),
            v::Status::kOk);
  EXPECT_FALSE(r.checked);
  for (std::uint32_t i = 0; i < s.n; ++i) {
    EXPECT_FALSE(failed[i]);
  }
  EXPECT_EQ(v::check_match_consistency(s.cam, s.truth, nullptr, 3U, v::ConsistencyParams{}, failed.data(), ws, r, w),
            v::Status::kBadInput);
  EXPECT_EQ(v::check_match_consistency(s.cam, s.truth, s.matches.data(), v::kMaxConsistencyMatches + 1U,
                                       v::ConsistencyParams{}, failed.data(), ws, r, w),
            v::Status::kBadInput);
  v::ConsistencyParams bad{};
  bad.iterations = 0U;
  EXPECT_EQ(v::check_match_consistency(s.cam, s.truth, s.matches.data(), s.n, bad, failed.data(), ws, r, w),
            v::Status::kBadInput);
}

}  // namespace
