/**
 * @file cost_model.hpp
 * @brief Converts counted work (bsp::Work) into cycles with a chip profile's cost table.
 *
 * Pure and constexpr so tests and tools can compute expected cycle counts
 * exactly. The port's cost_of(Work)/consume(Work) use the board's profile.
 */
#pragma once

#include "bsp_tile64/api/port.hpp"
#include "bsp_tile64/emu/profile.hpp"
#include "bsp_tile64/api/work.hpp"

#include <cstdint>
#include <limits>

namespace bsp {

namespace detail {
/** a * b + acc, saturating at the largest value instead of wrapping. */
constexpr std::uint64_t mul_add_sat(std::uint64_t acc, std::uint64_t a, std::uint64_t b) noexcept {
  constexpr std::uint64_t kMax = std::numeric_limits<std::uint64_t>::max();
  if (a != 0U && b > kMax / a) {
    return kMax;
  }
  const std::uint64_t p = a * b;
  return (p > kMax - acc) ? kMax : acc + p;
}
}  // namespace detail

/**
 * Cycles @p work costs on @p profile: the sum of count x cost over all kinds,
 * rounded up to a whole cycle (any non-zero work costs at least one cycle).
 * Saturates at UINT64_MAX instead of overflowing.
 */
constexpr Cycles cost_of(const ChipProfile& profile, const Work& work) noexcept {
  const CostTable& c = profile.cost;
  std::uint64_t x16 = 0U;
  x16 = detail::mul_add_sat(x16, work.int_ops, c.int_op_x16);
  x16 = detail::mul_add_sat(x16, work.int_macs, c.int_mac_x16);
  x16 = detail::mul_add_sat(x16, work.flops, c.flop_x16);
  x16 = detail::mul_add_sat(x16, work.fdivs, c.fdiv_x16);
  x16 = detail::mul_add_sat(x16, work.mem_words, c.mem_word_x16);
  return x16 / kCostScale + ((x16 % kCostScale) != 0U ? 1U : 0U);
}

/** Cycles for a packet of @p words words over @p hops hops: per-hop latency plus serialization. */
constexpr Cycles network_cycles(const ChipProfile& profile, std::uint64_t hops, std::uint64_t words) noexcept {
  const std::uint64_t x16 = detail::mul_add_sat(0U, hops, profile.cost.hop_x16);
  return x16 / kCostScale + ((x16 % kCostScale) != 0U ? 1U : 0U) + words;
}

}  // namespace bsp
