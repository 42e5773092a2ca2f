/**
 * @file config.hpp
 * @brief Kernel configuration: capacities and defaults, in one place (checked in config_check.hpp).
 *
 * The check header includes this one, not the other way round (no include
 * cycle). The kernel's task control block header (detail/tcb.hpp) includes
 * both, so the kernel library, whose scheduler includes it, never builds
 * without the checks.
 */
#pragma once

#include <cstdint>

namespace k::config {

/** Tasks per tile, including the idle task. */
inline constexpr std::uint32_t kMaxTasks = 16;
/** Priority levels; 0 is the most urgent, kNumPriorities - 1 belongs to the idle task. */
inline constexpr std::uint32_t kNumPriorities = 32;
/** Idle task stack, bytes. */
inline constexpr std::uint32_t kIdleStackBytes = 16U * 1024U;
/** Longest sleep of an idle tile with nothing due (tickless idle): an interrupt wakes it sooner. */
inline constexpr std::uint32_t kMaxIdleTicks = 1000U;
/** Bytes at the bottom of each stack holding the canary (checked at every switch). */
inline constexpr std::uint32_t kCanaryBytes = 64;
/** Byte painted over every stack at creation, for high-water marks. */
inline constexpr std::uint8_t kPaintByte = 0xA5;
/** Kernel trace ring kept per tile for inspection (entries). */
inline constexpr std::uint32_t kTraceRing = 64;

}  // namespace k::config
