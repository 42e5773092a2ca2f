/**
 * @file landmarks.hpp
 * @brief Landmark selection from the reference map: distinctive patches spread over the map.
 *
 * Run once at init. The map is cut into square cells (grid bucketing, so
 * landmarks cover the whole map, not just its busiest corner); in each cell,
 * candidate centres on a stride are scored by the Shi-Tomasi corner strength
 * of the whole template patch: the smaller eigenvalue of the gradient
 * structure tensor, per pixel. It is the NCC peak's curvature in its weakest
 * direction, so a high value means a match that is sharp in both axes; an
 * edge or a flat area has a small one. A candidate must also pass a minimum
 * grey-level standard deviation. Candidates stay cell_inset_px inside their
 * cell, so the winners of neighbouring cells cannot crowd a shared border
 * (2 x inset >= separation keeps every cell's winner); the best candidate
 * of each cell is kept, then a non-maximum suppression across neighbouring
 * cells drops the weaker of any two landmarks closer than min_separation_px.
 *
 * Two sets (SelectParams::dense_cell_px > 0): after the loose set above, the
 * map is cut again into smaller cells and selected the same way; a dense
 * candidate closer than min_separation_px to a loose landmark is dropped, and
 * the others are appended after the loose set (LandmarkTable::first_tight).
 * The loose set is the table one set gives, bit for bit; the dense landmarks
 * are for frames whose prior is tight (FramePlanParams::weak_max_radius_px):
 * near the ground the frame sees few loose landmarks, while a frame matched
 * with a loose prior keeps the loose set's count of matches (a larger batch
 * applied with a loose prior is overconfident, docs/VISION.md).
 *
 * Map geometry: pixel (col, row) centre is at x = x0_m + col * m_per_px (east),
 * y = y0_m - row * m_per_px (north; rows grow southward), z = elevation(col, row).
 */
#pragma once

#include "bsp_tile64/api/work.hpp"
#include "trn/vision/image.hpp"
#include "trn/vision/status.hpp"

#include <cstdint>

namespace trn::vision {

/** Capacity of the landmark table (also the most grid cells a selection may use, both sets together). */
inline constexpr std::uint32_t kMaxLandmarks = 18432;

struct MapGeometry {
  double m_per_px = 12.0;  ///< ground sample distance
  double x0_m = 0.0;       ///< map-frame east coordinate of pixel (0, 0)'s centre
  double y0_m = 0.0;       ///< map-frame north coordinate of pixel (0, 0)'s centre
};

struct Landmark {
  std::int32_t col_px = 0;  ///< patch centre column in the map
  std::int32_t row_px = 0;  ///< patch centre row in the map
  double p_m[3] = {0.0, 0.0, 0.0};  ///< map-frame position of the centre, m
  float corner = 0.0F;      ///< smaller structure-tensor eigenvalue per pixel, (DN/px)^2
  float stddev = 0.0F;      ///< grey-level standard deviation of the patch, DN
};

struct LandmarkTable {
  Landmark items[kMaxLandmarks];
  std::uint32_t count = 0;
  /// Items from this index on are the dense set (planned only with a tight prior); a table of one
  /// set has it at or past count.
  std::uint32_t first_tight = kMaxLandmarks;
  std::uint8_t keep[kMaxLandmarks]{};  ///< selection scratch (non-maximum suppression marks)
};

struct SelectParams {
  std::int32_t patch_px = 21;          ///< template side (odd)
  std::int32_t cell_px = 64;           ///< grid cell side
  std::int32_t stride_px = 4;          ///< candidate spacing inside a cell
  std::int32_t margin_px = 40;         ///< centres stay this far from the map border
  std::int32_t cell_inset_px = 16;     ///< candidates keep this far inside their cell (< cell_px / 2)
  std::int32_t min_separation_px = 32; ///< closest two landmarks may be (<= cell_px)
  float min_corner = 20.0F;            ///< (DN/px)^2: weakest-direction gradient RMS >= ~4.5 DN/px
  float min_stddev = 8.0F;             ///< DN
  std::int32_t dense_cell_px = 0;      ///< cell side of the dense set (0: one set; else < cell_px)
  std::int32_t dense_cell_inset_px = 0;  ///< the dense set's cell_inset_px (< dense_cell_px / 2)
};

/**
 * Selects landmarks from @p map into @p table (cleared first).
 * @param elevation_m heights of the map pixels (same size as @p map), or an invalid
 *        view for z = 0
 * @return kBadInput for invalid views, mismatched elevation, an even or too small
 *         patch, separation above a cell size, or a dense cell not smaller than the
 *         loose one; kTooLarge when the grids have more cells than kMaxLandmarks.
 */
Status select_landmarks(ConstImageU8 map, ConstImageF32 elevation_m, const MapGeometry& geo,
                        const SelectParams& p, LandmarkTable& table, bsp::Work& work) noexcept;

/** Where a stepwise selection stands: the next grid cell to search (the dense grid's follow the loose grid's); done once the table is final. */
struct SelectProgress {
  std::int32_t next_cell = 0;
  bool done = false;
};

/**
 * select_landmarks() in steps, so that a task can do other work between them:
 * each call searches at most @p max_cells more grid cells, and the call that
 * searches the last one decides and compacts the table (@p progress done).
 * Start with a fresh @p progress (the first call clears the table); the table
 * is the one select_landmarks() gives, whatever the steps. Errors as
 * select_landmarks(), and kBadInput for max_cells <= 0 or a progress past the grid.
 */
Status select_landmarks_step(ConstImageU8 map, ConstImageF32 elevation_m, const MapGeometry& geo,
                             const SelectParams& p, LandmarkTable& table, SelectProgress& progress,
                             std::int32_t max_cells, bsp::Work& work) noexcept;

/** Patch statistics used by the selection: corner strength and standard deviation. */
void patch_strength(ConstImageU8 map, std::int32_t col, std::int32_t row, std::int32_t patch_px, float& corner,
                    float& stddev, bsp::Work& work) noexcept;

}  // namespace trn::vision
