/**
 * @file warp_grid.hpp
 * @brief Homography resampling with the homography evaluated on a node grid and integers in between.
 *
 * warp_homography() evaluates the homography in double precision at every
 * destination pixel: on the TILE64 (soft float) that is ~1.5 k cycles a pixel.
 * warp_homography_grid() evaluates it exactly only at grid nodes every G
 * destination pixels (G a power of two; nodes at multiples of G up to the first
 * one at or past the last row/column), holds the node source coordinates in
 * fixed point (kGridFracBits fraction bits), interpolates them bilinearly over
 * each cell with integer adds, and samples the source bilinearly in integers
 * (kGridWeightBits weight bits, rounded half up like warp_homography()).
 *
 * Differences from warp_homography(), all bounded:
 *  - the source coordinate is the cell's bilinear interpolation of the exact
 *    node coordinates: off by the homography's curvature over a cell, which
 *    grows as G^2 (tests/trn/vision/warp_grid_test.cpp measures it per G);
 *  - inside/outside is decided on that coordinate rounded to 2^-kGridWeightBits px;
 *  - a cell with a node behind the camera (w <= 1e-12) or beyond
 *    kGridMaxCoordPx of the source origin is all outside (the exact warp may
 *    keep some of its pixels; such cells are far from usable anyway).
 * Same contract otherwise: a pixel whose source needs a neighbour outside the
 * source gets the fill value and is counted in outside_px.
 */
#pragma once

#include "bsp_tile64/api/work.hpp"
#include "trn/vision/image.hpp"
#include "trn/vision/status.hpp"
#include "trn/vision/warp.hpp"

#include <cstdint>

namespace trn::vision {

/** Smallest and largest grid spacing, px (powers of two in between). */
inline constexpr std::int32_t kGridWarpMinPx = 4;
inline constexpr std::int32_t kGridWarpMaxPx = 32;
/** Nodes per grid row held at a time: a 1024 px destination row at 8 px spacing. */
inline constexpr std::int32_t kGridWarpMaxNodes = 129;
/** Fraction bits of the interpolated source coordinates (Q16 in 32 bits). */
inline constexpr std::int32_t kGridFracBits = 16;
/** Fraction bits of the bilinear weights: 255 << 2 * 10 fits 32 bits with room. */
inline constexpr std::int32_t kGridWeightBits = 10;
/**
 * Largest |node source coordinate|, px: Q16 values stay below 2^29, so a
 * difference of two and its rounding term stay inside 32 bits.
 */
inline constexpr double kGridMaxCoordPx = 8192.0;

/**
 * Fills @p dst from @p src under @p dst_to_src, the homography exact at the
 * nodes of a @p grid_px grid and interpolated in fixed point between them.
 * @param grid_px node spacing, a power of two in [kGridWarpMinPx, kGridWarpMaxPx]
 * @param outside_px destination pixels that fell outside the source (given @p fill)
 * @return kBadInput for invalid views or spacing, kTooLarge when a grid row
 *         needs more than kGridWarpMaxNodes nodes.
 */
Status warp_homography_grid(ConstImageU8 src, const Homography& dst_to_src, std::int32_t grid_px, ImageU8 dst,
                            std::uint8_t fill, std::int32_t& outside_px, bsp::Work& work) noexcept;

namespace detail {

/** Node x value of a node the grid cannot use (behind the camera or out of range). */
inline constexpr std::int32_t kGridNoNode = INT32_MIN;

/** One row of grid nodes: Q16 source coordinates, x == kGridNoNode when unusable. */
struct GridNodeRow {
  std::int32_t x[kGridWarpMaxNodes];
  std::int32_t y[kGridWarpMaxNodes];
};

/** A grid's shape; ok() false when the spacing or the size is not supported. */
struct GridShape {
  std::int32_t shift = 0;  ///< log2 of the spacing
  std::int32_t nodes = 0;  ///< node columns: (width - 1) / G + 2
  Status status = Status::kBadInput;
};

/** The shape of a @p grid_px grid over a @p width x @p height destination. */
GridShape grid_shape(std::int32_t grid_px, std::int32_t width, std::int32_t height) noexcept;

/** Evaluates the nodes (k G, @p node_y), k < shape.nodes, exactly and rounds them to Q16. */
void grid_node_row(const Homography& h, const GridShape& shape, std::int32_t node_y, GridNodeRow& row,
                   bsp::Work& work) noexcept;

/** The Q16 source coordinate of a cell edge at row offset @p v of a band, between @p top and @p bot. */
struct GridEdge {
  std::int32_t x = 0;
  std::int32_t y = 0;
  bool usable = false;
};

inline GridEdge grid_edge(const GridNodeRow& top, const GridNodeRow& bot, std::int32_t k, std::int32_t v,
                          std::int32_t shift) noexcept {
  GridEdge e;
  e.usable = top.x[k] != kGridNoNode && bot.x[k] != kGridNoNode;
  if (e.usable) {
    // |bot - top| < 2^30 and v < 2^shift <= 32: the product needs 64 bits, the result fits 32.
    const std::int64_t half = std::int64_t{1} << (shift - 1);
    e.x = top.x[k] + static_cast<std::int32_t>((std::int64_t{bot.x[k] - top.x[k]} * v + half) >> shift);
    e.y = top.y[k] + static_cast<std::int32_t>((std::int64_t{bot.y[k] - top.y[k]} * v + half) >> shift);
  }
  return e;
}

/**
 * Walks every destination pixel of a @p shape grid over @p width x @p height,
 * row by row, calling visit(x, y, xq, yq, usable) with the Q16 source
 * coordinate (xq, yq) of pixel (x, y); usable false in cells the grid cannot
 * use (xq, yq are then 0). The warp samples through it and the tests measure
 * its coordinates through it, so both see the same arithmetic.
 * Pre: shape.status == kOk for this width and height. Node rows live on the
 * stack (2 x kGridWarpMaxNodes x 8 bytes).
 */
template <typename Visit>
void walk_grid(const Homography& h, const GridShape& shape, std::int32_t width, std::int32_t height, Visit& visit,
               bsp::Work& work) noexcept {
  const std::int32_t g = std::int32_t{1} << shape.shift;
  const std::int32_t half = g / 2;
  const std::int32_t bands = (height - 1) / g + 1;
  GridNodeRow rows[2];
  grid_node_row(h, shape, 0, rows[0], work);
  for (std::int32_t j = 0; j < bands; ++j) {
    const GridNodeRow& top = rows[j & 1];
    grid_node_row(h, shape, (j + 1) * g, rows[(j + 1) & 1], work);
    const GridNodeRow& bot = rows[(j + 1) & 1];
    const std::int32_t y_end = (j + 1) * g < height ? (j + 1) * g : height;
    for (std::int32_t y = j * g; y < y_end; ++y) {
      GridEdge left = grid_edge(top, bot, 0, y - j * g, shape.shift);
      for (std::int32_t k = 0; k + 1 < shape.nodes && k * g < width; ++k) {
        const GridEdge right = grid_edge(top, bot, k + 1, y - j * g, shape.shift);
        const bool usable = left.usable && right.usable;
        // Rounded step: <= 1/2 LSB off per pixel, <= G/2 LSB (2^-12 px at G = 32) across a cell.
        const std::int32_t step_x = usable ? (right.x - left.x + half) >> shape.shift : 0;
        const std::int32_t step_y = usable ? (right.y - left.y + half) >> shape.shift : 0;
        std::int32_t xq = usable ? left.x : 0;
        std::int32_t yq = usable ? left.y : 0;
        const std::int32_t x_end = (k + 1) * g < width ? (k + 1) * g : width;
        for (std::int32_t x = k * g; x < x_end; ++x) {
          visit(x, y, xq, yq, usable);
          xq += step_x;
          yq += step_y;
        }
        left = right;
      }
    }
  }
  const auto rows_px = static_cast<std::uint64_t>(height);
  const auto cols = static_cast<std::uint64_t>(shape.nodes);
  // Per row and node column, two edges (64-bit multiply as 2 MACs, 5 ALU ops each) and two rounded steps.
  work.int_macs += rows_px * cols * 4U;
  work.int_ops += rows_px * cols * 16U;
  // Per pixel: two coordinate adds and the loop.
  work.int_ops += rows_px * static_cast<std::uint64_t>(width) * 3U;
  work.mem_words += rows_px * cols * 4U;  // node values loaded for the edges
}

}  // namespace detail

}  // namespace trn::vision
