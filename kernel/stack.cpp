/**
 * @file stack.cpp
 * @brief Stack painting, canary and high-water scan.
 */
#include "kernel/detail/stack.hpp"

#include "kernel/config.hpp"

namespace k::detail {
namespace {
/** Canary byte at offset i: position-dependent so a constant fill cannot forge it. */
constexpr std::byte canary_byte(std::uint32_t i) noexcept {
  return static_cast<std::byte>(0xC3U ^ (i * 37U));
}
}  // namespace

void stack_prepare(std::byte* stack, std::uint32_t bytes) noexcept {
  for (std::uint32_t i = 0; i < config::kCanaryBytes; ++i) {
    stack[i] = canary_byte(i);
  }
  for (std::uint32_t i = config::kCanaryBytes; i < bytes; ++i) {
    stack[i] = static_cast<std::byte>(config::kPaintByte);
  }
}

bool stack_canary_ok(const std::byte* stack) noexcept {
  std::uint32_t diff = 0;
  for (std::uint32_t i = 0; i < config::kCanaryBytes; ++i) {
    diff |= static_cast<std::uint32_t>(stack[i] ^ canary_byte(i));
  }
  return diff == 0U;
}

// Reads the painted part of a stack whose live frames may carry
// AddressSanitizer redzones; the scan only reads bytes, it never writes.
[[gnu::no_sanitize_address]] std::uint32_t stack_high_water(const std::byte* stack, std::uint32_t bytes) noexcept {
  std::uint32_t i = config::kCanaryBytes;
  while (i < bytes && stack[i] == static_cast<std::byte>(config::kPaintByte)) {
    ++i;
  }
  return bytes - i;
}

}  // namespace k::detail
