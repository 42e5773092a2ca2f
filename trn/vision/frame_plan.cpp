/**
 * @file frame_plan.cpp
 * @brief plan_frame(): landmarks predicted at the prior pose, spread over the image, with their search radii.
 *
 * Every landmark of the table is projected at the prior pose (pose_geometry.hpp).
 * It is kept when it lies in front of the camera, inside the frame less the
 * border, and its whole search window (frame_window.hpp) lands in the frame.
 * The frame less the border is cut into g x g cells (g = ceil(sqrt(limit)),
 * at most kPlanMaxGrid); round k of a round robin takes the k-th kept landmark
 * (table order) of every cell that has one, cells in a scattered order
 * (PlanGrid), until the limit. Two passes over
 * the table (count, then emit) keep the memory to three small per-cell arrays;
 * each landmark is written straight to its round-robin slot, so the output is
 * ordered by round, then by cell: any prefix of it is spread over the image.
 *
 * Before either pass, landmarks that cannot be in the frame are culled by a
 * map-frame box (FootprintBox): the frame less the border is a pyramid from
 * the camera centre, and every landmark lies between the table's lowest and
 * highest landmark; that slab of the pyramid is the convex hull of the four
 * corner rays' hits on the slab's two planes, so the box around those eight
 * points holds every landmark that could project inside the frame. The cull
 * only skips work: the plan is the same with it as without (test). A corner
 * ray that does not go down through both planes turns the cull off.
 */
#include "trn/vision/frame.hpp"

#include "trn/vision/frame_window.hpp"
#include "trn/vision/pose_geometry.hpp"

#include <cmath>

namespace trn::vision {

namespace {

using detail::finite_nonneg;
using detail::make_window;
using detail::prior_pose;
using detail::Window;
using detail::window_inside;

/**
 * The image grid of a plan: g x g cells over the frame less the border,
 * visited in a scattered order so that a round cut short by the limit drops
 * cells all over the image rather than its last rows: visit k is the cell of
 * row-major index k * stride mod cells (stride near 0.618 cells and coprime
 * with it), so a cell's visit index is its row-major index times the
 * inverse stride, mod cells.
 */
struct PlanGrid {
  std::int32_t g = 1;
  std::int32_t cells = 1;
  std::int32_t inv_stride = 1;  ///< inverse of the visit stride modulo cells
  double x0 = 0.0;
  double y0 = 0.0;
  double cell_w = 1.0;
  double cell_h = 1.0;
};

std::int32_t gcd(std::int32_t a, std::int32_t b) noexcept {
  for (std::int32_t k = 0; k < 64 && b != 0; ++k) {  // Euclid: far fewer than 64 steps below 2^16
    const std::int32_t t = a % b;
    a = b;
    b = t;
  }
  return a;
}

/** Sets cells and the inverse of the golden-ratio visit stride. */
void set_visit_order(PlanGrid& grid, bsp::Work& work) noexcept {
  grid.cells = grid.g * grid.g;
  grid.inv_stride = 1;
  if (grid.cells < 3) {
    return;  // one or two cells: any order is the same
  }
  auto stride = static_cast<std::int32_t>(std::lround(0.618 * grid.cells));
  for (std::int32_t k = 0; k < grid.cells && gcd(stride, grid.cells) != 1; ++k) {
    stride = stride + 1 < grid.cells ? stride + 1 : 1;
  }
  for (std::int32_t q = 1; q < grid.cells; ++q) {
    if ((stride * q) % grid.cells == 1) {
      grid.inv_stride = q;
      break;
    }
  }
  work.int_ops += 8U * static_cast<std::uint64_t>(grid.cells);
}

/** Visit index of the cell holding (u, v). */
std::int32_t cell_of(const PlanGrid& grid, double u, double v) noexcept {
  auto gx = static_cast<std::int32_t>((u - grid.x0) / grid.cell_w);
  auto gy = static_cast<std::int32_t>((v - grid.y0) / grid.cell_h);
  gx = gx < 0 ? 0 : (gx >= grid.g ? grid.g - 1 : gx);
  gy = gy < 0 ? 0 : (gy >= grid.g ? grid.g - 1 : gy);
  return ((gy * grid.g + gx) * grid.inv_stride) % grid.cells;
}

/**
 * Search radius in map pixels for a landmark at @p p: the 1-sigma ground
 * displacement of its prediction on the landmark's horizontal plane is
 *   horizontal position sigma (the larger axis)
 *   + vertical sigma x tan(off-nadir angle)   (a height error slides the ray's hit radially)
 *   + attitude sigma x range / cos(incidence) (a ray turned by dth moves its hit by range dth,
 *                                              stretched by the plane's obliquity),
 * times sigma_k, in map pixels, plus kPlanRadiusMarginPx, clamped.
 * @return -1 when the landmark is not below the camera.
 */
std::int32_t search_radius(const PosePrior& prior, const PoseGeometry& pose, const double p[3], double m_per_px,
                           const FramePlanParams& fp, bsp::Work& work) noexcept {
  const double dx = p[0] - pose.c_m[0];
  const double dy = p[1] - pose.c_m[1];
  const double height = pose.c_m[2] - p[2];
  work.flops += 24U;
  work.fdivs += 5U;
  if (!(height > 1.0)) {
    return -1;
  }
  const double horiz = std::sqrt(dx * dx + dy * dy);
  const double range = std::sqrt(horiz * horiz + height * height);
  const double* sa = prior.sigma_att_rad;
  const double sig_att = std::sqrt(sa[0] * sa[0] + sa[1] * sa[1] + sa[2] * sa[2]);
  const double sig_h = prior.sigma_p_m[0] > prior.sigma_p_m[1] ? prior.sigma_p_m[0] : prior.sigma_p_m[1];
  const double sigma_m = sig_h + prior.sigma_p_m[2] * horiz / height + sig_att * range * (range / height);
  const double r = std::ceil(fp.sigma_k * sigma_m / m_per_px) + kPlanRadiusMarginPx;
  if (!(r < static_cast<double>(fp.max_radius_px))) {
    return fp.max_radius_px;  // also catches a non-finite r
  }
  return r < static_cast<double>(fp.min_radius_px) ? fp.min_radius_px : static_cast<std::int32_t>(r);
}

/**
 * Prediction of landmark @p lm: in front, inside the frame less the border, its window inside the frame.
 * A faint landmark, or one of the table's dense set (@p tight_only), only with a radius of at most
 * weak_max_radius_px.
 */
bool predict(const Landmark& lm, bool tight_only, const bsp::CameraModel& cam, const PoseGeometry& pose,
             const PosePrior& prior, const MapView& map, const FramePlanParams& fp, PlannedLandmark& out, bsp::Work& work) noexcept {
  double u = 0.0;
  double v = 0.0;
  if (!project_point(cam, pose, lm.p_m, u, v, nullptr, work)) {
    return false;
  }
  const double b = static_cast<double>(fp.border_px);
  if (!(u >= b && v >= b && u <= static_cast<double>(cam.width_px) - 1.0 - b &&
        v <= static_cast<double>(cam.height_px) - 1.0 - b)) {
    return false;
  }
  const std::int32_t r = search_radius(prior, pose, lm.p_m, map.geo.m_per_px, fp, work);
  if (r < 0 || ((tight_only || lm.corner < fp.strong_corner) && r > fp.weak_max_radius_px)) {
    return false;
  }
  Window win;
  if (!make_window(cam, pose, map, lm, r, true, 0, 0, win, work) || !window_inside(cam, map, win, work)) {
    return false;
  }
  out.u_px = static_cast<float>(u);
  out.v_px = static_cast<float>(v);
  out.radius_px = r;
  return true;
}

bool plan_params_ok(const bsp::CameraModel& cam, const PosePrior& prior, const FramePlanParams& p) noexcept {
  const auto w = static_cast<std::int64_t>(cam.width_px);
  const auto h = static_cast<std::int64_t>(cam.height_px);
  return p.border_px >= 0 && 2 * static_cast<std::int64_t>(p.border_px) < w &&
         2 * static_cast<std::int64_t>(p.border_px) < h && std::isfinite(p.sigma_k) && p.sigma_k > 0.0 &&
         p.min_radius_px >= 1 && p.min_radius_px <= p.max_radius_px && p.max_radius_px <= kFineMaxSearchPx &&
         finite_nonneg(prior.sigma_p_m, 3) && finite_nonneg(prior.sigma_att_rad, 3);
}

/**
 * Round-robin quotas: round k takes the k-th landmark of every cell that has
 * one (cells in visit order) until @p limit are taken.
 */
std::uint32_t fill_quotas(const std::uint16_t* counts, std::int32_t cells, std::uint32_t limit,
                          std::uint16_t* quota, bsp::Work& work) noexcept {
  std::uint32_t total = 0U;
  for (std::uint32_t k = 0U; k < kMaxLandmarks && total < limit; ++k) {
    bool any = false;
    for (std::int32_t c = 0; c < cells && total < limit; ++c) {
      if (counts[c] > k) {
        ++quota[c];
        ++total;
        any = true;
      }
    }
    work.int_ops += 3U * static_cast<std::uint64_t>(cells);
    if (!any) {
      break;
    }
  }
  return total;
}

/** Output slot of the landmark of rank @p rank in cell @p cell (visit index): rounds before it, then cells visited before it. */
std::uint32_t slot_of(const std::uint16_t* quota, std::int32_t cells, std::uint32_t rank, std::int32_t cell,
                      bsp::Work& work) noexcept {
  std::uint32_t pos = 0U;
  for (std::int32_t c = 0; c < cells; ++c) {
    pos += quota[c] < rank ? quota[c] : rank;
    pos += (c < cell && quota[c] > rank) ? 1U : 0U;
  }
  work.int_ops += 4U * static_cast<std::uint64_t>(cells);
  return pos;
}

/** Map-frame x-y box outside which no landmark of the table can project inside the frame less the border. */
struct FootprintBox {
  bool on = false;  ///< false: no cull (a corner ray misses a plane)
  double x_min = 0.0;
  double x_max = 0.0;
  double y_min = 0.0;
  double y_max = 0.0;
};

/** Slack of the box, m: covers rounding between the box's arithmetic and the projection's. */
constexpr double kFootprintSlackM = 1.0;

/** The box of @p table's landmarks seen at @p pose through the frame less @p border_px (file comment). */
FootprintBox footprint_box(const LandmarkTable& table, const bsp::CameraModel& cam, const PoseGeometry& pose,
                           std::int32_t border_px, bsp::Work& work) noexcept {
  FootprintBox box;
  if (table.count == 0U) {
    return box;
  }
  double z_lo = table.items[0].p_m[2];
  double z_hi = z_lo;
  for (std::uint32_t i = 1U; i < table.count; ++i) {
    const double z = table.items[i].p_m[2];
    z_lo = z < z_lo ? z : z_lo;
    z_hi = z > z_hi ? z : z_hi;
  }
  work.int_ops += 2ULL * table.count;
  if (!(std::isfinite(z_lo) && std::isfinite(z_hi) && pose.c_m[2] > z_hi)) {
    return box;
  }
  const double b = static_cast<double>(border_px);
  const double us[2] = {b, static_cast<double>(cam.width_px) - 1.0 - b};
  const double vs[2] = {b, static_cast<double>(cam.height_px) - 1.0 - b};
  const double planes[2] = {z_lo, z_hi};
  box.x_min = pose.c_m[0];
  box.x_max = pose.c_m[0];
  box.y_min = pose.c_m[1];
  box.y_max = pose.c_m[1];
  for (std::uint32_t k = 0U; k < 4U; ++k) {
    double w_c[3];
    double w_m[3];
    pixel_ray(cam, us[k & 1U], vs[k >> 1U], w_c, work);
    to_map(pose, w_c, w_m);
    if (!(w_m[2] < -1e-9)) {
      return FootprintBox{};  // this ray does not come down to the planes
    }
    for (const double z : planes) {
      const double t = (z - pose.c_m[2]) / w_m[2];
      const double x = pose.c_m[0] + t * w_m[0];
      const double y = pose.c_m[1] + t * w_m[1];
      box.x_min = x < box.x_min ? x : box.x_min;
      box.x_max = x > box.x_max ? x : box.x_max;
      box.y_min = y < box.y_min ? y : box.y_min;
      box.y_max = y > box.y_max ? y : box.y_max;
    }
  }
  work.flops += 4ULL * (15ULL + 2ULL * 5ULL);  // per corner: rotation, then two plane hits
  work.fdivs += 8U;
  box.x_min -= kFootprintSlackM;
  box.x_max += kFootprintSlackM;
  box.y_min -= kFootprintSlackM;
  box.y_max += kFootprintSlackM;
  box.on = std::isfinite(box.x_min) && std::isfinite(box.x_max) && std::isfinite(box.y_min) &&
           std::isfinite(box.y_max);
  return box;
}

/** False when @p lm lies outside @p box (so it cannot be in the frame). */
bool in_box(const FootprintBox& box, const Landmark& lm) noexcept {
  return !box.on ||
         (lm.p_m[0] >= box.x_min && lm.p_m[0] <= box.x_max && lm.p_m[1] >= box.y_min && lm.p_m[1] <= box.y_max);
}

/** The g x g plan grid over the frame less @p border_px for @p limit landmarks, its visit order set. */
PlanGrid make_grid(const bsp::CameraModel& cam, std::int32_t border_px, std::uint32_t limit, bsp::Work& work) noexcept {
  PlanGrid grid;
  grid.g = static_cast<std::int32_t>(std::ceil(std::sqrt(static_cast<double>(limit))));
  grid.g = grid.g > kPlanMaxGrid ? kPlanMaxGrid : grid.g;
  grid.x0 = static_cast<double>(border_px);
  grid.y0 = static_cast<double>(border_px);
  grid.cell_w = (static_cast<double>(cam.width_px) - 1.0 - 2.0 * grid.x0) / grid.g + 1e-9;
  grid.cell_h = (static_cast<double>(cam.height_px) - 1.0 - 2.0 * grid.y0) / grid.g + 1e-9;
  set_visit_order(grid, work);
  return grid;
}

/**
 * Pass 2 from the @p kept predictions of @p scratch (table order): the first
 * quota[c] of each cell, each written to its round-robin slot. @return the
 * landmarks written (at most @p total).
 */
std::uint32_t emit_kept(const PlanScratch& scratch, std::uint32_t kept, const std::uint16_t* quota,
                        std::int32_t cells, std::uint32_t total, PlannedLandmark* out, bsp::Work& work) noexcept {
  std::uint16_t taken[kPlanMaxGrid * kPlanMaxGrid] = {};
  std::uint32_t n = 0U;
  for (std::uint32_t k = 0U; k < kept && n < total; ++k) {
    const std::int32_t c = scratch.cell[k];
    if (taken[c] < quota[c]) {
      out[slot_of(quota, cells, taken[c], c, work)] = scratch.kept[k];
      ++taken[c];
      ++n;
    }
  }
  work.int_ops += 4U * static_cast<std::uint64_t>(kept);
  work.mem_words += 5U * static_cast<std::uint64_t>(kept);  // written once, read once
  return n;
}

}  // namespace

Status plan_frame(const LandmarkTable& table, const MapView& map, const bsp::CameraModel& cam,
                  const PosePrior& prior, const FramePlanParams& p, PlannedLandmark* out, std::uint32_t cap,
                  std::uint32_t& n, bsp::Work& work) noexcept {
  return plan_frame(table, map, cam, prior, p, out, cap, n, nullptr, work);
}

Status plan_frame(const LandmarkTable& table, const MapView& map, const bsp::CameraModel& cam,
                  const PosePrior& prior, const FramePlanParams& p, PlannedLandmark* out, std::uint32_t cap,
                  std::uint32_t& n, PlanScratch* scratch, bsp::Work& work) noexcept {
  n = 0U;
  PoseGeometry pose;
  if ((out == nullptr && cap > 0U) || !map.image.valid() ||
      !(std::isfinite(map.geo.m_per_px) && map.geo.m_per_px > 0.0) ||
      table.count > kMaxLandmarks || !prior_pose(prior, cam, pose, work) || !plan_params_ok(cam, prior, p)) {
    return Status::kBadInput;
  }
  const std::uint32_t limit = p.max_landmarks < cap ? p.max_landmarks : cap;
  if (limit == 0U) {
    return Status::kOk;
  }
  const PlanGrid grid = make_grid(cam, p.border_px, limit, work);
  const std::int32_t cells = grid.cells;
  std::uint16_t counts[kPlanMaxGrid * kPlanMaxGrid] = {};
  std::uint16_t quota[kPlanMaxGrid * kPlanMaxGrid] = {};
  std::uint16_t taken[kPlanMaxGrid * kPlanMaxGrid] = {};
  PlannedLandmark pl;
  const FootprintBox box = p.footprint_cull ? footprint_box(table, cam, pose, p.border_px, work) : FootprintBox{};
  // Pass 1: how many landmarks each cell can offer (each prediction kept when there is a scratch).
  std::uint32_t kept = 0U;
  for (std::uint32_t i = 0U; i < table.count; ++i) {
    if (in_box(box, table.items[i]) &&
        predict(table.items[i], i >= table.first_tight, cam, pose, prior, map, p, pl, work)) {
      const std::int32_t c = cell_of(grid, pl.u_px, pl.v_px);
      ++counts[c];
      if (scratch != nullptr) {
        pl.landmark = static_cast<std::uint16_t>(i);
        scratch->kept[kept] = pl;
        scratch->cell[kept] = static_cast<std::uint16_t>(c);
        ++kept;  // at most table.count <= kMaxLandmarks
      }
    }
  }
  const std::uint32_t total = fill_quotas(counts, cells, limit, quota, work);
  if (scratch != nullptr) {
    n = emit_kept(*scratch, kept, quota, cells, total, out, work);
    work.int_ops += 12U * static_cast<std::uint64_t>(table.count);
    return Status::kOk;
  }
  // Pass 2: the first quota[c] landmarks of each cell (table order), written in round-robin order.
  for (std::uint32_t i = 0U; i < table.count && n < total; ++i) {
    if (!in_box(box, table.items[i]) ||
        !predict(table.items[i], i >= table.first_tight, cam, pose, prior, map, p, pl, work)) {
      continue;
    }
    const std::int32_t c = cell_of(grid, pl.u_px, pl.v_px);
    if (taken[c] < quota[c]) {
      pl.landmark = static_cast<std::uint16_t>(i);
      out[slot_of(quota, cells, taken[c], c, work)] = pl;
      ++taken[c];
      ++n;
    }
  }
  work.int_ops += 12U * static_cast<std::uint64_t>(table.count);  // loops and the box test, both passes
  return Status::kOk;
}

}  // namespace trn::vision
