/**
 * @file plan_test.cpp
 * @brief plan_frame(): predictions where the camera projects the landmarks, spread over the image,
 *        radii from the prior sigmas, border and caps respected, deterministic; bad inputs refused.
 */
#include "bsp_tile64/emu/devices/camera.hpp"
#include "trn/vision/frame.hpp"

#include <gtest/gtest.h>

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <map>
#include <set>
#include <vector>

namespace {

namespace tv = trn::vision;

constexpr double kPi = 3.14159265358979323846;
constexpr double kDeg = kPi / 180.0;
constexpr std::int32_t kMapPx = 2000;
constexpr double kMPerPx = 6.0;

Eigen::Quaterniond attitude(double yaw_deg, double pitch_deg, double roll_deg) {
  Eigen::Matrix3d ned_to_enu;
  ned_to_enu << 0, 1, 0, 1, 0, 0, 0, 0, -1;
  return Eigen::Quaterniond(ned_to_enu) * Eigen::AngleAxisd(yaw_deg * kDeg, Eigen::Vector3d::UnitZ()) *
         Eigen::AngleAxisd(pitch_deg * kDeg, Eigen::Vector3d::UnitY()) *
         Eigen::AngleAxisd(roll_deg * kDeg, Eigen::Vector3d::UnitX());
}

/** A flat 12 km map (height 0) with a landmark every 30 px: dense, so the plan's choices are its own. */
class Plan : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    image_.assign(static_cast<std::size_t>(kMapPx) * kMapPx, 128);
    elevation_.assign(static_cast<std::size_t>(kMapPx) * kMapPx, 0);
    map_.image = tv::ConstImageU8{image_.data(), kMapPx, kMapPx, kMapPx};
    map_.elevation = elevation_.data();
    map_.geo = tv::MapGeometry{kMPerPx, -0.5 * (kMapPx - 1) * kMPerPx, 0.5 * (kMapPx - 1) * kMPerPx};
    table_.count = 0;
    for (std::int32_t r = 40; r < kMapPx - 40 && table_.count < tv::kMaxLandmarks; r += 30) {
      for (std::int32_t c = 40; c < kMapPx - 40 && table_.count < tv::kMaxLandmarks; c += 30) {
        tv::Landmark& lm = table_.items[table_.count++];
        lm.col_px = c;
        lm.row_px = r;
        lm.p_m[0] = map_.geo.x0_m + c * kMPerPx;
        lm.p_m[1] = map_.geo.y0_m - r * kMPerPx;
        lm.p_m[2] = 0.0;
      }
    }
  }

  static tv::PosePrior prior(const bsp::CameraPose& p) {
    tv::PosePrior pr;
    for (int k = 0; k < 3; ++k) pr.p_m[k] = p.r_m[k];
    pr.q_mb[0] = p.q_mb.w();
    pr.q_mb[1] = p.q_mb.x();
    pr.q_mb[2] = p.q_mb.y();
    pr.q_mb[3] = p.q_mb.z();
    return pr;
  }

  /** The plan of @p t at the test pose with every position sigma @p sigma_m (up to 400). */
  std::vector<tv::PlannedLandmark> plan_at_sigma(const tv::LandmarkTable& t, const tv::FramePlanParams& p,
                                                 double sigma_m) {
    tv::PosePrior pr = prior(pose_);
    pr.sigma_p_m[0] = pr.sigma_p_m[1] = pr.sigma_p_m[2] = sigma_m;
    std::vector<tv::PlannedLandmark> out(400);
    std::uint32_t n = 0;
    EXPECT_EQ(tv::plan_frame(t, map_, cam_, pr, p, out.data(), 400, n, work_), tv::Status::kOk);
    out.resize(n);
    return out;
  }

  std::vector<tv::PlannedLandmark> plan(const tv::PosePrior& pr, const tv::FramePlanParams& p,
                                        std::uint32_t cap = 400) {
    std::vector<tv::PlannedLandmark> out(cap);
    std::uint32_t n = 12345;
    work_ = bsp::Work{};
    EXPECT_EQ(tv::plan_frame(table_, map_, cam_, pr, p, out.data(), cap, n, work_), tv::Status::kOk);
    out.resize(n);
    return out;
  }

  static inline std::vector<std::uint8_t> image_;
  static inline std::vector<std::int16_t> elevation_;
  static inline tv::MapView map_{};
  static inline tv::LandmarkTable table_{};
  static inline tv::PlanScratch scratch_{};
  bsp::CameraModel cam_ = bsp::make_camera(1024, 1024, 90.0);
  bsp::CameraPose pose_{{100.0, -50.0, 3000.0}, attitude(30.0, 2.0, -1.0)};
  bsp::Work work_{};
};

TEST_F(Plan, PredictionsAreWhereTheCameraProjectsTheLandmarks) {
  const std::vector<tv::PlannedLandmark> out = plan(prior(pose_), tv::FramePlanParams{});
  ASSERT_EQ(out.size(), 150U);  // hundreds in view: the cap binds
  std::set<std::uint16_t> seen;
  for (const tv::PlannedLandmark& pl : out) {
    const tv::Landmark& lm = table_.items[pl.landmark];
    const bsp::PixelPoint ref = bsp::project(cam_, pose_, Eigen::Vector3d(lm.p_m[0], lm.p_m[1], lm.p_m[2]));
    ASSERT_TRUE(ref.in_front);
    EXPECT_NEAR(pl.u_px, ref.u_px, 1e-3);
    EXPECT_NEAR(pl.v_px, ref.v_px, 1e-3);
    EXPECT_TRUE(seen.insert(pl.landmark).second) << "landmark " << pl.landmark << " planned twice";
  }
  EXPECT_GT(work_.flops, 1000U);
  EXPECT_GT(work_.fdivs, 100U);
}

TEST_F(Plan, LandmarksAreSpreadOverTheImageAndAnyPrefixIsToo) {
  const tv::FramePlanParams p;
  const std::vector<tv::PlannedLandmark> out = plan(prior(pose_), p);
  ASSERT_EQ(out.size(), 150U);
  // Over 4 x 4 blocks of the usable image, the counts stay close to 150 / 16.
  std::vector<int> blocks(16, 0);
  const double side = 1024.0 - 2.0 * p.border_px;
  for (const tv::PlannedLandmark& pl : out) {
    const int bx = std::min(3, static_cast<int>((static_cast<double>(pl.u_px) - p.border_px) / (side / 4)));
    const int by = std::min(3, static_cast<int>((static_cast<double>(pl.v_px) - p.border_px) / (side / 4)));
    ++blocks[static_cast<std::size_t>(by * 4 + bx)];
  }
  const auto [lo, hi] = std::minmax_element(blocks.begin(), blocks.end());
  std::printf("blocks of 4x4: min %d max %d\n", *lo, *hi);
  EXPECT_GE(*lo, 7);
  EXPECT_LE(*hi, 12);
  // The plan grid is 13 x 13 (ceil sqrt 150): the first 150 are round 0, one per cell, all distinct.
  std::set<int> cells;
  for (const tv::PlannedLandmark& pl : out) {
    const int cx = std::min(12, static_cast<int>((static_cast<double>(pl.u_px) - p.border_px) / ((side - 1.0) / 13)));
    const int cy = std::min(12, static_cast<int>((static_cast<double>(pl.v_px) - p.border_px) / ((side - 1.0) / 13)));
    cells.insert(cy * 13 + cx);
  }
  EXPECT_EQ(cells.size(), 150U);
}

TEST_F(Plan, RoundRobinFillsCellsEvenlyWhenTheCapExceedsTheCells) {
  tv::FramePlanParams p;
  p.max_landmarks = 300;  // grid 16 x 16 = 256 cells: round 0 then part of round 1
  const std::vector<tv::PlannedLandmark> out = plan(prior(pose_), p);
  ASSERT_EQ(out.size(), 300U);
  const double side = 1024.0 - 2.0 * p.border_px;
  std::map<int, int> per_cell;
  std::vector<int> cell_of_entry;
  for (const tv::PlannedLandmark& pl : out) {
    const int cx = std::min(15, static_cast<int>((static_cast<double>(pl.u_px) - p.border_px) / ((side - 1.0) / 16)));
    const int cy = std::min(15, static_cast<int>((static_cast<double>(pl.v_px) - p.border_px) / ((side - 1.0) / 16)));
    ++per_cell[cy * 16 + cx];
    cell_of_entry.push_back(cy * 16 + cx);
  }
  EXPECT_GE(per_cell.size(), 200U);
  for (const auto& [cell, count] : per_cell) {
    EXPECT_LE(count, 2) << "cell " << cell;
  }
  const std::set<int> first_round(cell_of_entry.begin(),
                                  cell_of_entry.begin() + static_cast<std::ptrdiff_t>(per_cell.size()));
  EXPECT_EQ(first_round.size(), per_cell.size()) << "round 0 (one per cell) comes first";
}

TEST_F(Plan, RadiusFollowsThePriorSigmasAndItsClamps) {
  tv::FramePlanParams p;
  tv::PosePrior pr = prior(pose_);
  const std::vector<tv::PlannedLandmark> exact = plan(pr, p);
  for (const tv::PlannedLandmark& pl : exact) EXPECT_EQ(pl.radius_px, p.min_radius_px);
  // 10 m horizontal: ceil(3 * 10 / 6) + 2 = 7 everywhere.
  pr.sigma_p_m[0] = 10.0;
  pr.sigma_p_m[1] = 4.0;
  for (const tv::PlannedLandmark& pl : plan(pr, p)) EXPECT_EQ(pl.radius_px, 7);
  // Attitude: grows with range^2 / height, so off-nadir landmarks get more.
  pr.sigma_p_m[0] = pr.sigma_p_m[1] = 0.0;
  pr.sigma_att_rad[0] = 2e-3;
  const std::vector<tv::PlannedLandmark> att = plan(pr, p);
  double near_r = 0.0;
  double far_r = 0.0;
  for (const tv::PlannedLandmark& pl : att) {
    const tv::Landmark& lm = table_.items[pl.landmark];
    const double dx = lm.p_m[0] - pose_.r_m.x();
    const double dy = lm.p_m[1] - pose_.r_m.y();
    const double h = pose_.r_m.z() - lm.p_m[2];
    const double range2 = dx * dx + dy * dy + h * h;
    const double want = std::ceil(3.0 * 2e-3 * range2 / h / kMPerPx) + 2.0;
    EXPECT_EQ(pl.radius_px, static_cast<std::int32_t>(std::max(4.0, want))) << "landmark " << pl.landmark;
    (range2 < h * h * 1.1 ? near_r : far_r) = std::max(range2 < h * h * 1.1 ? near_r : far_r, 1.0 * pl.radius_px);
  }
  EXPECT_GT(far_r, near_r);
  // Larger sigmas never shrink a radius; huge ones hit the clamp.
  pr.sigma_att_rad[0] = 1.0;
  for (const tv::PlannedLandmark& pl : plan(pr, p)) EXPECT_EQ(pl.radius_px, p.max_radius_px);
  p.max_radius_px = 12;
  for (const tv::PlannedLandmark& pl : plan(pr, p)) EXPECT_EQ(pl.radius_px, 12);
}

TEST_F(Plan, BorderIsRespected) {
  tv::FramePlanParams p;
  p.max_landmarks = 1000;
  const std::size_t n48 = plan(prior(pose_), p, 1000).size();
  p.border_px = 200;
  const std::vector<tv::PlannedLandmark> out = plan(prior(pose_), p, 1000);
  ASSERT_FALSE(out.empty());
  EXPECT_LT(out.size(), n48);
  for (const tv::PlannedLandmark& pl : out) {
    EXPECT_GE(pl.u_px, 200.0F);
    EXPECT_GE(pl.v_px, 200.0F);
    EXPECT_LE(pl.u_px, 1023.0F - 200.0F);
    EXPECT_LE(pl.v_px, 1023.0F - 200.0F);
  }
}

TEST_F(Plan, CapsAreRespected) {
  tv::FramePlanParams p;
  EXPECT_EQ(plan(prior(pose_), p, 10).size(), 10U);
  p.max_landmarks = 7;
  EXPECT_EQ(plan(prior(pose_), p).size(), 7U);
  p.max_landmarks = 0;
  EXPECT_EQ(plan(prior(pose_), p).size(), 0U);
  std::uint32_t n = 99;
  EXPECT_EQ(tv::plan_frame(table_, map_, cam_, prior(pose_), tv::FramePlanParams{}, nullptr, 0, n, work_),
            tv::Status::kOk);
  EXPECT_EQ(n, 0U);
}

TEST_F(Plan, IsDeterministic) {
  tv::PosePrior pr = prior(pose_);
  pr.sigma_p_m[0] = 30.0;
  pr.sigma_att_rad[1] = 2e-3;
  const std::vector<tv::PlannedLandmark> a = plan(pr, tv::FramePlanParams{});
  ASSERT_GT(a.size(), 20U) << "a plan to compare";
  // Another plan in between: scratch state a plan left behind would show in the next.
  tv::PosePrior other = prior(pose_);
  other.sigma_p_m[0] = 200.0;
  (void)plan(other, tv::FramePlanParams{});
  const std::vector<tv::PlannedLandmark> b = plan(pr, tv::FramePlanParams{});
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a[i].landmark, b[i].landmark);
    EXPECT_EQ(a[i].u_px, b[i].u_px);
    EXPECT_EQ(a[i].v_px, b[i].v_px);
    EXPECT_EQ(a[i].radius_px, b[i].radius_px);
  }
}

TEST_F(Plan, NothingIsPlannedWhenTheCameraLooksAwayOrOffTheMap) {
  const bsp::CameraPose up{{0.0, 0.0, 3000.0}, attitude(0.0, 0.0, 180.0)};
  EXPECT_TRUE(plan(prior(up), tv::FramePlanParams{}).empty());
  const bsp::CameraPose away{{40000.0, 0.0, 3000.0}, attitude(0.0, 0.0, 0.0)};
  EXPECT_TRUE(plan(prior(away), tv::FramePlanParams{}).empty());
}

TEST_F(Plan, BadInputsAreRefused) {
  std::vector<tv::PlannedLandmark> out(10);
  std::uint32_t n = 0;
  const tv::PosePrior good = prior(pose_);
  const auto run = [&](const tv::MapView& m, const bsp::CameraModel& c, const tv::PosePrior& pr,
                       const tv::FramePlanParams& p, tv::PlannedLandmark* o) {
    n = 77;
    const tv::Status st = tv::plan_frame(table_, m, c, pr, p, o, 10, n, work_);
    EXPECT_EQ(n, 0U);
    return st;
  };
  EXPECT_EQ(run(map_, cam_, good, tv::FramePlanParams{}, nullptr), tv::Status::kBadInput);
  bsp::CameraModel bad_cam = cam_;
  bad_cam.fx_px = -1.0;
  EXPECT_EQ(run(map_, bad_cam, good, tv::FramePlanParams{}, out.data()), tv::Status::kBadInput);
  tv::MapView bad_map = map_;
  bad_map.geo.m_per_px = 0.0;
  EXPECT_EQ(run(bad_map, cam_, good, tv::FramePlanParams{}, out.data()), tv::Status::kBadInput);
  bad_map = map_;
  bad_map.image = tv::ConstImageU8{};
  EXPECT_EQ(run(bad_map, cam_, good, tv::FramePlanParams{}, out.data()), tv::Status::kBadInput);
  tv::PosePrior bad = good;
  bad.q_mb[0] = bad.q_mb[1] = bad.q_mb[2] = bad.q_mb[3] = 0.0;
  EXPECT_EQ(run(map_, cam_, bad, tv::FramePlanParams{}, out.data()), tv::Status::kBadInput);
  bad = good;
  bad.p_m[2] = std::nan("");
  EXPECT_EQ(run(map_, cam_, bad, tv::FramePlanParams{}, out.data()), tv::Status::kBadInput);
  bad = good;
  bad.sigma_att_rad[2] = -1e-3;
  EXPECT_EQ(run(map_, cam_, bad, tv::FramePlanParams{}, out.data()), tv::Status::kBadInput);
  tv::FramePlanParams p;
  p.border_px = 512;
  EXPECT_EQ(run(map_, cam_, good, p, out.data()), tv::Status::kBadInput);
  p = tv::FramePlanParams{};
  p.sigma_k = 0.0;
  EXPECT_EQ(run(map_, cam_, good, p, out.data()), tv::Status::kBadInput);
  p = tv::FramePlanParams{};
  p.min_radius_px = 10;
  p.max_radius_px = 9;
  EXPECT_EQ(run(map_, cam_, good, p, out.data()), tv::Status::kBadInput);
  p = tv::FramePlanParams{};
  p.max_radius_px = tv::kFineMaxSearchPx + 1;
  EXPECT_EQ(run(map_, cam_, good, p, out.data()), tv::Status::kBadInput);
  p = tv::FramePlanParams{};
  p.min_radius_px = 0;
  EXPECT_EQ(run(map_, cam_, good, p, out.data()), tv::Status::kBadInput);
}

TEST_F(Plan, TheFootprintCullAndTheScratchGiveTheSamePlanForLessWork) {
  // The dense table with heights between -300 and +450 m, so the cull's slab has a thickness.
  static tv::LandmarkTable hilly;
  hilly = table_;
  for (std::uint32_t i = 0; i < hilly.count; ++i) {
    tv::Landmark& lm = hilly.items[i];
    lm.p_m[2] = 375.0 * std::sin(lm.p_m[0] / 1700.0) * std::cos(lm.p_m[1] / 2300.0) + 75.0;
  }
  tv::FramePlanParams on;
  tv::FramePlanParams off;
  off.footprint_cull = false;
  std::uint32_t poses = 0;
  std::uint32_t culled_cheaper = 0;
  for (const double alt : {900.0, 1500.0, 2500.0, 4200.0}) {
    for (const double yaw : {0.0, 37.0, 145.0, 260.0}) {
      for (const double tilt : {0.0, 8.0, 25.0, 50.0}) {
        const bsp::CameraPose pose{{350.0 - yaw, 200.0 - 2.0 * tilt, alt}, attitude(yaw, tilt, -0.4 * tilt)};
        tv::PosePrior pr = prior(pose);
        pr.sigma_p_m[0] = pr.sigma_p_m[1] = 20.0;
        pr.sigma_att_rad[0] = pr.sigma_att_rad[1] = pr.sigma_att_rad[2] = 0.002;
        for (const std::uint32_t cap : {40U, 400U}) {
          std::vector<tv::PlannedLandmark> a(cap);
          std::vector<tv::PlannedLandmark> b(cap);
          std::uint32_t na = 0;
          std::uint32_t nb = 0;
          bsp::Work wa{};
          bsp::Work wb{};
          std::vector<tv::PlannedLandmark> c(cap);
          std::uint32_t nc = 0;
          bsp::Work wc{};
          ASSERT_EQ(tv::plan_frame(hilly, map_, cam_, pr, on, a.data(), cap, na, wa), tv::Status::kOk);
          ASSERT_EQ(tv::plan_frame(hilly, map_, cam_, pr, off, b.data(), cap, nb, wb), tv::Status::kOk);
          ASSERT_EQ(tv::plan_frame(hilly, map_, cam_, pr, on, c.data(), cap, nc, &scratch_, wc), tv::Status::kOk);
          ASSERT_EQ(na, nb) << "alt " << alt << " yaw " << yaw << " tilt " << tilt;
          ASSERT_EQ(na, nc) << "with the scratch, alt " << alt << " yaw " << yaw << " tilt " << tilt;
          for (std::uint32_t k = 0; k < na; ++k) {
            ASSERT_EQ(a[k].landmark, b[k].landmark) << "place " << k << ", alt " << alt << " tilt " << tilt;
            ASSERT_EQ(a[k].u_px, b[k].u_px);
            ASSERT_EQ(a[k].v_px, b[k].v_px);
            ASSERT_EQ(a[k].radius_px, b[k].radius_px);
            ASSERT_EQ(a[k].landmark, c[k].landmark) << "with the scratch, place " << k;
            ASSERT_EQ(a[k].u_px, c[k].u_px);
            ASSERT_EQ(a[k].v_px, c[k].v_px);
            ASSERT_EQ(a[k].radius_px, c[k].radius_px);
          }
          if (na > 0U) {
            EXPECT_LT(wc.flops, wa.flops) << "the scratch predicts each landmark once";
          }
          ++poses;
          culled_cheaper += wa.flops < wb.flops ? 1U : 0U;
          if (alt == 900.0 && tilt == 0.0 && cap == 400U) {
            // A footprint of ~2.4 km (the slab's low plane 1.2 km down) on a 12 km map: most landmarks
            // are skipped unprojected (4.7x fewer flops when written).
            EXPECT_GT(na, 20U);
            EXPECT_LT(wa.flops * 4U, wb.flops);
          }
        }
      }
    }
  }
  std::printf("%u plans the same with and without the cull; %u of them cheaper with it\n", poses, culled_cheaper);
  // At 50 deg of tilt the far edge of a 90 deg field of view looks above the horizon: no cull, no saving.
  EXPECT_GE(culled_cheaper, poses / 2U);
}

TEST_F(Plan, FaintLandmarksWaitForATightPrior) {
  // Every other landmark faint (corner 6), the rest strong (30).
  static tv::LandmarkTable mixed;
  mixed = table_;
  for (std::uint32_t i = 0; i < mixed.count; ++i) {
    mixed.items[i].corner = (i % 2U) == 0U ? 6.0F : 30.0F;
  }
  tv::FramePlanParams p;
  p.strong_corner = 20.0F;
  p.weak_max_radius_px = 8;
  const auto plan_of = [&](double sigma_m) { return plan_at_sigma(mixed, p, sigma_m); };
  const auto faint = [&](const std::vector<tv::PlannedLandmark>& v) {
    return std::count_if(v.begin(), v.end(), [&](const tv::PlannedLandmark& pl) {
      return mixed.items[pl.landmark].corner < p.strong_corner;
    });
  };
  const std::vector<tv::PlannedLandmark> tight = plan_of(1.0);  // radius 4 px: everyone
  const std::vector<tv::PlannedLandmark> loose = plan_of(40.0);  // radius 22 px: strong ones only
  ASSERT_EQ(tight.size(), 150U);
  ASSERT_EQ(loose.size(), 150U) << "enough strong landmarks in view to fill the plan";
  EXPECT_GT(faint(tight), 50);
  EXPECT_EQ(faint(loose), 0);
  for (const tv::PlannedLandmark& pl : tight) {
    EXPECT_LE(pl.radius_px, p.weak_max_radius_px);
  }
  for (const tv::PlannedLandmark& pl : loose) {
    EXPECT_GT(pl.radius_px, p.weak_max_radius_px);
  }
}

TEST_F(Plan, TheTablesDenseSetWaitsForATightPriorWhateverItsStrength) {
  // The table's second half is its dense set; every landmark strong, so only the set decides.
  static tv::LandmarkTable two;
  two = table_;
  two.first_tight = two.count / 2U;
  for (std::uint32_t i = 0; i < two.count; ++i) {
    two.items[i].corner = 30.0F;
  }
  tv::FramePlanParams p;
  p.strong_corner = 20.0F;
  p.weak_max_radius_px = 8;
  const auto plan_of = [&](const tv::LandmarkTable& t, double sigma_m) { return plan_at_sigma(t, p, sigma_m); };
  const auto dense = [&](const std::vector<tv::PlannedLandmark>& v) {
    return std::count_if(v.begin(), v.end(), [&](const tv::PlannedLandmark& pl) { return pl.landmark >= two.first_tight; });
  };
  const std::vector<tv::PlannedLandmark> tight = plan_of(two, 1.0);
  const std::vector<tv::PlannedLandmark> loose = plan_of(two, 40.0);
  ASSERT_EQ(tight.size(), 150U);
  ASSERT_FALSE(loose.empty());
  EXPECT_GT(dense(tight), 20);
  EXPECT_EQ(dense(loose), 0);
  // With a loose prior the plan is the loose set's own: the table cut at first_tight plans the same.
  static tv::LandmarkTable cut;
  cut = two;
  cut.count = two.first_tight;
  const std::vector<tv::PlannedLandmark> alone = plan_of(cut, 40.0);
  ASSERT_EQ(alone.size(), loose.size());
  for (std::size_t k = 0; k < alone.size(); ++k) {
    EXPECT_EQ(alone[k].landmark, loose[k].landmark) << k;
    EXPECT_EQ(alone[k].radius_px, loose[k].radius_px) << k;
  }
}

}  // namespace
