/**
 * @file stack_paint.cpp
 * @brief Stack painting and high-water measurement.
 */
#include "bsp_tile64/emu/stack_paint.hpp"

#include <cstring>

namespace bsp {

void stack_paint(std::span<std::byte> stack) noexcept {
  std::memset(stack.data(), static_cast<int>(kStackPaint), stack.size());
}

std::size_t stack_high_water(std::span<const std::byte> stack) noexcept {
  for (std::size_t i = 0; i < stack.size(); ++i) {
    if (stack[i] != kStackPaint) {
      return stack.size() - i;
    }
  }
  return 0U;
}

}  // namespace bsp
