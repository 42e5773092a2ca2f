/**
 * @file stack_paint.hpp
 * @brief Stack painting: fill a stack with a pattern, later measure how deep it was used.
 */
#pragma once

#include <cstddef>
#include <span>

namespace bsp {

/** Byte the painted stack is filled with (unlikely as data: alternating bits). */
inline constexpr std::byte kStackPaint{0xA5};

/** Fills @p stack with kStackPaint. Call before the stack is first used. [task|host] */
void stack_paint(std::span<std::byte> stack) noexcept;

/**
 * Bytes of @p stack used at the deepest point since it was painted: stacks grow
 * down, so this is the distance from the top to the lowest overwritten byte.
 * A pattern byte written by chance hides at most that one byte. [task|host]
 */
std::size_t stack_high_water(std::span<const std::byte> stack) noexcept;

}  // namespace bsp
