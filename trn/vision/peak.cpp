/**
 * @file peak.cpp
 * @brief Peak search, parabola refinement and the quality checks (see peak.hpp).
 */
#include "trn/vision/peak.hpp"

namespace trn::vision {

namespace detail {
namespace {

/** True when (x, y) is no lower than any of its existing 8 neighbours. */
bool is_local_max(ConstImageF32 s, std::int32_t x, std::int32_t y) noexcept {
  const float v = s.at(x, y);
  for (std::int32_t dy = -1; dy <= 1; ++dy) {
    for (std::int32_t dx = -1; dx <= 1; ++dx) {
      if ((dx != 0 || dy != 0) && s.contains(x + dx, y + dy) && s.at(x + dx, y + dy) > v) {
        return false;
      }
    }
  }
  return true;
}

/** Highest local maximum farther than @p radius from (px, py); -1 when there is none. */
float second_peak(ConstImageF32 s, std::int32_t px, std::int32_t py, std::int32_t radius) noexcept {
  float best = -1.0F;
  const std::int64_t r2 = static_cast<std::int64_t>(radius) * radius;
  for (std::int32_t y = 0; y < s.height; ++y) {
    for (std::int32_t x = 0; x < s.width; ++x) {
      const std::int64_t dx = x - px;
      const std::int64_t dy = y - py;
      if (dx * dx + dy * dy > r2 && s.at(x, y) > best && is_local_max(s, x, y)) {
        best = s.at(x, y);
      }
    }
  }
  return best;
}

/** Sub-pixel refinement around the integer peak (neighbours that exist only). */
void refine(ConstImageF32 s, const QualityParams& q, Peak& p) noexcept {
  p.x_px = p.ix;
  p.y_px = p.iy;
  const bool inner = p.ix > 0 && p.iy > 0 && p.ix + 1 < s.width && p.iy + 1 < s.height;
  if (q.subpixel == Subpixel::kParaboloid && inner) {
    double v[9];
    for (std::int32_t j = 0; j < 3; ++j) {
      for (std::int32_t i = 0; i < 3; ++i) {
        v[j * 3 + i] = s.at(p.ix + i - 1, p.iy + j - 1);
      }
    }
    double dx = 0.0;
    double dy = 0.0;
    if (paraboloid_offset(v, dx, dy)) {
      p.x_px += dx;
      p.y_px += dy;
      return;
    }
  }
  if (p.ix > 0 && p.ix + 1 < s.width) {
    p.x_px += parabola_offset(s.at(p.ix - 1, p.iy), p.score, s.at(p.ix + 1, p.iy));
  }
  if (p.iy > 0 && p.iy + 1 < s.height) {
    p.y_px += parabola_offset(s.at(p.ix, p.iy - 1), p.score, s.at(p.ix, p.iy + 1));
  }
}

}  // namespace
}  // namespace detail

bool paraboloid_offset(const double s[9], double& dx, double& dy) noexcept {
  // Least squares on the 3x3 grid {-1, 0, 1}^2: the regressors are orthogonal
  // after centring, so each coefficient is a fixed contrast of the samples.
  const double col_l = s[0] + s[3] + s[6];
  const double col_c = s[1] + s[4] + s[7];
  const double col_r = s[2] + s[5] + s[8];
  const double row_t = s[0] + s[1] + s[2];
  const double row_c = s[3] + s[4] + s[5];
  const double row_b = s[6] + s[7] + s[8];
  const double b = (col_r - col_l) / 6.0;
  const double c = (row_b - row_t) / 6.0;
  const double d = (col_l + col_r - 2.0 * col_c) / 6.0;
  const double f = (row_t + row_b - 2.0 * row_c) / 6.0;
  const double e = (s[8] - s[6] - s[2] + s[0]) / 4.0;
  const double det = 4.0 * d * f - e * e;
  if (!(d < 0.0 && det > 0.0)) {
    return false;  // not a maximum (saddle, ridge or valley)
  }
  const double x = (e * c - 2.0 * f * b) / det;
  const double y = (e * b - 2.0 * d * c) / det;
  if (!(x >= -1.0 && x <= 1.0 && y >= -1.0 && y <= 1.0)) {
    return false;
  }
  dx = x;
  dy = y;
  return true;
}

double parabola_offset(double left, double centre, double right) noexcept {
  const double curv = left - 2.0 * centre + right;
  if (!(curv < 0.0)) {
    return 0.0;  // not a strict maximum along this axis: keep the integer position
  }
  double d = (left - right) / (2.0 * curv);
  d = d > 0.5 ? 0.5 : (d < -0.5 ? -0.5 : d);
  return d;
}

Peak find_peak(ConstImageF32 surface, const QualityParams& q, bsp::Work& work) noexcept {
  Peak p;
  if (!surface.valid()) {
    return p;
  }
  p.score = surface.at(0, 0);
  for (std::int32_t y = 0; y < surface.height; ++y) {
    for (std::int32_t x = 0; x < surface.width; ++x) {
      if (surface.at(x, y) > p.score) {
        p.score = surface.at(x, y);
        p.ix = x;
        p.iy = y;
      }
    }
  }
  detail::refine(surface, q, p);
  p.second = detail::second_peak(surface, p.ix, p.iy, q.exclusion_radius_px);
  const auto positions = static_cast<std::uint64_t>(surface.width) * static_cast<std::uint64_t>(surface.height);
  work.int_ops += positions * 6U;     // max scan, distance test, neighbour compares (typical)
  work.mem_words += positions * 3U;
  work.flops += 40U;
  work.fdivs += 4U;
  const std::int32_t m = q.edge_margin_px;
  if (p.score < q.min_peak) {
    p.reason = Reject::kLowPeak;
  } else if (p.second > q.max_second_ratio * p.score) {
    p.reason = Reject::kAmbiguous;
  } else if (p.ix < m || p.iy < m || p.ix > surface.width - 1 - m || p.iy > surface.height - 1 - m) {
    p.reason = Reject::kOnEdge;
  } else {
    p.reason = Reject::kNone;
  }
  return p;
}

}  // namespace trn::vision
