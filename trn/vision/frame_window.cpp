/**
 * @file frame_window.cpp
 * @brief Input checks and landmark search windows of the per-frame vision (see frame_window.hpp).
 */
#include "trn/vision/frame_window.hpp"

#include <cmath>

namespace trn::vision::detail {

bool finite_nonneg(const double* v, std::int32_t n) noexcept {
  for (std::int32_t i = 0; i < n; ++i) {
    if (!(std::isfinite(v[i]) && v[i] >= 0.0)) {
      return false;
    }
  }
  return true;
}

bool frame_matches(ConstImageU8 frame, const bsp::CameraModel& cam) noexcept {
  return frame.valid() && static_cast<std::uint32_t>(frame.width) == cam.width_px &&
         static_cast<std::uint32_t>(frame.height) == cam.height_px;
}

bool map_ok(const MapView& map) noexcept {
  return map.image.valid() && map.elevation != nullptr && std::isfinite(map.elevation_scale_m) &&
         std::isfinite(map.geo.m_per_px) && map.geo.m_per_px > 0.0 && std::isfinite(map.geo.x0_m) &&
         std::isfinite(map.geo.y0_m);
}

bool nonzero3(const double v[3]) noexcept { return v[0] != 0.0 || v[1] != 0.0 || v[2] != 0.0; }

bool prior_pose(const PosePrior& prior, const bsp::CameraModel& cam, PoseGeometry& pose, bsp::Work& work) noexcept {
  return camera_ok(cam) && make_pose(prior.p_m, prior.q_mb, cam, pose, work);
}

bool make_window(const bsp::CameraModel& cam, const PoseGeometry& pose, const MapView& map, const Landmark& lm,
                 std::int32_t radius_px, bool terrain, double shift_col, double shift_row, Window& out,
                 bsp::Work& work) noexcept {
  const std::int32_t c = kHalfTemplate + radius_px;
  out.side = kFineTemplatePx + 2 * radius_px;
  out.col0 = lm.col_px - c;
  out.row0 = lm.row_px - c;
  out.z0_m = lm.p_m[2];
  if (out.col0 < 0 || out.row0 < 0 || out.col0 > map.image.width - out.side ||
      out.row0 > map.image.height - out.side) {
    return false;
  }
  const double s = map.geo.m_per_px;
  PlaneGrid grid;
  grid.origin_m[0] = lm.p_m[0] + (shift_col - c) * s;  // column 0 lies west of the landmark
  grid.origin_m[1] = lm.p_m[1] - (shift_row - c) * s;  // row 0 lies north of it
  grid.origin_m[2] = lm.p_m[2];
  grid.m_per_px = s;
  out.h = plane_homography(cam, pose, grid, work);
  out.g[0] = 0.0;
  out.g[1] = 0.0;
  out.g[2] = 0.0;
  if (terrain && map.elevation != nullptr) {
    vertical_column(cam, pose, out.g);
  }
  return true;
}

double window_dz(const MapView& map, const Window& win, double x, double y) noexcept {
  if (!nonzero3(win.g)) {
    return 0.0;
  }
  return map_elevation_m(map, win.col0 + x, win.row0 + y) - win.z0_m;
}

bool window_to_image(const MapView& map, const Window& win, double x, double y, double& u, double& v) noexcept {
  return apply_lifted(win.h, win.g, window_dz(map, win, x, y), x, y, u, v);
}

bool window_inside(const bsp::CameraModel& cam, const MapView& map, const Window& win, bsp::Work& work) noexcept {
  const auto last = static_cast<double>(win.side - 1);
  const double xs[4] = {0.0, last, 0.0, last};
  const double ys[4] = {0.0, 0.0, last, last};
  const double umax = static_cast<double>(cam.width_px) - 2.0;
  const double vmax = static_cast<double>(cam.height_px) - 2.0;
  work.flops += 120U;  // four lifted corners
  work.fdivs += 8U;
  for (std::int32_t k = 0; k < 4; ++k) {
    double u = 0.0;
    double v = 0.0;
    if (!window_to_image(map, win, xs[k], ys[k], u, v) || !(u >= 1.0 && v >= 1.0 && u <= umax && v <= vmax)) {
      return false;
    }
  }
  return true;
}

}  // namespace trn::vision::detail
