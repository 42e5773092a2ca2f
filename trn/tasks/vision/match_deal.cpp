/**
 * @file match_deal.cpp
 * @brief The quadrant deal of a frame's matches: the order, then the permutation by its cycles.
 */
#include "trn/tasks/vision/match_deal.hpp"

#include <array>

namespace trn::tasks {

std::uint32_t match_quadrant(const Match& m, double cx_px, double cy_px) noexcept {
  return (m.u_px < cx_px ? 0U : 1U) + (m.v_px < cy_px ? 0U : 2U);
}

bool deal_by_quadrant(std::span<Match> matches, std::uint32_t first, double cx_px, double cy_px,
                      std::span<std::uint16_t> order, std::span<bool> placed) noexcept {
  const std::size_t n = matches.size();
  if (order.size() < n || placed.size() < n || first > n || n > 0xFFFFU) {
    return false;
  }
  const auto count = static_cast<std::uint32_t>(n);
  std::array<std::uint32_t, 4> cursor{first, first, first, first};
  std::uint32_t place = first;
  // Each round gives every quadrant with a match left its next one; at most n rounds.
  for (std::uint32_t round = first; round < count && place < count; ++round) {
    for (std::uint32_t q = 0; q < 4U; ++q) {
      while (cursor[q] < count && match_quadrant(matches[cursor[q]], cx_px, cy_px) != q) {
        ++cursor[q];
      }
      if (cursor[q] < count) {
        order[place] = static_cast<std::uint16_t>(cursor[q]);
        placed[place] = false;
        ++place;
        ++cursor[q];
      }
    }
  }
  // Apply the permutation by following its cycles (place j takes match order[j]).
  for (std::uint32_t i = first; i < count; ++i) {
    if (placed[i]) {
      continue;
    }
    const Match held = matches[i];
    std::uint32_t j = i;
    for (std::uint32_t step = first; step < count; ++step) {
      placed[j] = true;
      const std::uint32_t from = order[j];
      if (from == i) {
        matches[j] = held;
        break;
      }
      matches[j] = matches[from];
      j = from;
    }
  }
  return true;
}

}  // namespace trn::tasks
