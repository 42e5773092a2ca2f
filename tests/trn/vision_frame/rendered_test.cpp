/**
 * @file rendered_test.cpp
 * @brief Per-frame vision on rendered frames of the default world and descent, two world seeds:
 *        fine matches land on the truth projection (exact and offset priors), the coarse stage
 *        removes kilometre errors and fine matching works after it (by the spatial and the
 *        transform correlation alike, bit for bit), its grid footprint warp stays within a
 *        sixty-fourth of a pixel and 1 DN of the exact warp, bad inputs are refused.
 *
 * The world (default 4096^2 terrain, map product, descent shading, landmarks)
 * is built once per seed: the tests are typed over the seed so that gtest runs
 * every test of one seed before the next. Numbers are printed for docs/VISION.md.
 */
#include "tests/trn/vision_frame/world.hpp"

#include "bsp_tile64/emu/cost_model.hpp"
#include "bsp_tile64/emu/profile.hpp"
#include "trn/tasks/vision/vision_coord.hpp"
#include "trn/vision/pose_geometry.hpp"
#include "trn/vision/warp_grid.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cstdio>
#include <type_traits>

namespace {

using namespace frame_test;  // NOLINT(google-build-using-namespace): test helpers

/** Outcome of planning and matching one frame. */
struct FrameRun {
  std::uint32_t planned = 0;
  std::uint32_t accepted = 0;
  std::vector<double> err_px;  ///< |(u, v) - truth projection of p_m|
  std::vector<double> norm;    ///< per-axis |error| / sigma_px
  bsp::Work work{};

  double median() const { return quantile(err_px, 0.5); }
  double rate() const { return planned == 0 ? 0.0 : static_cast<double>(accepted) / planned; }
  void print(const char* what, std::uint64_t seed, double alt) const {
    std::printf("[ seed %llu %6.0f m %-10s] planned %3u accepted %3u (%3.0f %%) error median %.3f p95 %.3f max %.3f px,"
                " per-axis |e|/sigma robust sd %.2f; per planned landmark %.0f k MACs %.0f k flops %.1f k fdivs\n",
                static_cast<unsigned long long>(seed), alt, what, planned, accepted, 100.0 * rate(), median(),
                quantile(err_px, 0.95), quantile(err_px, 1.0), 1.4826 * quantile(norm, 0.5),
                1e-3 * static_cast<double>(work.int_macs) / std::max(1U, planned),
                1e-3 * static_cast<double>(work.flops) / std::max(1U, planned),
                1e-3 * static_cast<double>(work.fdivs) / std::max(1U, planned));
  }
};

/** Plans @p f at @p prior and matches every planned landmark; scores against the truth pose. */
FrameRun run_fine(World& w, const std::vector<std::uint8_t>& f, const bsp::CameraPose& truth,
                  const tv::PosePrior& prior, const tv::LandmarkMatchParams& mp) {
  static tv::PlannedLandmark planned[200];
  static tv::LandmarkWorkspace ws;
  FrameRun run;
  EXPECT_EQ(tv::plan_frame(*w.table, w.fine, w.cam, prior, tv::FramePlanParams{}, planned, 200, run.planned,
                           run.work),
            tv::Status::kOk);
  for (std::uint32_t i = 0; i < run.planned; ++i) {
    trn::Match m{};
    bool ok = false;
    tv::LandmarkDiag diag;
    EXPECT_EQ(tv::match_landmark(w.view(f), w.cam, prior, w.fine, *w.table, planned[i].landmark,
                                 planned[i].radius_px, mp, ws, m, ok, diag, run.work),
              tv::Status::kOk);
    if (!ok) {
      continue;
    }
    ++run.accepted;
    const tv::Landmark& lm = w.table->items[planned[i].landmark];
    const bsp::PixelPoint t = bsp::project(w.cam, truth, Eigen::Vector3d(lm.p_m[0], lm.p_m[1], lm.p_m[2]));
    run.err_px.push_back(std::hypot(m.u_px - t.u_px, m.v_px - t.v_px));
    run.norm.push_back(std::fabs(m.u_px - t.u_px) / m.sigma_px);
    run.norm.push_back(std::fabs(m.v_px - t.v_px) / m.sigma_px);
    // The Match is self-consistent: w_c is the unit ray of (u, v), p_m the landmark's, metadata set.
    EXPECT_NEAR(std::hypot(std::hypot(m.w_c[0], m.w_c[1]), m.w_c[2]), 1.0, 1e-12);
    EXPECT_NEAR(w.cam.cx_px + w.cam.fx_px * m.w_c[0] / m.w_c[2], m.u_px, 1e-9);
    EXPECT_NEAR(w.cam.cy_px + w.cam.fy_px * m.w_c[1] / m.w_c[2], m.v_px, 1e-9);
    EXPECT_EQ(m.p_m[0], lm.p_m[0]);
    EXPECT_EQ(m.p_m[2], lm.p_m[2]);
    EXPECT_EQ(m.landmark, planned[i].landmark);
    EXPECT_EQ(m.t_s, prior.t_s);
    EXPECT_GE(m.quality, tv::kFineQuality.min_peak);
    EXPECT_GE(m.sigma_px, tv::kFineSigmaFloorPx);
    EXPECT_EQ(diag.outside_px, 0);
  }
  return run;
}

/** A prior from the truth with small sigmas (the filter's state after a few good frames). */
tv::PosePrior tight_prior(const bsp::CameraPose& truth, double t) {
  tv::PosePrior prior = prior_of(truth, t);
  for (int k = 0; k < 3; ++k) {
    prior.sigma_p_m[k] = 5.0;
    prior.sigma_att_rad[k] = 0.5e-3;
  }
  return prior;
}

template <class Seed>
class Rendered : public ::testing::Test {
 protected:
  static constexpr std::uint64_t kSeed = Seed::value;
  void SetUp() override { w_ = &World::use(kSeed); }
  World* w_ = nullptr;
};

using Seeds = ::testing::Types<std::integral_constant<std::uint64_t, 1>, std::integral_constant<std::uint64_t, 2>>;
TYPED_TEST_SUITE(Rendered, Seeds);

TYPED_TEST(Rendered, FineMatchesWithTheTruthAsPriorLandOnTheTruthProjection) {
  World& w = *this->w_;
  for (const double alt : {4000.0, 2500.0, 1200.0}) {
    double t = 0.0;
    const bsp::CameraPose truth = w.truth_at(alt, &t);
    const FrameRun run = run_fine(w, w.frame_at(alt), truth, tight_prior(truth, t), tv::LandmarkMatchParams{});
    run.print("exact", this->kSeed, alt);
    EXPECT_GE(run.planned, 8U) << "seed " << this->kSeed << " altitude " << alt;
    EXPECT_GE(run.rate(), 0.9) << "seed " << this->kSeed << " altitude " << alt;
    EXPECT_LT(run.median(), 0.5) << "seed " << this->kSeed << " altitude " << alt;
    EXPECT_GT(run.work.int_macs, 100000U * run.accepted);
  }
}

TYPED_TEST(Rendered, FineMatchesWithAPriorThirtyMetresAndOneDegreeOffLandOnTheTruthProjection) {
  World& w = *this->w_;
  for (const double alt : {4000.0, 2500.0, 1200.0}) {
    double t = 0.0;
    const bsp::CameraPose truth = w.truth_at(alt, &t);
    bsp::CameraPose off = truth;
    off.r_m += Eigen::Vector3d(24.0, -18.0, 15.0);
    off.q_mb = truth.q_mb * Eigen::Quaterniond(Eigen::AngleAxisd(
                                1.0 * kDeg, Eigen::Vector3d(0.6, -0.7, 0.39).normalized()));
    tv::PosePrior prior = prior_of(off, t);
    for (int k = 0; k < 3; ++k) {
      prior.sigma_p_m[k] = 20.0;
      prior.sigma_att_rad[k] = 1.0 * kDeg / std::sqrt(3.0);
    }
    const FrameRun run = run_fine(w, w.frame_at(alt), truth, prior, tv::LandmarkMatchParams{});
    run.print("30m+1deg", this->kSeed, alt);
    EXPECT_GE(run.planned, 8U) << "seed " << this->kSeed << " altitude " << alt;
    EXPECT_GE(run.rate(), 0.75) << "seed " << this->kSeed << " altitude " << alt;
    EXPECT_LT(run.median(), 0.5) << "seed " << this->kSeed << " altitude " << alt;
  }
}

TYPED_TEST(Rendered, WithoutRelightingTheMapSunDefeatsTheFineChecks) {
  // Why templates are relit: the map product is shaded under another sun, and topographic
  // shading changes with the sun's azimuth, so unrelit peaks fall below 0.8.
  World& w = *this->w_;
  double t = 0.0;
  const bsp::CameraPose truth = w.truth_at(2500.0, &t);
  tv::LandmarkMatchParams mp;
  mp.relight = false;
  const FrameRun run = run_fine(w, w.frame_at(2500.0), truth, tight_prior(truth, t), mp);
  run.print("unrelit", this->kSeed, 2500.0);
  EXPECT_GE(run.planned, 20U);
  EXPECT_LT(run.rate(), 0.25);
}

/** Coarse stage at @p alt with the prior moved by (dx, dy); returns the result and the error after dp_m. */
tv::CoarseFrameResult run_coarse(World& w, double alt, double dx, double dy, const tv::MapView& map, double& err_m,
                                 tv::PosePrior& prior, bsp::CameraPose& truth,
                                 const tv::CoarseFrameParams& params = tv::CoarseFrameParams{},
                                 bsp::Work* work_out = nullptr) {
  static tv::CoarseFrameWorkspace ws;
  double t = 0.0;
  truth = w.truth_at(alt, &t);
  prior = prior_of(truth, t);
  prior.p_m[0] += dx;
  prior.p_m[1] += dy;
  tv::CoarseFrameResult r;
  bsp::Work work;
  EXPECT_EQ(tv::coarse_frame(w.view(w.frame_at(alt)), w.cam, prior, map, params, ws, r, work), tv::Status::kOk);
  if (work_out != nullptr) {
    *work_out = work;
  }
  err_m = std::hypot(prior.p_m[0] + r.dp_m[0] - truth.r_m.x(), prior.p_m[1] + r.dp_m[1] - truth.r_m.y());
  if (r.accepted && params.coarse.method == tv::CorrelationMethod::kSpatial) {
    EXPECT_GT(work.int_macs, 100000000U);  // ~153 M MACs of correlation
    if (dx > 0.0 && dy > 0.0 && dx < 3000.0) {
      std::printf("[ coarse work ] %.1f M MACs %.2f M int ops %.2f M flops %.2f M fdivs %.2f M mem words\n",
                  1e-6 * static_cast<double>(work.int_macs), 1e-6 * static_cast<double>(work.int_ops),
                  1e-6 * static_cast<double>(work.flops), 1e-6 * static_cast<double>(work.fdivs),
                  1e-6 * static_cast<double>(work.mem_words));
    }
  }
  return r;
}

TYPED_TEST(Rendered, CoarseStageRemovesThreeToFourKilometreErrorsThenFineMatchingWorks) {
  World& w = *this->w_;
  std::vector<double> errs;
  for (int d = 0; d < 9; ++d) {
    // Eight directions at 3.2 km, then 4.2 km east.
    const double az = d * 45.0 * kDeg;
    const double r = d < 8 ? 3200.0 : 4200.0;
    double err = 0.0;
    tv::PosePrior prior;
    bsp::CameraPose truth;
    const tv::CoarseFrameResult c =
        run_coarse(w, 4000.0, r * std::sin(az), r * std::cos(az), w.coarse_lit, err, prior, truth);
    ASSERT_TRUE(c.accepted) << "seed " << this->kSeed << " direction " << d << " reason "
                            << static_cast<int>(c.coarse.match.reason());
    errs.push_back(err);
    std::printf("[ seed %llu   4000 m coarse    ] direction %d: error after dp %.2f m\n",
                static_cast<unsigned long long>(this->kSeed), d, err);
    EXPECT_LT(err, 25.0) << "seed " << this->kSeed << " direction " << d;  // half a coarse-scale (48 m) pixel
    // The coarse Match: the image point sees its map point, within its sigma.
    const trn::Match& m = c.match;
    const bsp::PixelPoint tp = bsp::project(w.cam, truth, Eigen::Vector3d(m.p_m[0], m.p_m[1], m.p_m[2]));
    EXPECT_LT(std::hypot(m.u_px - tp.u_px, m.v_px - tp.v_px), 2.0 * m.sigma_px) << "direction " << d;
    EXPECT_EQ(m.landmark, trn::kCoarseLandmark);
    EXPECT_EQ(m.t_s, prior.t_s);
    EXPECT_NEAR(std::hypot(std::hypot(m.w_c[0], m.w_c[1]), m.w_c[2]), 1.0, 1e-12);
    EXPECT_NEAR(w.cam.cx_px + w.cam.fx_px * m.w_c[0] / m.w_c[2], m.u_px, 1e-9);
    EXPECT_GT(m.quality, 0.85F);
    EXPECT_EQ(c.outside_px, 0);
    if (d == 1 || d == 8) {
      // Fine matching around the corrected prior.
      prior.p_m[0] += c.dp_m[0];
      prior.p_m[1] += c.dp_m[1];
      for (int k = 0; k < 3; ++k) {
        prior.sigma_p_m[k] = c.sigma_m;
        prior.sigma_att_rad[k] = 0.5e-3;
      }
      const FrameRun run = run_fine(w, w.frame_at(4000.0), truth, prior, tv::LandmarkMatchParams{});
      run.print("coarse+fine", this->kSeed, 4000.0);
      EXPECT_GE(run.rate(), 0.9);
      EXPECT_LT(run.median(), 0.5);
    }
  }
  std::printf("[ seed %llu   4000 m coarse    ] 9 priors 3.2-4.2 km off: error after dp median %.1f max %.1f m\n",
              static_cast<unsigned long long>(this->kSeed), quantile(errs, 0.5), quantile(errs, 1.0));
}

TYPED_TEST(Rendered, CoarseStageOnTheUnrelitMapIsBiasedButWithinOneHundredMetres) {
  World& w = *this->w_;
  std::vector<double> errs;
  for (int d = 0; d < 4; ++d) {
    const double az = (45.0 + d * 90.0) * kDeg;
    double err = 0.0;
    tv::PosePrior prior;
    bsp::CameraPose truth;
    const tv::CoarseFrameResult c =
        run_coarse(w, 4000.0, 3200.0 * std::sin(az), 3200.0 * std::cos(az), w.coarse, err, prior, truth);
    EXPECT_TRUE(c.accepted) << "seed " << this->kSeed << " direction " << d;
    EXPECT_LT(err, 100.0) << "seed " << this->kSeed << " direction " << d;
    errs.push_back(err);
  }
  std::printf("[ seed %llu   4000 m coarse    ] unrelit map: error after dp median %.1f max %.1f m\n",
              static_cast<unsigned long long>(this->kSeed), quantile(errs, 0.5), quantile(errs, 1.0));
}

/** The bits of a double, for bit-for-bit comparisons. */
std::uint64_t bits(double v) { return std::bit_cast<std::uint64_t>(v); }

/** The coarse surface of the last coarse_frame(), copied (the next call reuses the workspace). */
std::vector<std::uint32_t> surface_bits(const tv::CoarseFrameResult& r) {
  std::vector<std::uint32_t> v;
  const tv::ConstImageF32 s = r.coarse.match.surface;
  for (std::int32_t y = 0; y < s.height; ++y)
    for (std::int32_t x = 0; x < s.width; ++x) v.push_back(std::bit_cast<std::uint32_t>(s.at(x, y)));
  return v;
}

TYPED_TEST(Rendered, CoarseStageByTheTransformGivesTheSpatialResultBitForBit) {
  // The scenes of CoarseStageRemovesThreeToFourKilometreErrors: the relit layer, eight directions at
  // 3.2 km, then 4.2 km east. The transform path must give the same result to the last bit.
  World& w = *this->w_;
  tv::CoarseFrameParams transform_p;
  transform_p.coarse.method = tv::CorrelationMethod::kTransform;
  for (int d = 0; d < 9; ++d) {
    const double az = d * 45.0 * kDeg;
    const double r = d < 8 ? 3200.0 : 4200.0;
    double err_s = 0.0;
    double err_t = 0.0;
    tv::PosePrior prior;
    bsp::CameraPose truth;
    bsp::Work ws;
    bsp::Work wt;
    const tv::CoarseFrameResult s = run_coarse(w, 4000.0, r * std::sin(az), r * std::cos(az), w.coarse_lit, err_s,
                                               prior, truth, tv::CoarseFrameParams{}, &ws);
    const std::vector<std::uint32_t> surface_s = surface_bits(s);
    const tv::CoarseFrameResult t = run_coarse(w, 4000.0, r * std::sin(az), r * std::cos(az), w.coarse_lit, err_t,
                                               prior, truth, transform_p, &wt);
    ASSERT_TRUE(s.accepted) << "seed " << this->kSeed << " direction " << d;
    EXPECT_EQ(t.accepted, s.accepted) << "direction " << d;
    EXPECT_EQ(bits(t.dp_m[0]), bits(s.dp_m[0])) << "direction " << d;
    EXPECT_EQ(bits(t.dp_m[1]), bits(s.dp_m[1])) << "direction " << d;
    EXPECT_EQ(bits(t.sigma_m), bits(s.sigma_m));
    EXPECT_EQ(bits(t.ground_z_m), bits(s.ground_z_m));
    EXPECT_EQ(t.outside_px, s.outside_px);
    EXPECT_EQ(bits(t.coarse.x_px), bits(s.coarse.x_px)) << "direction " << d;
    EXPECT_EQ(bits(t.coarse.y_px), bits(s.coarse.y_px)) << "direction " << d;
    EXPECT_EQ(t.coarse.match.peak.ix, s.coarse.match.peak.ix);
    EXPECT_EQ(t.coarse.match.peak.iy, s.coarse.match.peak.iy);
    EXPECT_EQ(std::bit_cast<std::uint32_t>(t.coarse.match.peak.score),
              std::bit_cast<std::uint32_t>(s.coarse.match.peak.score));
    EXPECT_EQ(std::bit_cast<std::uint32_t>(t.coarse.match.peak.second),
              std::bit_cast<std::uint32_t>(s.coarse.match.peak.second));
    EXPECT_EQ(t.coarse.match.flat_windows, s.coarse.match.flat_windows);
    EXPECT_EQ(t.coarse.match.recomputes, s.coarse.match.recomputes);
    for (int k = 0; k < 3; ++k) {
      EXPECT_EQ(bits(t.match.w_c[k]), bits(s.match.w_c[k])) << "direction " << d;
      EXPECT_EQ(bits(t.match.p_m[k]), bits(s.match.p_m[k])) << "direction " << d;
    }
    EXPECT_EQ(bits(t.match.u_px), bits(s.match.u_px));
    EXPECT_EQ(bits(t.match.v_px), bits(s.match.v_px));
    EXPECT_EQ(bits(t.match.sigma_px), bits(s.match.sigma_px));
    EXPECT_EQ(std::bit_cast<std::uint32_t>(t.match.quality), std::bit_cast<std::uint32_t>(s.match.quality));
    EXPECT_EQ(surface_bits(t), surface_s) << "direction " << d;
    const auto cs = static_cast<double>(bsp::cost_of(bsp::kTile64, ws));
    const auto ct = static_cast<double>(bsp::cost_of(bsp::kTile64, wt));
    // The footprint warp (grid warp, ~3.7 M cycles) is the same on both paths.
    EXPECT_LT(ct, 0.4 * cs) << "direction " << d;
    if (d == 0) {
      std::printf("[ seed %llu   4000 m coarse    ] coarse_frame TILE64 cycles: spatial %.1f M, transform %.1f M\n",
                  static_cast<unsigned long long>(this->kSeed), cs / 1e6, ct / 1e6);
    }
  }
}

/**
 * coarse_frame_prepare(), the surface in bands of @p band_rows by correlate_band(), gathered by
 * correlate_gathered(), coarse_frame_finish(): what the coordinator and the vision tiles do.
 */
tv::CoarseFrameResult run_coarse_in_bands(World& w, const tv::ConstImageU8 frame, const tv::PosePrior& prior,
                                          const tv::CoarseFrameParams& params, std::int32_t band_rows,
                                          std::uint32_t& bands) {
  static tv::CoarseFrameWorkspace ws;
  tv::CoarseFrameStage stage;
  tv::CoarseFrameResult r;
  bsp::Work work;
  EXPECT_EQ(tv::coarse_frame_prepare(frame, w.cam, prior, w.coarse_lit, params, ws, stage, r, work), tv::Status::kOk);
  EXPECT_TRUE(stage.search);
  const tv::CoarsePrepared& prep = stage.prep;
  const std::int32_t sw = prep.surface_w;
  const std::int32_t sh = prep.surface_h;
  const auto entries = static_cast<std::size_t>(prep.window.width + 1) * static_cast<std::size_t>(band_rows + prep.tmpl.height);
  std::vector<std::uint32_t> sum(entries);
  std::vector<std::uint64_t> sum_sq(entries);
  std::vector<float> band(static_cast<std::size_t>(sw * band_rows));
  std::vector<std::uint8_t> flags(band.size());
  std::vector<float> surface(static_cast<std::size_t>(sw * sh));
  std::uint64_t digest = 0U;
  std::int32_t flats = 0;
  std::uint32_t recomputes = 0U;
  bands = 0U;
  for (std::int32_t row0 = 0; row0 < sh; row0 += band_rows) {
    const std::int32_t n = row0 + band_rows <= sh ? band_rows : sh - row0;
    tv::BandResult b;
    const tv::BandBuffers buf{sum.data(), sum_sq.data(), static_cast<std::int64_t>(entries), band.data(), flags.data(),
                              static_cast<std::int64_t>(band.size())};
    EXPECT_EQ(tv::correlate_band(prep.tmpl, prep.window, row0, n, buf, b, work), tv::Status::kOk);
    std::copy(band.begin(), band.begin() + sw * n, surface.begin() + static_cast<std::ptrdiff_t>(row0) * sw);
    digest += b.digest;
    flats += b.flat_windows;
    recomputes += b.recomputes;
    ++bands;
  }
  tv::MatchResult m;
  EXPECT_EQ(tv::correlate_gathered(prep.tmpl, prep.window, params.coarse.quality,
                                   tv::ConstImageF32{surface.data(), sw, sh, sw}, digest, flats, recomputes,
                                   ws.coarse.corr.buffers(), m, work),
            tv::Status::kOk);
  tv::coarse_frame_finish(w.cam, w.coarse_lit, params, stage, m, r, work);
  // The surface lives in this function: what the caller compares is its match.
  r.coarse.match.surface = tv::ConstImageF32{};
  return r;
}

TYPED_TEST(Rendered, CoarseStageInBandsGivesTheOnePieceResultBitForBit) {
  // What the coordinator's coarse stage does over the vision tiles (bands of 5 rows: 40 tiles;
  // 16 rows: the most a tile's slot holds; 193: one band), on the scenes of
  // CoarseStageRemovesThreeToFourKilometreErrors: the one-piece result to the last bit.
  World& w = *this->w_;
  const tv::CoarseFrameParams params = trn::tasks::coord_coarse_params();
  for (int d = 0; d < 9; ++d) {
    const double az = d * 45.0 * kDeg;
    const double r = d < 8 ? 3200.0 : 4200.0;
    double err = 0.0;
    tv::PosePrior prior;
    bsp::CameraPose truth;
    const tv::CoarseFrameResult one = run_coarse(w, 4000.0, r * std::sin(az), r * std::cos(az), w.coarse_lit, err,
                                                 prior, truth, params);
    ASSERT_TRUE(one.accepted) << "direction " << d;
    for (const std::int32_t rows : {5, 16, 193}) {
      std::uint32_t bands = 0U;
      const tv::CoarseFrameResult b = run_coarse_in_bands(w, w.view(w.frame_at(4000.0)), prior, params, rows, bands);
      EXPECT_EQ(bands, (193U + static_cast<std::uint32_t>(rows) - 1U) / static_cast<std::uint32_t>(rows));
      EXPECT_EQ(b.accepted, one.accepted) << "direction " << d << " rows " << rows;
      EXPECT_EQ(bits(b.dp_m[0]), bits(one.dp_m[0])) << "direction " << d << " rows " << rows;
      EXPECT_EQ(bits(b.dp_m[1]), bits(one.dp_m[1])) << "direction " << d << " rows " << rows;
      EXPECT_EQ(bits(b.sigma_m), bits(one.sigma_m));
      EXPECT_EQ(bits(b.coarse.x_px), bits(one.coarse.x_px));
      EXPECT_EQ(bits(b.coarse.y_px), bits(one.coarse.y_px));
      EXPECT_EQ(std::bit_cast<std::uint32_t>(b.coarse.match.peak.score),
                std::bit_cast<std::uint32_t>(one.coarse.match.peak.score));
      EXPECT_EQ(std::bit_cast<std::uint32_t>(b.coarse.match.peak.second),
                std::bit_cast<std::uint32_t>(one.coarse.match.peak.second));
      EXPECT_EQ(b.coarse.match.flat_windows, one.coarse.match.flat_windows);
      EXPECT_FALSE(b.coarse.match.check_failed);
      for (int k = 0; k < 3; ++k) {
        EXPECT_EQ(bits(b.match.w_c[k]), bits(one.match.w_c[k]));
        EXPECT_EQ(bits(b.match.p_m[k]), bits(one.match.p_m[k]));
      }
      EXPECT_EQ(bits(b.match.u_px), bits(one.match.u_px));
      EXPECT_EQ(bits(b.match.v_px), bits(one.match.v_px));
      EXPECT_EQ(bits(b.match.sigma_px), bits(one.match.sigma_px));
      EXPECT_EQ(b.match.t_s, one.match.t_s);
    }
  }
}

TYPED_TEST(Rendered, CoarseFootprintGridWarpIsWithinASixtyFourthPixelAndOneDnOfTheExactWarp) {
  // The scenes of CoarseStageRemovesThreeToFourKilometreErrors, by the coordinator's method: the
  // footprint homographies coarse_frame builds, the grid warp's source coordinates against them per
  // spacing, its pixels against warp_homography()'s, and the stage's offsets and cycles both ways.
  World& w = *this->w_;
  tv::CoarseFrameParams grid_p;
  grid_p.coarse.method = tv::CorrelationMethod::kTransform;
  tv::CoarseFrameParams exact_p = grid_p;
  exact_p.warp_grid_px = 0;
  ASSERT_EQ(grid_p.warp_grid_px, 8);
  static std::vector<std::uint8_t> exact_px(std::size_t{256} * 256U);
  static std::vector<std::uint8_t> grid_px(std::size_t{256} * 256U);
  double worst_px[4] = {};
  int worst_dn[2] = {};  // G 8 (the default), G 16
  double worst_dp_m = 0.0;
  for (int d = 0; d < 9; ++d) {
    const double az = d * 45.0 * kDeg;
    const double r = d < 8 ? 3200.0 : 4200.0;
    double err_e = 0.0;
    double err_g = 0.0;
    tv::PosePrior prior;
    bsp::CameraPose truth;
    bsp::Work we;
    bsp::Work wg;
    const tv::CoarseFrameResult e = run_coarse(w, 4000.0, r * std::sin(az), r * std::cos(az), w.coarse_lit, err_e,
                                               prior, truth, exact_p, &we);
    const tv::CoarseFrameResult g = run_coarse(w, 4000.0, r * std::sin(az), r * std::cos(az), w.coarse_lit, err_g,
                                               prior, truth, grid_p, &wg);
    ASSERT_TRUE(e.accepted && g.accepted) << "seed " << this->kSeed << " direction " << d;
    // The same footprint geometry both ways; only the resampling differs.
    for (int k = 0; k < 9; ++k) EXPECT_EQ(bits(g.footprint_h.h[k]), bits(e.footprint_h.h[k]));
    const double dp_m = std::hypot(g.dp_m[0] - e.dp_m[0], g.dp_m[1] - e.dp_m[1]);
    worst_dp_m = std::max(worst_dp_m, dp_m);
    std::printf("[ seed %llu   4000 m coarse    ] direction %d: error after dp exact warp %.2f m, grid warp %.2f m "
                "(dp %.2f m apart)\n",
                static_cast<unsigned long long>(this->kSeed), d, err_e, err_g, dp_m);
    EXPECT_LT(err_g, 25.0) << "direction " << d;
    EXPECT_LT(dp_m, 0.5) << "direction " << d;  // a hundredth of a 48 m coarse-scale pixel (measured <= 0.07)
    const tv::ConstImageU8 frame = w.view(w.frame_at(4000.0));
    for (std::int32_t gp = 8, i = 0; gp <= 32; gp *= 2, ++i) {
      const tv::detail::GridShape shape = tv::detail::grid_shape(gp, 256, 256);
      auto visit = [&](std::int32_t x, std::int32_t y, std::int32_t xq, std::int32_t yq, bool usable) {
        ASSERT_TRUE(usable);
        double u = 0.0;
        double v = 0.0;
        ASSERT_TRUE(tv::apply_homography(g.footprint_h, x, y, u, v));
        worst_px[i] = std::max(worst_px[i], std::max(std::fabs(xq / 65536.0 - u), std::fabs(yq / 65536.0 - v)));
      };
      bsp::Work work;
      tv::detail::walk_grid(g.footprint_h, shape, 256, 256, visit, work);
    }
    std::int32_t out_e = -1;
    bsp::Work work;
    ASSERT_EQ(tv::warp_homography(frame, g.footprint_h, {exact_px.data(), 256, 256, 256}, 0, out_e, work),
              tv::Status::kOk);
    EXPECT_EQ(out_e, 0);
    for (std::int32_t gp = 8, i = 0; gp <= 16; gp *= 2, ++i) {
      std::int32_t out_g = -1;
      ASSERT_EQ(tv::warp_homography_grid(frame, g.footprint_h, gp, {grid_px.data(), 256, 256, 256}, 0, out_g, work),
                tv::Status::kOk);
      EXPECT_EQ(out_g, 0);
      for (std::size_t k = 0; k < exact_px.size(); ++k)
        worst_dn[i] = std::max(worst_dn[i], std::abs(exact_px[k] - grid_px[k]));
    }
    if (d == 0) {
      std::printf("[ seed %llu   4000 m coarse    ] coarse_frame TILE64 cycles (transform): exact warp %.1f M, "
                  "grid warp %.1f M\n",
                  static_cast<unsigned long long>(this->kSeed),
                  static_cast<double>(bsp::cost_of(bsp::kTile64, we)) / 1e6,
                  static_cast<double>(bsp::cost_of(bsp::kTile64, wg)) / 1e6);
    }
  }
  std::printf("[ seed %llu   4000 m coarse    ] grid warp source coordinates within %.5f px (G 8), %.5f (G 16), "
              "%.5f (G 32); pixels within %d DN (G 8), %d DN (G 16); dp within %.2f m of the exact warp's\n",
              static_cast<unsigned long long>(this->kSeed), worst_px[0], worst_px[1], worst_px[2], worst_dn[0],
              worst_dn[1], worst_dp_m);
  // Measured: 0.0032 px at G 8, 0.013 at G 16 (2 DN: the footprint samples sharp rendered detail).
  EXPECT_LT(worst_px[0], 1.0 / 256.0);
  EXPECT_LT(worst_px[1], 1.0 / 64.0);
  EXPECT_LE(worst_dn[0], 1);
}

TYPED_TEST(Rendered, CoarseFootprintLargerThanTheFrameIsNotSearched) {
  // At 1200 m the frame covers ~2.4 km: a 256 px x 12 m footprint (3 km) does not fit.
  World& w = *this->w_;
  double err = 0.0;
  tv::PosePrior prior;
  bsp::CameraPose truth;
  const tv::CoarseFrameResult c = run_coarse(w, 1200.0, 500.0, 0.0, w.coarse_lit, err, prior, truth);
  EXPECT_FALSE(c.accepted);
  EXPECT_GT(c.outside_px, 0);
}

TYPED_TEST(Rendered, BadInputsAreRefused) {
  World& w = *this->w_;
  static tv::LandmarkWorkspace lws;
  static tv::CoarseFrameWorkspace cws;
  double t = 0.0;
  const bsp::CameraPose truth = w.truth_at(4000.0, &t);
  const tv::PosePrior good = tight_prior(truth, t);
  const tv::ConstImageU8 frame = w.view(w.frame_at(4000.0));
  trn::Match m{};
  bool ok = true;
  tv::LandmarkDiag diag;
  bsp::Work work;
  const auto match = [&](tv::ConstImageU8 f, const tv::PosePrior& pr, std::uint16_t index, std::int32_t radius,
                         const tv::LandmarkMatchParams& mp) {
    ok = true;
    const tv::Status st = tv::match_landmark(f, w.cam, pr, w.fine, *w.table, index, radius, mp, lws, m, ok, diag, work);
    EXPECT_FALSE(ok);
    return st;
  };
  const tv::LandmarkMatchParams mp;
  EXPECT_EQ(match(frame.sub(0, 0, 512, 512), good, 0, 8, mp), tv::Status::kBadInput);  // not the camera's size
  EXPECT_EQ(match(tv::ConstImageU8{}, good, 0, 8, mp), tv::Status::kBadInput);
  EXPECT_EQ(match(frame, good, static_cast<std::uint16_t>(w.table->count), 8, mp), tv::Status::kBadInput);
  EXPECT_EQ(match(frame, good, 0, 0, mp), tv::Status::kBadInput);
  EXPECT_EQ(match(frame, good, 0, tv::kFineMaxSearchPx + 1, mp), tv::Status::kBadInput);
  tv::PosePrior bad = good;
  bad.q_mb[0] = std::nan("");
  EXPECT_EQ(match(frame, bad, 0, 8, mp), tv::Status::kBadInput);
  tv::LandmarkMatchParams bad_mp;
  bad_mp.sigma_map_px = 0.0;
  EXPECT_EQ(match(frame, good, 0, 8, bad_mp), tv::Status::kBadInput);
  bad_mp = tv::LandmarkMatchParams{};
  bad_mp.subsamples = tv::kMaxSubsamples + 1;
  EXPECT_EQ(match(frame, good, 0, 8, bad_mp), tv::Status::kBadInput);
  // A landmark outside the frame is not an error: not matched, the window's misses counted.
  std::uint16_t far = 0;
  for (std::uint32_t i = 0; i < w.table->count; ++i) {
    const tv::Landmark& lm = w.table->items[i];
    if (std::hypot(lm.p_m[0] - truth.r_m.x(), lm.p_m[1] - truth.r_m.y()) > 6000.0) {
      far = static_cast<std::uint16_t>(i);
      break;
    }
  }
  EXPECT_EQ(match(frame, good, far, 8, mp), tv::Status::kOk);
  EXPECT_GT(diag.outside_px, 0);
  // The short form uses the default params.
  ok = true;
  EXPECT_EQ(tv::match_landmark(frame.sub(0, 0, 512, 512), w.cam, good, w.fine, *w.table, 0, 8, lws, m, ok, diag, work),
            tv::Status::kBadInput);
  EXPECT_FALSE(ok);

  tv::CoarseFrameResult r;
  const tv::CoarseFrameParams cp;
  EXPECT_EQ(tv::coarse_frame(frame.sub(0, 0, 512, 512), w.cam, good, w.coarse, cp, cws, r, work),
            tv::Status::kBadInput);
  tv::MapView no_elev = w.coarse;
  no_elev.elevation = nullptr;
  EXPECT_EQ(tv::coarse_frame(frame, w.cam, good, no_elev, cp, cws, r, work), tv::Status::kBadInput);
  tv::CoarseFrameParams big = cp;
  big.search_px = w.coarse.image.width + 1;  // not enough map
  EXPECT_EQ(tv::coarse_frame(frame, w.cam, good, w.coarse, big, cws, r, work), tv::Status::kBadInput);
  big = cp;
  big.footprint_px = 1100;
  big.search_px = 1200;
  EXPECT_EQ(tv::coarse_frame(frame, w.cam, good, w.coarse, big, cws, r, work), tv::Status::kTooLarge);
  big = cp;
  big.search_px = 1100;  // 275 decimated pixels > kCoarseMaxPx
  EXPECT_EQ(tv::coarse_frame(frame, w.cam, good, w.coarse, big, cws, r, work), tv::Status::kTooLarge);
  big = cp;
  big.footprint_px = 200;  // 50 decimated pixels < the 64 px template
  EXPECT_EQ(tv::coarse_frame(frame, w.cam, good, w.coarse, big, cws, r, work), tv::Status::kBadInput);
  tv::PosePrior up = good;
  const Eigen::Quaterniond flipped = truth.q_mb * Eigen::Quaterniond(Eigen::AngleAxisd(kPi, Eigen::Vector3d::UnitX()));
  up.q_mb[0] = flipped.w();
  up.q_mb[1] = flipped.x();
  up.q_mb[2] = flipped.y();
  up.q_mb[3] = flipped.z();
  EXPECT_EQ(tv::coarse_frame(frame, w.cam, up, w.coarse, cp, cws, r, work), tv::Status::kBadInput);
  tv::PosePrior below = good;
  below.p_m[2] = -500.0;
  EXPECT_EQ(tv::coarse_frame(frame, w.cam, below, w.coarse, cp, cws, r, work), tv::Status::kBadInput);
  EXPECT_FALSE(r.accepted);

  tv::MapView v;
  EXPECT_EQ(tv::map_view(nullptr, 0, v), tv::Status::kBadInput);
  EXPECT_EQ(tv::map_view(w.product, bsp::kMapLayers, v), tv::Status::kBadInput);
  EXPECT_EQ(v.image.data, nullptr);
}

TYPED_TEST(Rendered, MapViewsDescribeTheProduct) {
  World& w = *this->w_;
  const bsp::MapLayerHeader& h = w.product->layers[bsp::kMapLayerFine];
  EXPECT_EQ(w.fine.image.width, static_cast<std::int32_t>(h.width_px));
  EXPECT_EQ(w.fine.image.data, bsp::map_image(w.product, bsp::kMapLayerFine));
  EXPECT_EQ(w.fine.geo.m_per_px, h.m_per_px);
  EXPECT_EQ(w.coarse.geo.m_per_px, w.product->layers[bsp::kMapLayerCoarse].m_per_px);
  double sun[3];
  tv::sun_direction(w.product->sun_azimuth_deg, w.product->sun_elevation_deg, sun);
  EXPECT_EQ(w.fine.sun_m[0], sun[0]);
  EXPECT_EQ(w.fine.sun_m[2], sun[2]);
  // Elevation lookups agree with the product's pixel positions.
  for (std::uint32_t k = 0; k < 50; ++k) {
    const std::uint32_t col = 100U + 37U * k;
    const std::uint32_t row = 200U + 29U * k;
    double p[3];
    bsp::map_pixel_position(w.product, bsp::kMapLayerFine, col, row, p);
    EXPECT_DOUBLE_EQ(tv::map_elevation_m(w.fine, col, row), p[2]);
  }
}

}  // namespace
