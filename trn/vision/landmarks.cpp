/**
 * @file landmarks.cpp
 * @brief Landmark selection by corner strength with grid bucketing and suppression.
 */
#include "trn/vision/landmarks.hpp"

#include <cmath>

namespace trn::vision {

void patch_strength(ConstImageU8 map, std::int32_t col, std::int32_t row, std::int32_t patch_px, float& corner,
                    float& stddev, bsp::Work& work) noexcept {
  const std::int32_t h = patch_px / 2;
  std::int64_t sxx = 0;
  std::int64_t syy = 0;
  std::int64_t sxy = 0;
  std::int64_t s = 0;
  std::int64_t ss = 0;
  // Pre: the patch and a one-pixel ring around it are inside the map (margin checked by the caller).
  for (std::int32_t y = row - h; y <= row + h; ++y) {
    const std::uint8_t* r = map.row(y);
    const std::uint8_t* up = map.row(y - 1);
    const std::uint8_t* dn = map.row(y + 1);
    for (std::int32_t x = col - h; x <= col + h; ++x) {
      const std::int64_t gx = static_cast<std::int64_t>(r[x + 1]) - r[x - 1];
      const std::int64_t gy = static_cast<std::int64_t>(dn[x]) - up[x];
      sxx += gx * gx;
      syy += gy * gy;
      sxy += gx * gy;
      s += r[x];
      ss += static_cast<std::int64_t>(r[x]) * r[x];
    }
  }
  const auto n = static_cast<double>(patch_px) * patch_px;
  // Central differences are twice the gradient: divide the tensor by 4.
  const double a = static_cast<double>(sxx) / (4.0 * n);
  const double c = static_cast<double>(syy) / (4.0 * n);
  const double b = static_cast<double>(sxy) / (4.0 * n);
  const double half_diff = 0.5 * (a - c);
  corner = static_cast<float>(0.5 * (a + c) - std::sqrt(half_diff * half_diff + b * b));
  const double mean = static_cast<double>(s) / n;
  const double var = static_cast<double>(ss) / n - mean * mean;
  stddev = static_cast<float>(var > 0.0 ? std::sqrt(var) : 0.0);
  const auto px = static_cast<std::uint64_t>(n);
  work.int_macs += 5U * px;
  work.int_ops += 4U * px;
  work.mem_words += px;  // four byte loads per pixel
  work.flops += 16U;
  work.fdivs += 6U;
}

namespace detail {
namespace {

struct Grid {
  std::int32_t cols = 0;
  std::int32_t rows = 0;
};

/** Best candidate of cell (cx, cy) into @p out; false when none passes the thresholds. */
bool best_in_cell(ConstImageU8 map, const SelectParams& p, std::int32_t cx, std::int32_t cy, Landmark& out,
                  bsp::Work& work) noexcept {
  const std::int32_t in = p.cell_inset_px;
  const std::int32_t x_lo = cx * p.cell_px + in > p.margin_px ? cx * p.cell_px + in : p.margin_px;
  const std::int32_t y_lo = cy * p.cell_px + in > p.margin_px ? cy * p.cell_px + in : p.margin_px;
  const std::int32_t x_hi = (cx + 1) * p.cell_px - in;
  const std::int32_t y_hi = (cy + 1) * p.cell_px - in;
  const std::int32_t x_end = x_hi < map.width - p.margin_px ? x_hi : map.width - p.margin_px;
  const std::int32_t y_end = y_hi < map.height - p.margin_px ? y_hi : map.height - p.margin_px;
  bool found = false;
  for (std::int32_t y = y_lo; y < y_end; y += p.stride_px) {
    for (std::int32_t x = x_lo; x < x_end; x += p.stride_px) {
      float corner = 0.0F;
      float sd = 0.0F;
      patch_strength(map, x, y, p.patch_px, corner, sd, work);
      if (corner >= p.min_corner && sd >= p.min_stddev && (!found || corner > out.corner)) {
        out.col_px = x;
        out.row_px = y;
        out.corner = corner;
        out.stddev = sd;
        found = true;
      }
    }
  }
  return found;
}

/** True when cell @p i has a stronger landmark closer than the minimum separation. */
bool dominated(const LandmarkTable& t, const Grid& g, const SelectParams& p, std::int32_t i) noexcept {
  const Landmark& a = t.items[i];
  const std::int32_t cx = i % g.cols;
  const std::int32_t cy = i / g.cols;
  const std::int64_t sep2 = static_cast<std::int64_t>(p.min_separation_px) * p.min_separation_px;
  for (std::int32_t ny = cy - 1; ny <= cy + 1; ++ny) {
    for (std::int32_t nx = cx - 1; nx <= cx + 1; ++nx) {
      const std::int32_t j = ny * g.cols + nx;
      if (nx < 0 || ny < 0 || nx >= g.cols || ny >= g.rows || j == i || t.items[j].corner <= 0.0F) {
        continue;
      }
      const Landmark& b = t.items[j];
      const std::int64_t dx = b.col_px - a.col_px;
      const std::int64_t dy = b.row_px - a.row_px;
      const bool stronger = b.corner > a.corner || (b.corner == a.corner && j < i);
      if (stronger && dx * dx + dy * dy < sep2) {
        return true;
      }
    }
  }
  return false;
}

bool params_ok(ConstImageU8 map, ConstImageF32 elev, const SelectParams& p) noexcept {
  const bool elev_ok = !elev.valid() || (elev.width == map.width && elev.height == map.height);
  return map.valid() && elev_ok && p.patch_px >= 3 && p.patch_px % 2 == 1 && p.cell_px > 0 && p.stride_px > 0 &&
         p.margin_px > p.patch_px / 2 && p.min_separation_px >= 0 && p.min_separation_px <= p.cell_px && p.min_corner > 0.0F &&
         p.cell_inset_px >= 0 && 2 * p.cell_inset_px < p.cell_px;
}

}  // namespace
}  // namespace detail

Status select_landmarks_step(ConstImageU8 map, ConstImageF32 elevation_m, const MapGeometry& geo,
                             const SelectParams& p, LandmarkTable& table, SelectProgress& progress,
                             std::int32_t max_cells, bsp::Work& work) noexcept {
  if (progress.next_cell == 0) {
    table.count = 0;
  }
  if (!detail::params_ok(map, elevation_m, p) || max_cells <= 0 || progress.next_cell < 0) {
    return Status::kBadInput;
  }
  const detail::Grid g{(map.width + p.cell_px - 1) / p.cell_px, (map.height + p.cell_px - 1) / p.cell_px};
  const std::int32_t cells = g.cols * g.rows;
  if (static_cast<std::int64_t>(g.cols) * g.rows > static_cast<std::int64_t>(kMaxLandmarks)) {
    return Status::kTooLarge;
  }
  if (progress.next_cell > cells) {
    return Status::kBadInput;
  }
  // Pass 1, up to max_cells cells of it: one candidate per cell, stored at the cell's index
  // (corner 0 marks an empty cell).
  const std::int32_t stop = cells - progress.next_cell > max_cells ? progress.next_cell + max_cells : cells;
  for (std::int32_t i = progress.next_cell; i < stop; ++i) {
    table.items[i] = Landmark{};
    if (!detail::best_in_cell(map, p, i % g.cols, i / g.cols, table.items[i], work)) {
      table.items[i].corner = 0.0F;
    }
  }
  progress.next_cell = stop;
  if (stop < cells) {
    return Status::kOk;  // more cells to do: call again
  }
  // Pass 2: decide suppression on the unmodified candidates, then compact in cell order.
  for (std::int32_t i = 0; i < cells; ++i) {
    table.keep[i] = (table.items[i].corner > 0.0F && !detail::dominated(table, g, p, i)) ? 1U : 0U;
  }
  std::uint32_t n = 0;
  for (std::int32_t i = 0; i < cells; ++i) {
    if (table.keep[i] != 0U) {
      Landmark lm = table.items[i];
      lm.p_m[0] = geo.x0_m + lm.col_px * geo.m_per_px;
      lm.p_m[1] = geo.y0_m - lm.row_px * geo.m_per_px;
      lm.p_m[2] = elevation_m.valid() ? static_cast<double>(elevation_m.at(lm.col_px, lm.row_px)) : 0.0;
      table.items[n] = lm;  // n <= i: compaction never overwrites an unread cell
      ++n;
    }
  }
  table.count = n;
  progress.done = true;
  work.int_ops += static_cast<std::uint64_t>(cells) * 40U;
  return Status::kOk;
}

Status select_landmarks(ConstImageU8 map, ConstImageF32 elevation_m, const MapGeometry& geo,
                        const SelectParams& p, LandmarkTable& table, bsp::Work& work) noexcept {
  SelectProgress progress{};
  return select_landmarks_step(map, elevation_m, geo, p, table, progress, static_cast<std::int32_t>(kMaxLandmarks),
                               work);
}

}  // namespace trn::vision
