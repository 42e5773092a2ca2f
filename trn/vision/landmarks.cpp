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

/** A selection grid: cells of cell_px over the map, candidates inset px inside each. */
struct Grid {
  std::int32_t cols = 0;
  std::int32_t rows = 0;
  std::int32_t cell_px = 1;
  std::int32_t inset = 0;
};

Grid grid_of(ConstImageU8 map, std::int32_t cell_px, std::int32_t inset) noexcept {
  if (cell_px <= 0) {
    return Grid{0, 0, 1, 0};  // no such set
  }
  return Grid{(map.width + cell_px - 1) / cell_px, (map.height + cell_px - 1) / cell_px, cell_px, inset};
}

/** Loose landmarks a dense cell's candidates must keep away from: those near the cell (at most 3 x 3 loose cells). */
struct Avoid {
  const Landmark* items[9] = {};
  std::int32_t n = 0;
  std::int64_t sep2 = 0;
};

/** True when @p a candidate at (x, y) is closer than the separation to a landmark of @p avoid. */
bool too_near(const Avoid& avoid, std::int32_t x, std::int32_t y) noexcept {
  for (std::int32_t k = 0; k < avoid.n; ++k) {
    const std::int64_t dx = avoid.items[k]->col_px - x;
    const std::int64_t dy = avoid.items[k]->row_px - y;
    if (dx * dx + dy * dy < avoid.sep2) {
      return true;
    }
  }
  return false;
}

/** Best candidate of cell (cx, cy) of @p g, away from @p avoid, into @p out; false when none passes the thresholds. */
bool best_in_cell(ConstImageU8 map, const SelectParams& p, const Grid& g, std::int32_t cx, std::int32_t cy,
                  const Avoid& avoid, Landmark& out, bsp::Work& work) noexcept {
  const std::int32_t in = g.inset;
  const std::int32_t x_lo = cx * g.cell_px + in > p.margin_px ? cx * g.cell_px + in : p.margin_px;
  const std::int32_t y_lo = cy * g.cell_px + in > p.margin_px ? cy * g.cell_px + in : p.margin_px;
  const std::int32_t x_hi = (cx + 1) * g.cell_px - in;
  const std::int32_t y_hi = (cy + 1) * g.cell_px - in;
  const std::int32_t x_end = x_hi < map.width - p.margin_px ? x_hi : map.width - p.margin_px;
  const std::int32_t y_end = y_hi < map.height - p.margin_px ? y_hi : map.height - p.margin_px;
  bool found = false;
  std::uint64_t tested = 0U;
  for (std::int32_t y = y_lo; y < y_end; y += p.stride_px) {
    for (std::int32_t x = x_lo; x < x_end; x += p.stride_px) {
      ++tested;
      if (too_near(avoid, x, y)) {
        continue;
      }
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
  work.int_ops += static_cast<std::uint64_t>(4 * avoid.n) * tested;
  return found;
}

/** True when cell @p i of @p cand (one candidate per cell of @p g) has a stronger neighbour closer than @p sep. */
bool dominated(const Landmark* cand, const Grid& g, std::int32_t sep, std::int32_t i) noexcept {
  const Landmark& a = cand[i];
  const std::int32_t cx = i % g.cols;
  const std::int32_t cy = i / g.cols;
  const std::int64_t sep2 = static_cast<std::int64_t>(sep) * sep;
  for (std::int32_t ny = cy - 1; ny <= cy + 1; ++ny) {
    for (std::int32_t nx = cx - 1; nx <= cx + 1; ++nx) {
      const std::int32_t j = ny * g.cols + nx;
      if (nx < 0 || ny < 0 || nx >= g.cols || ny >= g.rows || j == i || cand[j].corner <= 0.0F) {
        continue;
      }
      const Landmark& b = cand[j];
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

/** Cell index of @p lm in grid @p g. */
std::int32_t cell_index(const Grid& g, const Landmark& lm) noexcept {
  return (lm.row_px / g.cell_px) * g.cols + lm.col_px / g.cell_px;
}

/** The loose landmark of loose cell @p c (table items before first_tight, in cell order), or null: binary search. */
const Landmark* loose_in_cell(const LandmarkTable& t, const Grid& loose, std::int32_t c, bsp::Work& work) noexcept {
  std::uint32_t lo = 0U;
  std::uint32_t hi = t.first_tight;
  for (std::uint32_t k = 0U; k < 32U && lo < hi; ++k) {
    const std::uint32_t mid = lo + (hi - lo) / 2U;
    if (cell_index(loose, t.items[mid]) < c) {
      lo = mid + 1U;
    } else {
      hi = mid;
    }
  }
  work.int_ops += 60U;
  return lo < t.first_tight && cell_index(loose, t.items[lo]) == c ? &t.items[lo] : nullptr;
}

/**
 * The loose landmarks within @p sep of dense cell (cx, cy)'s candidates: the
 * loose cells the candidates' area widened by sep overlaps (at most 3 x 3,
 * as sep + the dense cell < 2 loose cells).
 */
Avoid loose_near(const LandmarkTable& t, const Grid& loose, const Grid& dense, std::int32_t sep, std::int32_t cx,
                 std::int32_t cy, bsp::Work& work) noexcept {
  Avoid a;
  a.sep2 = static_cast<std::int64_t>(sep) * sep;
  const std::int32_t x0 = cx * dense.cell_px + dense.inset - sep;
  const std::int32_t y0 = cy * dense.cell_px + dense.inset - sep;
  const std::int32_t x1 = (cx + 1) * dense.cell_px - dense.inset + sep;
  const std::int32_t y1 = (cy + 1) * dense.cell_px - dense.inset + sep;
  const std::int32_t lx0 = x0 > 0 ? x0 / loose.cell_px : 0;
  const std::int32_t ly0 = y0 > 0 ? y0 / loose.cell_px : 0;
  const std::int32_t lx1 = x1 / loose.cell_px < loose.cols - 1 ? x1 / loose.cell_px : loose.cols - 1;
  const std::int32_t ly1 = y1 / loose.cell_px < loose.rows - 1 ? y1 / loose.cell_px : loose.rows - 1;
  for (std::int32_t ly = ly0; ly <= ly1 && ly < ly0 + 3; ++ly) {
    for (std::int32_t lx = lx0; lx <= lx1 && lx < lx0 + 3; ++lx) {
      const Landmark* lm = loose_in_cell(t, loose, ly * loose.cols + lx, work);
      if (lm != nullptr) {
        a.items[a.n] = lm;
        ++a.n;
      }
    }
  }
  return a;
}

bool params_ok(ConstImageU8 map, ConstImageF32 elev, const SelectParams& p) noexcept {
  const bool elev_ok = !elev.valid() || (elev.width == map.width && elev.height == map.height);
  const bool dense_ok = p.dense_cell_px == 0 ||
                        (p.dense_cell_px > 0 && p.dense_cell_px < p.cell_px && p.min_separation_px <= p.dense_cell_px &&
                         p.dense_cell_inset_px >= 0 && 2 * p.dense_cell_inset_px < p.dense_cell_px);
  return map.valid() && elev_ok && p.patch_px >= 3 && p.patch_px % 2 == 1 && p.cell_px > 0 && p.stride_px > 0 &&
         p.margin_px > p.patch_px / 2 && p.min_separation_px >= 0 && p.min_separation_px <= p.cell_px && p.min_corner > 0.0F &&
         p.cell_inset_px >= 0 && 2 * p.cell_inset_px < p.cell_px && dense_ok;
}

/**
 * Searches cells [from, stop) of @p g, each's candidate at cand[cell] (corner
 * 0 marks an empty cell); with @p loose, candidates keep away from the
 * table's loose landmarks (the dense set).
 */
void search_cells(ConstImageU8 map, const SelectParams& p, const Grid& g, std::int32_t from, std::int32_t stop,
                  const LandmarkTable& t, const Grid* loose, Landmark* cand, bsp::Work& work) noexcept {
  for (std::int32_t i = from; i < stop; ++i) {
    const std::int32_t cx = i % g.cols;
    const std::int32_t cy = i / g.cols;
    const Avoid avoid = loose != nullptr ? loose_near(t, *loose, g, p.min_separation_px, cx, cy, work) : Avoid{};
    cand[i] = Landmark{};
    if (!best_in_cell(map, p, g, cx, cy, avoid, cand[i], work)) {
      cand[i].corner = 0.0F;
    }
  }
}

/**
 * Keeps the marked candidates of @p cand (@p cells of them, marks in
 * t.keep), in cell order, with their map positions, written from
 * t.items[@p base] on. @return how many.
 */
std::uint32_t compact(LandmarkTable& t, std::uint32_t base, std::int32_t cells, ConstImageF32 elev,
                      const MapGeometry& geo) noexcept {
  std::uint32_t n = 0;
  for (std::int32_t i = 0; i < cells; ++i) {
    if (t.keep[i] != 0U) {
      Landmark lm = t.items[base + static_cast<std::uint32_t>(i)];
      lm.p_m[0] = geo.x0_m + lm.col_px * geo.m_per_px;
      lm.p_m[1] = geo.y0_m - lm.row_px * geo.m_per_px;
      lm.p_m[2] = elev.valid() ? static_cast<double>(elev.at(lm.col_px, lm.row_px)) : 0.0;
      t.items[base + n] = lm;  // n <= i: compaction never overwrites an unread cell
      ++n;
    }
  }
  return n;
}

}  // namespace
}  // namespace detail

Status select_landmarks_step(ConstImageU8 map, ConstImageF32 elevation_m, const MapGeometry& geo,
                             const SelectParams& p, LandmarkTable& table, SelectProgress& progress,
                             std::int32_t max_cells, bsp::Work& work) noexcept {
  if (progress.next_cell == 0) {
    table.count = 0;
    table.first_tight = kMaxLandmarks;
  }
  if (!detail::params_ok(map, elevation_m, p) || max_cells <= 0 || progress.next_cell < 0) {
    return Status::kBadInput;
  }
  const detail::Grid loose = detail::grid_of(map, p.cell_px, p.cell_inset_px);
  const detail::Grid dense = detail::grid_of(map, p.dense_cell_px, p.dense_cell_inset_px);
  const std::int32_t loose_cells = loose.cols * loose.rows;
  const std::int32_t dense_cells = dense.cols * dense.rows;
  if (static_cast<std::int64_t>(loose_cells) + dense_cells > static_cast<std::int64_t>(kMaxLandmarks)) {
    return Status::kTooLarge;
  }
  if (progress.next_cell > loose_cells + dense_cells || (progress.next_cell > loose_cells && table.first_tight > table.count)) {
    return Status::kBadInput;
  }
  if (progress.next_cell < loose_cells) {
    // The loose set: one candidate per cell, stored at the cell's index; then suppression decided on
    // the unmodified candidates and the table compacted in cell order.
    const std::int32_t stop = loose_cells - progress.next_cell > max_cells ? progress.next_cell + max_cells : loose_cells;
    detail::search_cells(map, p, loose, progress.next_cell, stop, table, nullptr, table.items, work);
    progress.next_cell = stop;
    if (stop < loose_cells) {
      return Status::kOk;  // more cells to do: call again
    }
    for (std::int32_t i = 0; i < loose_cells; ++i) {
      table.keep[i] = (table.items[i].corner > 0.0F && !detail::dominated(table.items, loose, p.min_separation_px, i)) ? 1U : 0U;
    }
    table.count = detail::compact(table, 0U, loose_cells, elevation_m, geo);
    table.first_tight = table.count;
    work.int_ops += static_cast<std::uint64_t>(loose_cells) * 40U;
    progress.done = dense_cells == 0;
    return Status::kOk;
  }
  // The dense set, its candidates after the loose set and away from its landmarks.
  Landmark* cand = table.items + table.first_tight;
  const std::int32_t from = progress.next_cell - loose_cells;
  const std::int32_t stop = dense_cells - from > max_cells ? from + max_cells : dense_cells;
  detail::search_cells(map, p, dense, from, stop, table, &loose, cand, work);
  progress.next_cell = loose_cells + stop;
  if (stop < dense_cells) {
    return Status::kOk;
  }
  for (std::int32_t i = 0; i < dense_cells; ++i) {
    table.keep[i] = (cand[i].corner > 0.0F && !detail::dominated(cand, dense, p.min_separation_px, i)) ? 1U : 0U;
  }
  table.count = table.first_tight + detail::compact(table, table.first_tight, dense_cells, elevation_m, geo);
  work.int_ops += static_cast<std::uint64_t>(dense_cells) * 40U;
  progress.done = true;
  return Status::kOk;
}

Status select_landmarks(ConstImageU8 map, ConstImageF32 elevation_m, const MapGeometry& geo,
                        const SelectParams& p, LandmarkTable& table, bsp::Work& work) noexcept {
  SelectProgress progress{};
  Status s = Status::kOk;
  for (std::int32_t k = 0; k < 4 && s == Status::kOk && !progress.done; ++k) {  // loose set, then dense set
    s = select_landmarks_step(map, elevation_m, geo, p, table, progress, static_cast<std::int32_t>(kMaxLandmarks),
                              work);
  }
  return s;
}

}  // namespace trn::vision
