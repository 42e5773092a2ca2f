/**
 * @file stack.cpp
 * @brief Stack painting, canary and high-water scan.
 */
#include "kernel/detail/stack.hpp"

#include "kernel/config.hpp"

#include <array>
#include <cstring>

namespace k::detail {
namespace {
/** Canary byte at offset i: position-dependent so a constant fill cannot forge it. */
constexpr std::byte canary_byte(std::uint32_t i) noexcept {
  return static_cast<std::byte>(0xC3U ^ (i * 37U));
}

constexpr std::array<std::byte, config::kCanaryBytes> make_canary() noexcept {
  std::array<std::byte, config::kCanaryBytes> c{};
  for (std::uint32_t i = 0; i < config::kCanaryBytes; ++i) {
    c[i] = canary_byte(i);
  }
  return c;
}

/** The whole canary, so that the check at every switch is one block compare. */
constexpr std::array<std::byte, config::kCanaryBytes> kCanary = make_canary();
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
  return std::memcmp(stack, kCanary.data(), kCanary.size()) == 0;
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
