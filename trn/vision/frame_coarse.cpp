/**
 * @file frame_coarse.cpp
 * @brief coarse_frame(): the image centre warped into coarse-map geometry and searched over the map around the prior.
 *
 * Ground point: the optical axis of the prior pose meets the horizontal plane
 * at the map's mean elevation around the prior's nadir (the true ground is
 * unknown at km-level error; a height error dz only scales the footprint by
 * dz / altitude and is removed from the result, see coarse_solution()).
 * The footprint (footprint_px square of the layer's pixels, north-up, on the
 * map pixel grid, centred on the map pixel nearest the ground point) is
 * resampled from the frame through the plane's homography (exact at nodes every
 * warp_grid_px pixels, fixed point between: warp_grid.hpp); the search region
 * (search_px square centred on the same pixel, clamped to the map) is a view
 * of the layer, not a copy. coarse_prepare() decimates both; the correlation runs
 * here (coarse_frame()) or in bands on other tiles (coarse_frame_prepare(), _finish()).
 */
#include "trn/vision/frame.hpp"

#include "trn/vision/frame_window.hpp"
#include "trn/vision/pose_geometry.hpp"
#include "trn/vision/warp_grid.hpp"

#include <cmath>

namespace trn::vision {

namespace {

using detail::frame_matches;
using detail::map_ok;
using detail::prior_pose;

/** Map pixel (column, row) of map-frame (x, y), fractional. */
void map_pixel_of(const MapGeometry& geo, double x, double y, double& col, double& row) noexcept {
  col = (x - geo.x0_m) / geo.m_per_px;
  row = (geo.y0_m - y) / geo.m_per_px;
}

/**
 * Mean map elevation over the side x side pixels centred on (col, row) (clamped
 * to the layer), sampled every 8 pixels: the height the footprint is warped onto.
 */
double mean_elevation_m(const MapView& map, double col, double row, std::int32_t side, bsp::Work& work) noexcept {
  constexpr std::int32_t kStep = 8;
  const std::int32_t steps = side / kStep > 1 ? side / kStep : 1;
  const double c0 = col - 0.5 * side;
  const double r0 = row - 0.5 * side;
  double sum = 0.0;
  for (std::int32_t j = 0; j < steps; ++j) {
    for (std::int32_t i = 0; i < steps; ++i) {
      sum += map_elevation_m(map, c0 + (i + 0.5) * kStep, r0 + (j + 0.5) * kStep);
    }
  }
  const auto samples = static_cast<std::uint64_t>(steps) * static_cast<std::uint64_t>(steps);
  work.flops += samples * 14U;
  work.mem_words += samples * 4U;
  return sum / static_cast<double>(samples);
}

bool coarse_params_ok(const CoarseFrameParams& p, const MapView& map) noexcept {
  return p.coarse.factor >= 1 && p.coarse.factor <= kCoarseMaxFactor && p.footprint_px >= 2 &&
         p.footprint_px / p.coarse.factor >= p.coarse.template_px && p.search_px >= p.footprint_px &&
         p.search_px <= map.image.width && p.search_px <= map.image.height && std::isfinite(p.sigma_coarse_px) &&
         p.sigma_coarse_px > 0.0 &&
         (p.warp_grid_px == 0 || detail::grid_shape(p.warp_grid_px, 1, 1).status == Status::kOk);
}

/** Where the footprint and the search region lie in the map, in whole map pixels. */
struct CoarseLayout {
  std::int32_t foot_col = 0;    ///< map column of footprint pixel (0, 0) at the prior
  std::int32_t foot_row = 0;
  std::int32_t search_col = 0;  ///< map column of search-region pixel (0, 0)
  std::int32_t search_row = 0;
};

/**
 * The prior's ground point: the optical axis meets the plane z = @p z_ref at
 * c + t a (a = R_MC e_z, t = (z_ref - c_z) / a_z); the footprint is centred on
 * the map pixel nearest to it, the search region on the same pixel, clamped to the map.
 * @return false when the axis does not point down to the plane.
 */
bool coarse_layout(const PoseGeometry& pose, const MapView& map, const CoarseFrameParams& p, double z_ref,
                   CoarseLayout& out, bsp::Work& work) noexcept {
  const double ez[3] = {0.0, 0.0, 1.0};
  double a[3];
  to_map(pose, ez, a);
  work.flops += 20U;
  work.fdivs += 3U;
  const double drop = z_ref - pose.c_m[2];
  if (!(a[2] < -0.1) || !(drop < 0.0)) {
    return false;  // axis within ~6 deg of the horizon or above it, or camera below the plane
  }
  const double t = drop / a[2];
  double col = 0.0;
  double row = 0.0;
  map_pixel_of(map.geo, pose.c_m[0] + t * a[0], pose.c_m[1] + t * a[1], col, row);
  const double lim = 1e6;
  if (!(std::fabs(col) < lim && std::fabs(row) < lim)) {
    return false;
  }
  const auto gc = static_cast<std::int32_t>(std::lround(col));
  const auto gr = static_cast<std::int32_t>(std::lround(row));
  out.foot_col = gc - p.footprint_px / 2;
  out.foot_row = gr - p.footprint_px / 2;
  const std::int32_t sc = gc - p.search_px / 2;
  const std::int32_t sr = gr - p.search_px / 2;
  const std::int32_t sc_max = map.image.width - p.search_px;
  const std::int32_t sr_max = map.image.height - p.search_px;
  out.search_col = sc < 0 ? 0 : (sc > sc_max ? sc_max : sc);
  out.search_row = sr < 0 ? 0 : (sr > sr_max ? sr_max : sr);
  return true;
}

/**
 * The accepted coarse offset as a position correction and a Match of the
 * footprint centre. Footprint pixel (i, j) was sampled where the prior sees the
 * plane point of map pixel (foot_col + i, foot_row + j); the correlation found
 * its content at map pixel (search_col + x + i, search_row + y + j), i.e. at Q.
 * The image ray r through the footprint centre therefore hits the terrain at
 * (Q, z(Q)). With the attitude and the altitude of the prior kept, the camera
 * that sees it there is at (Q, z(Q)) - t' r with t' = (z(Q) - c_z) / r_z, so
 * dp = Q - t' r_xy - c_xy (= Q - P when z(Q) equals the plane's height).
 */
void coarse_solution(const bsp::CameraModel& cam, const PoseGeometry& pose, const MapView& map,
                     const CoarseFrameParams& p, std::int32_t search_col, std::int32_t search_row, const Homography& h,
                     CoarseFrameResult& out, bsp::Work& work) noexcept {
  const double fc = 0.5 * static_cast<double>(p.footprint_px - 1);
  double u = 0.0;
  double v = 0.0;
  if (!apply_homography(h, fc, fc, u, v)) {
    return;
  }
  const double qc = search_col + out.coarse.x_px + fc;  // map pixel of the centre's content
  const double qr = search_row + out.coarse.y_px + fc;
  Match& m = out.match;
  m.p_m[0] = map.geo.x0_m + qc * map.geo.m_per_px;
  m.p_m[1] = map.geo.y0_m - qr * map.geo.m_per_px;
  m.p_m[2] = map_elevation_m(map, qc, qr);
  pixel_ray(cam, u, v, m.w_c, work);
  double r[3];
  to_map(pose, m.w_c, r);
  if (!(r[2] < -1e-6)) {
    return;  // the centre ray must point down (it does near the axis the layout checked)
  }
  const double tq = (m.p_m[2] - pose.c_m[2]) / r[2];
  out.dp_m[0] = m.p_m[0] - tq * r[0] - pose.c_m[0];
  out.dp_m[1] = m.p_m[1] - tq * r[1] - pose.c_m[1];
  const double coarse_m = p.sigma_coarse_px * p.coarse.factor * map.geo.m_per_px;
  out.sigma_m = coarse_m;
  m.u_px = u;
  m.v_px = v;
  m.sigma_px = p.sigma_coarse_px * p.coarse.factor * homography_scale(h, fc, fc, work);
  m.quality = out.coarse.match.peak.score;
  m.landmark = kCoarseLandmark;
  out.accepted = true;
  work.flops += 40U;
  work.fdivs += 2U;
}

}  // namespace

Status coarse_frame_prepare(ConstImageU8 frame, const bsp::CameraModel& cam, const PosePrior& prior,
                            const MapView& map, const CoarseFrameParams& p, CoarseFrameWorkspace& ws,
                            CoarseFrameStage& stage, CoarseFrameResult& out, bsp::Work& work) noexcept {
  out = CoarseFrameResult{};
  stage = CoarseFrameStage{};
  PoseGeometry pose;
  if (!frame_matches(frame, cam) || !map_ok(map) || !coarse_params_ok(p, map) ||
      !prior_pose(prior, cam, pose, work)) {
    return Status::kBadInput;
  }
  if (p.footprint_px > ws.footprint.kMaxWidth) {
    return Status::kTooLarge;
  }
  // Ground height: unknown at km-level error, so the map's mean elevation around the prior's nadir.
  double col = 0.0;
  double row = 0.0;
  map_pixel_of(map.geo, pose.c_m[0], pose.c_m[1], col, row);
  out.ground_z_m = mean_elevation_m(map, col, row, p.footprint_px, work);
  CoarseLayout lay;
  if (!coarse_layout(pose, map, p, out.ground_z_m, lay, work) ||
      !ws.footprint.resize(p.footprint_px, p.footprint_px)) {
    return Status::kBadInput;
  }
  PlaneGrid grid;
  grid.origin_m[0] = map.geo.x0_m + lay.foot_col * map.geo.m_per_px;
  grid.origin_m[1] = map.geo.y0_m - lay.foot_row * map.geo.m_per_px;
  grid.origin_m[2] = out.ground_z_m;
  grid.m_per_px = map.geo.m_per_px;
  const Homography h = plane_homography(cam, pose, grid, work);
  out.footprint_h = h;
  // The grid warp stays within 1/256 px and 1 DN of the exact one on the descent's footprints
  // at 8 px spacing (tests/trn/vision_frame/rendered_test.cpp), for ~4 % of its soft-float cost.
  Status st = p.warp_grid_px == 0
                  ? warp_homography(frame, h, ws.footprint.view(), 0U, out.outside_px, work)
                  : warp_homography_grid(frame, h, p.warp_grid_px, ws.footprint.view(), 0U, out.outside_px, work);
  if (st != Status::kOk || out.outside_px > 0) {
    return st;  // a footprint the frame does not cover is not searched
  }
  const ConstImageU8 region = map.image.sub(lay.search_col, lay.search_row, p.search_px, p.search_px);
  st = coarse_prepare(region, ws.footprint.cview(), p.coarse, ws.coarse, stage.prep, work);
  if (st != Status::kOk) {
    return st;
  }
  stage.search = true;
  stage.pose = pose;
  stage.t_s = prior.t_s;
  stage.search_col = lay.search_col;
  stage.search_row = lay.search_row;
  return Status::kOk;
}

void coarse_frame_finish(const bsp::CameraModel& cam, const MapView& map, const CoarseFrameParams& p,
                         const CoarseFrameStage& stage, const MatchResult& m, CoarseFrameResult& out,
                         bsp::Work& work) noexcept {
  coarse_result(stage.prep, p.coarse, m, out.coarse);
  if (!stage.search || !out.coarse.accepted()) {
    return;
  }
  out.match.t_s = stage.t_s;
  coarse_solution(cam, stage.pose, map, p, stage.search_col, stage.search_row, out.footprint_h, out, work);
}

Status coarse_frame(ConstImageU8 frame, const bsp::CameraModel& cam, const PosePrior& prior, const MapView& map,
                    const CoarseFrameParams& p, CoarseFrameWorkspace& ws, CoarseFrameResult& out,
                    bsp::Work& work) noexcept {
  CoarseFrameStage stage;
  Status st = coarse_frame_prepare(frame, cam, prior, map, p, ws, stage, out, work);
  if (st != Status::kOk || !stage.search) {
    return st;
  }
  CorrelatorBuffers buf = ws.coarse.corr.buffers();
  buf.transform = ws.coarse.transform.buffers();
  MatchResult m;
  st = correlate(stage.prep.tmpl, stage.prep.window, p.coarse.quality, buf, m, work, CorrelationTaps{}, p.coarse.method);
  if (st != Status::kOk) {
    out.coarse.match = m;
    return st;
  }
  coarse_frame_finish(cam, map, p, stage, m, out, work);
  return Status::kOk;
}

}  // namespace trn::vision
