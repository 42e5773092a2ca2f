/**
 * @file ft_event.hpp
 * @brief What the fault-tolerant messaging layer reports, and the sink it reports through.
 *
 * The messaging layer sits below fault management, so it never includes the
 * flight event log: a node is given a sink (a plain function and its context)
 * and reports each event there as it happens, on the tile that saw it. The
 * fault-management layer installs the sink that writes the flight event log
 * (fdir::ft_event_sink); tests install one that records. A node without a sink
 * only counts (FtStats).
 */
#pragma once

#include "bsp_tile64/api/port.hpp"

#include <cstdint>

namespace udn {

/**
 * What a give-up says of its packet (FtEvent::word of kRetriesExhausted and
 * kUnreachable; of kSettled, kDelivered or kNotDelivered).
 */
enum class FtDelivery : std::uint8_t {
  kUnknown = 0,       ///< it left the tile and no ACK came back: it may have arrived
  kNotDelivered = 1,  ///< it never left the tile, or the receiver's record shows it skipped
  kDelivered = 2,     ///< the receiver's record shows it delivered: only its ACKs were lost
};

enum class FtCause : std::uint8_t {
  kRetriesExhausted,   ///< a reliable packet given up (word: FtDelivery, what is known of it)
  kUnreachable,        ///< no route to the destination (send refused: not delivered; or a give-up without a route, word: FtDelivery)
  kForwardUnreachable, ///< a forwarder had no route for a packet passing through
  kSuspectNeighbour,   ///< the probe missed a neighbour's switch too often
  kCorrected,          ///< a packet decoded with corrected bits (peer: its source)
  kForwarded,          ///< a packet for another tile was forwarded (peer: its source, seq: low bits of its destination)
  kDamaged,            ///< a packet beyond correction (peer: its source if identified, else kNoTile; seq: 1 if NACKed)
  kResentNack,         ///< a stream resent go-back-N after a NACK (peer: destination)
  kResentTimeout,      ///< a stream resent go-back-N after its timeout (peer: destination)
  kResentBusy,         ///< ... after its timeout, its receiver having answered BUSY (flow control: counted, never emitted)
  kMapApplied,         ///< routes rebuilt from a newer fault map (peer: tile it came from; word: version)
  kMapPushed,          ///< a neighbour probed with an older map version was sent ours (peer: neighbour; word: version)
  kTransitLost,        ///< a transit probe's target stopped answering (peer: target)
  kTransitBack,        ///< a lost transit answers again (peer: target)
  kSettled,            ///< a packet given up with its delivery unknown: the receiver's record tells (peer: destination; word: FtDelivery)
  /**
   * A check of the node's or the endpoint's own state found a value no valid
   * state holds (an upset of its RAM): that part was reset (channel: FtRepair,
   * peer: the index of the part, word: the value found).
   */
  kStateRepaired,
};

struct FtEvent {
  std::uint32_t tick = 0U;
  FtCause cause = FtCause::kRetriesExhausted;
  std::uint8_t channel = 0U;
  std::uint8_t seq = 0U;
  bsp::TileId peer = bsp::kNoTile;  ///< destination, source or suspect tile (see the cause)
  std::uint32_t word = 0U;          ///< cause-specific value (a map version, an FtDelivery)
};

/** Where a node's events go. Called on the tile that saw the event. [task|isr] */
struct FtEventSink {
  void (*fn)(void* ctx, bsp::TileId tile, const FtEvent& e) = nullptr;
  void* ctx = nullptr;
};

/** Hands @p e to @p sink if it has a function. */
inline void ft_event_emit(const FtEventSink& sink, bsp::TileId tile, const FtEvent& e) noexcept {
  if (sink.fn != nullptr) {
    sink.fn(sink.ctx, tile, e);
  }
}

}  // namespace udn
