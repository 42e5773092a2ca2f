/**
 * @file ft_event.hpp
 * @brief Fixed-capacity log of fault-tolerant messaging events (give-ups, unreachable routes, suspects).
 *
 * Written by the messaging layer of one tile, read later by the fdir layer.
 * When full the oldest entry is overwritten and overwritten counts it, so no
 * event disappears without a trace.
 */
#pragma once

#include "bsp_tile64/port.hpp"

#include <array>
#include <cstdint>

namespace udn {

enum class FtCause : std::uint8_t {
  kRetriesExhausted,   ///< a reliable packet was not acknowledged after its retries
  kUnreachable,        ///< no route to the destination (send refused, or give-up without a route)
  kForwardUnreachable, ///< a forwarder had no route for a packet passing through
  kSuspectNeighbour,   ///< the probe missed a neighbour's switch too often
};

struct FtEvent {
  std::uint32_t tick = 0U;
  FtCause cause = FtCause::kRetriesExhausted;
  std::uint8_t channel = 0U;
  std::uint8_t seq = 0U;
  bsp::TileId peer = bsp::kNoTile;  ///< destination, or the suspect tile
};

inline constexpr std::uint32_t kFtEventCapacity = 64U;

struct FtEventLog {
  std::array<FtEvent, kFtEventCapacity> ring{};
  std::uint32_t next = 0U;         ///< total events written
  std::uint32_t overwritten = 0U;  ///< events lost to wrap-around (still counted)
};

/** Appends an event, overwriting the oldest when full. [task|host] */
inline void ft_event_push(FtEventLog& log, const FtEvent& e) noexcept {
  if (log.next >= kFtEventCapacity) {
    ++log.overwritten;
  }
  log.ring[log.next % kFtEventCapacity] = e;
  ++log.next;
}

/** Events held (at most kFtEventCapacity); the i-th oldest is ft_event_at(log, i). */
inline std::uint32_t ft_event_count(const FtEventLog& log) noexcept {
  return log.next < kFtEventCapacity ? log.next : kFtEventCapacity;
}
inline const FtEvent& ft_event_at(const FtEventLog& log, std::uint32_t i) noexcept {
  const std::uint32_t first = log.next < kFtEventCapacity ? 0U : log.next - kFtEventCapacity;
  return log.ring[(first + i) % kFtEventCapacity];
}

}  // namespace udn
