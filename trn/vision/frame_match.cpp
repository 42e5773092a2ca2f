/**
 * @file frame_match.cpp
 * @brief match_landmark(): one landmark's fine match on a frame, turned into a trn::Match.
 *
 * 1. Template: the landmark's kFineTemplatePx patch of the map layer, relit
 *    to the descent sun when the map view knows both suns (relight_region()).
 * 2. Search: the frame resampled on the landmark's window (frame_window.hpp)
 *    of radius r, each pixel lifted by its map height (ortho.hpp) and
 *    box-filtered by sub-sampling when the image is finer than the map;
 *    fine_match() over it. The peak's offset d from the window centre is the
 *    prior's error near the landmark, in map pixels.
 * 3. Refinement: a window of radius kRefineRadiusPx whose plane is shifted by
 *    d but whose pixels carry the relief of the landmark's own neighbourhood,
 *    where the frame shows it; fine_match() again. With an exact prior
 *    (d = 0) it repeats step 2 on a smaller window.
 * 4. Measurement: the template centre lies at window position (x, y); the
 *    frame point sampled there, (u, v) = H (x, y, 1) + dz g, is where the
 *    landmark is seen, whatever the prior's error. w_c is its unit ray.
 */
#include "trn/vision/frame.hpp"

#include "bsp_tile64/api/port.hpp"
#include "trn/vision/frame_window.hpp"
#include "trn/vision/ortho.hpp"
#include "trn/vision/pose_geometry.hpp"

#include <array>
#include <cmath>

namespace trn::vision {

namespace {

using detail::kHalfTemplate;
using detail::make_window;
using detail::nonzero3;
using detail::Window;

/** Search radius of the refinement pass: the residual offset is a fraction of a pixel; the peak needs an edge margin. */
constexpr std::int32_t kRefineRadiusPx = 3;

bool match_params_ok(const LandmarkMatchParams& mp) noexcept {
  return std::isfinite(mp.sigma_map_px) && mp.sigma_map_px > 0.0 && std::isfinite(mp.sigma_floor_px) &&
         mp.sigma_floor_px >= 0.0 && mp.subsamples >= 0 && mp.subsamples <= kMaxSubsamples;
}

/** The landmark's map patch, relit into @p ws.tmpl when the view knows both suns and the params allow. */
bool landmark_template(const MapView& map, const Landmark& lm, const LandmarkMatchParams& mp, LandmarkWorkspace& ws,
                       ConstImageU8& tmpl, bsp::Work& work) noexcept {
  tmpl = map.image.sub(lm.col_px - kHalfTemplate, lm.row_px - kHalfTemplate, kFineTemplatePx, kFineTemplatePx);
  if (!mp.relight || !nonzero3(map.descent_sun_m) || !nonzero3(map.sun_m)) {
    return tmpl.valid();
  }
  if (!ws.tmpl.resize(kFineTemplatePx, kFineTemplatePx) ||
      relight_region(map, lm.col_px - kHalfTemplate, lm.row_px - kHalfTemplate, map.descent_sun_m, ws.tmpl.view(),
                     work) != Status::kOk) {
    return false;
  }
  tmpl = ws.tmpl.cview();
  return true;
}

/** Samples per window pixel and axis: mp.subsamples, or the image pixels per map pixel at the centre, rounded. */
std::int32_t subsamples(const Window& win, const LandmarkMatchParams& mp, bsp::Work& work) noexcept {
  if (mp.subsamples > 0) {
    return mp.subsamples;
  }
  const double c = 0.5 * static_cast<double>(win.side - 1);
  const double scale = homography_scale(win.h, c, c, work);
  const std::int32_t sub = scale < 1.5 ? 1 : static_cast<std::int32_t>(std::lround(scale));
  return sub > kMaxSubsamples ? kMaxSubsamples : sub;
}

/**
 * Resamples the frame on @p win and correlates @p tmpl in it.
 * @return as fine_match(); kOk with @p out not accepted when a window pixel fell
 *         outside the frame (fill values would bias the correlation).
 */
Status search(ConstImageU8 frame, const MapView& map, const Window& win, ConstImageU8 tmpl, std::int32_t sub,
              const LandmarkMatchParams& mp, LandmarkWorkspace& ws, MatchResult& out, std::int32_t& outside_px,
              bsp::Work& work) noexcept {
  out = MatchResult{};
  if (!ws.window.resize(win.side, win.side)) {
    return Status::kBadInput;
  }
  Status st = Status::kOk;
  if (map.elevation == nullptr) {
    st = warp_homography(frame, win.h, ws.window.view(), 0U, outside_px, work);
  } else {
    GridHeights gh;
    gh.first = map.elevation + static_cast<std::int64_t>(win.row0) * map.image.width + win.col0;
    gh.stride = map.image.width;
    gh.scale_m = map.elevation_scale_m;
    gh.plane_z_m = win.z0_m;
    st = warp_terrain(frame, win.h, win.g, gh, sub, ws.window.view(), 0U, outside_px, work);
  }
  if (st != Status::kOk || outside_px > 0) {
    return st;
  }
  return fine_match(tmpl, ws.window.cview(), mp.quality, ws.corr, out, work);
}

/** Adds the checks of correlation pass @p r to @p d. */
void note_checks(const MatchResult& r, LandmarkDiag& d) noexcept {
  d.recomputes += r.recomputes;
  d.check_failed = d.check_failed || r.check_failed;
  if (d.first_check == CorrelationCheck::kNone) {
    d.first_check = r.first_check;
  }
}

/** Fills @p out from the accepted peak of @p r in window @p win. False when it maps behind the camera. */
bool make_match(const bsp::CameraModel& cam, const MapView& map, const Landmark& lm, std::uint16_t index,
                const Window& win, const MatchResult& r, const LandmarkMatchParams& mp, double t_s, Match& out,
                bsp::Work& work) noexcept {
  // The template's centre lies at window position (x + h, y + h).
  const double xw = r.x_px + kHalfTemplate;
  const double yw = r.y_px + kHalfTemplate;
  double u = 0.0;
  double v = 0.0;
  if (!detail::window_to_image(map, win, xw, yw, u, v)) {
    return false;
  }
  // The position as found is a published result: where a tile that matches wrong is injected.
  std::array<double, 2> uv{u, v};
  (void)bsp::publish_filter(kMatchPositionChannel, uv.data(), sizeof uv);
  u = uv[0];
  v = uv[1];
  pixel_ray(cam, u, v, out.w_c, work);
  for (std::int32_t k = 0; k < 3; ++k) {
    out.p_m[k] = lm.p_m[k];
  }
  out.u_px = u;
  out.v_px = v;
  const double sigma = mp.sigma_map_px * homography_scale(win.h, xw, yw, work);
  out.sigma_px = sigma > mp.sigma_floor_px ? sigma : mp.sigma_floor_px;
  out.quality = r.peak.score;
  out.landmark = index;
  out.tile = 0U;
  out.frame = 0U;
  out.t_s = t_s;
  work.flops += 40U;
  work.fdivs += 2U;
  return true;
}

}  // namespace

Status match_landmark(ConstImageU8 frame, const bsp::CameraModel& cam, const PosePrior& prior, const MapView& map,
                      const LandmarkTable& table, std::uint16_t index, std::int32_t radius_px,
                      LandmarkWorkspace& ws, Match& out, bool& accepted, LandmarkDiag& diag,
                      bsp::Work& work) noexcept {
  return match_landmark(frame, cam, prior, map, table, index, radius_px, LandmarkMatchParams{}, ws, out, accepted,
                        diag, work);
}

Status match_landmark(ConstImageU8 frame, const bsp::CameraModel& cam, const PosePrior& prior, const MapView& map,
                      const LandmarkTable& table, std::uint16_t index, std::int32_t radius_px,
                      const LandmarkMatchParams& mp, LandmarkWorkspace& ws, Match& out, bool& accepted,
                      LandmarkDiag& diag, bsp::Work& work) noexcept {
  accepted = false;
  diag = LandmarkDiag{};
  PoseGeometry pose;
  Window win;
  ConstImageU8 tmpl;
  if (!detail::frame_matches(frame, cam) || !map.image.valid() || !(map.geo.m_per_px > 0.0) ||
      index >= table.count || table.count > kMaxLandmarks || radius_px < 1 || radius_px > kFineMaxSearchPx ||
      !match_params_ok(mp) || !detail::prior_pose(prior, cam, pose, work) ||
      !make_window(cam, pose, map, table.items[index], radius_px, mp.terrain, 0, 0, win, work) ||
      !landmark_template(map, table.items[index], mp, ws, tmpl, work)) {
    return Status::kBadInput;
  }
  const std::int32_t sub = subsamples(win, mp, work);
  Status st = search(frame, map, win, tmpl, sub, mp, ws, diag.search, diag.outside_px, work);
  note_checks(diag.search, diag);
  diag.fine = diag.search;
  if (st != Status::kOk || !diag.search.accepted()) {
    return st;
  }
  // Refinement around the peak, with the landmark's relief where the frame shows it.
  diag.shift_px[0] = diag.search.x_px - radius_px;
  diag.shift_px[1] = diag.search.y_px - radius_px;
  if (!make_window(cam, pose, map, table.items[index], kRefineRadiusPx, mp.terrain, diag.shift_px[0],
                   diag.shift_px[1], win, work)) {
    return Status::kBadInput;
  }
  st = search(frame, map, win, tmpl, sub, mp, ws, diag.fine, diag.outside_px, work);
  note_checks(diag.fine, diag);
  if (st != Status::kOk || !diag.fine.accepted()) {
    return st;
  }
  accepted = make_match(cam, map, table.items[index], index, win, diag.fine, mp, prior.t_s, out, work);
  return Status::kOk;
}

}  // namespace trn::vision
