/**
 * @file match_deal.hpp
 * @brief Deals a frame's matches round the image's quadrants, in place (the coordinator's batch order).
 *
 * The filter applies a frame's batch a few matches per job. Dealt one from each
 * quadrant in turn, each job's few span the image and fix position and
 * attitude together, instead of one corner's bearings pulling the solution
 * along their common direction (docs/FILTER.md, "Fix and convergence").
 */
#pragma once

#include "trn/match.hpp"

#include <cstdint>
#include <span>

namespace trn::tasks {

/** The image quadrant of @p m about the optical centre (@p cx_px, @p cy_px): 0 upper left .. 3 lower right. */
std::uint32_t match_quadrant(const Match& m, double cx_px, double cy_px) noexcept;

/**
 * Permutes @p matches from index @p first on so that they come one from each
 * quadrant in turn (0, 1, 2, 3, 0, ...; a quadrant with none left is
 * skipped), each quadrant's matches in their present order; the places before
 * @p first stay. @p order and @p placed are scratch of at least matches.size()
 * entries.
 * @return false (nothing moved) when the scratch is too small, @p first is
 *         past the end, or there are more matches than a 16-bit order holds.
 */
bool deal_by_quadrant(std::span<Match> matches, std::uint32_t first, double cx_px, double cy_px,
                      std::span<std::uint16_t> order, std::span<bool> placed) noexcept;

}  // namespace trn::tasks
