/**
 * @file udn_driver.hpp
 * @brief The UDN driver API: what flight code may do with the network (send, receive, bind, poll).
 *
 * Interface control, like a network interface's register map: a tile sends
 * packets, binds tags to its demux queues, polls and pops them, and learns the
 * grid it sits on. Nothing here controls or observes the model from outside
 * (failing switches, bit-error rates, sending as another tile, statistics):
 * that is udn_net.hpp, for images, tests and tools. Flight code (kernel udn
 * fdir trn) includes this header and udn_hw.hpp, never udn_net.hpp; the
 * flight-rules checker enforces it.
 *
 * Timing, ordering and back-pressure are the model's (udn_net.hpp, docs/NETWORK.md):
 * a packet sent now is visible to its destination at a later quantum barrier,
 * which raises Irq::kUdn there. Tiles: id = y * cols + x.
 */
#pragma once

#include "bsp_tile64/api/port.hpp"
#include "bsp_tile64/api/udn_hw.hpp"

#include <cstdint>
#include <span>

namespace bsp {

enum class NetError : std::uint8_t {
  kOk,
  kNotInit,    ///< udn_net_init() was not called since board_init()
  kBadTile,    ///< tile outside the grid
  kBadLength,  ///< length field 0, above the maximum, or not the number of words given
  kBadQueue,   ///< queue index >= kUdnQueues
  kBadConfig,  ///< see udn_net_init()
  kFull,       ///< the source has its maximum of packets in flight, or a table is full
  kEmpty,      ///< nothing in the queue
};

/** Incremented by every successful udn_net_init(): drivers tell a new board from the last one. [any] */
std::uint32_t udn_net_generation() noexcept;

/** Grid of the network (0 before udn_net_init()). [any] */
std::uint32_t udn_grid_cols() noexcept;
std::uint32_t udn_grid_rows() noexcept;

/**
 * Sends one packet from the current tile: words[0] is the header, words[1] the
 * tag, the rest payload; words.size() must be 1 + the header's length. [task]
 * @return kOk (queued for the next barrier), kFull (back-pressure: retry after
 *         Irq::kUdn), kBadLength, kNotInit.
 */
NetError udn_net_send(std::span<const std::uint32_t> words) noexcept;

/** A received packet and its statistics. */
struct RxPacket {
  TileId source;
  std::uint32_t tag;
  std::uint32_t payload_words;  ///< payload words (the length field minus the tag)
  Cycles send_cycle;            ///< sender's local time at the send
  Cycles arrival_cycle;         ///< modelled arrival (last word in the ejection port)
  Cycles delivered_cycle;       ///< barrier at which software could see it
};

/**
 * Pops the oldest packet of queue @p queue of the current tile, non-blocking,
 * copying up to payload.size() payload words (the rest are discarded). [task]
 * @return kOk, kEmpty, kBadQueue, kNotInit.
 */
NetError udn_net_receive(std::uint32_t queue, RxPacket& out, std::span<std::uint32_t> payload) noexcept;

/** Packets waiting in a queue (0 for bad arguments). [task|isr|host] */
std::uint32_t udn_net_queue_packets(TileId tile, std::uint32_t queue) noexcept;

/** True if the tile may send (fewer than the maximum packets in flight). [task|isr|host] */
bool udn_net_can_send(TileId tile) noexcept;

/**
 * Packets the tile may still put in flight (the send credits its network
 * interface shows; 0 for a tile off the grid). [task|isr|host]
 */
std::uint32_t udn_net_send_credits(TileId tile) noexcept;

/**
 * Binds @p tag to demux queue @p queue (< kUdnDemuxQueues) on @p tile; the
 * binding takes effect at the next barrier. Rebinding a tag replaces it.
 * Unbound tags go to the catch-all queue. [task|host]
 * @return kOk, kBadTile, kBadQueue, kFull (kUdnTagBindings entries used).
 */
NetError udn_net_bind(TileId tile, std::uint32_t tag, std::uint32_t queue) noexcept;

}  // namespace bsp
