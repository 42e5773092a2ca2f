/**
 * @file stack.hpp
 * @brief Stack painting, canary and high-water mark (internal).
 *
 * Stacks grow down: the canary occupies the lowest kCanaryBytes, the rest is
 * painted at creation. An overflow reaches the canary before anything else.
 */
#pragma once

#include <cstddef>
#include <cstdint>

namespace k::detail {

/** Writes the canary at the bottom of the stack and paints the rest. */
void stack_prepare(std::byte* stack, std::uint32_t bytes) noexcept;

/** True while the canary is intact. */
bool stack_canary_ok(const std::byte* stack) noexcept;

/** Most bytes ever used, from the top down to the deepest unpainted byte. */
std::uint32_t stack_high_water(const std::byte* stack, std::uint32_t bytes) noexcept;

}  // namespace k::detail
