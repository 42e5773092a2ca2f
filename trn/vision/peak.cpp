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

}  // namespace
}  // namespace detail

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
  p.x_px = p.ix;
  p.y_px = p.iy;
  if (p.ix > 0 && p.ix + 1 < surface.width) {
    p.x_px += parabola_offset(surface.at(p.ix - 1, p.iy), p.score, surface.at(p.ix + 1, p.iy));
  }
  if (p.iy > 0 && p.iy + 1 < surface.height) {
    p.y_px += parabola_offset(surface.at(p.ix, p.iy - 1), p.score, surface.at(p.ix, p.iy + 1));
  }
  p.second = detail::second_peak(surface, p.ix, p.iy, q.exclusion_radius_px);
  const auto positions = static_cast<std::uint64_t>(surface.width) * static_cast<std::uint64_t>(surface.height);
  work.int_ops += positions * 6U;     // max scan, distance test, neighbour compares (typical)
  work.mem_words += positions * 3U;
  work.flops += 12U;
  work.fdivs += 2U;
  const std::int32_t m = q.edge_margin_px;
  if (p.score < q.min_peak) {
    p.reason = Reject::kLowPeak;
  } else if (p.ix < m || p.iy < m || p.ix > surface.width - 1 - m || p.iy > surface.height - 1 - m) {
    p.reason = Reject::kOnEdge;
  } else if (p.second > q.max_second_ratio * p.score) {
    p.reason = Reject::kAmbiguous;
  } else {
    p.reason = Reject::kNone;
  }
  return p;
}

}  // namespace trn::vision
