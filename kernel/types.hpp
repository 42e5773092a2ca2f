/**
 * @file types.hpp
 * @brief Kernel vocabulary: ticks, timeouts, status values, task identifiers.
 */
#pragma once

#include <cstdint>

namespace k {

using Ticks = std::uint64_t;
using TaskId = std::uint8_t;

inline constexpr TaskId kNoTask = 0xFF;

/** A timeout in ticks; kNoWait returns at once, kForever never times out. */
struct Timeout {
  std::uint32_t ticks;
};
inline constexpr Timeout kNoWait{0};
inline constexpr Timeout kForever{0xFFFF'FFFFU};

/** Result of every kernel call that can fail. */
enum class Status : std::uint8_t {
  kOk,
  kTimeout,     ///< the timeout expired before the condition
  kWouldBlock,  ///< kNoWait and the condition is not met
  kExhausted,   ///< pool or queue has no room (non-blocking forms)
  kBadArg,      ///< argument out of range
  kNoMemory,    ///< the tile's RAM region cannot hold the task table
  kBadState,    ///< call not allowed here (e.g. blocking from an interrupt)
};

}  // namespace k
