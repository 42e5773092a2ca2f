/**
 * @file udn_net.hpp
 * @brief The UDN mesh model: X-then-Y routing, link contention, demux queues, back-pressure, faults.
 *
 * A send puts the packet into a static in-flight pool stamped with the
 * sender's local time; nothing crosses tiles before the next quantum barrier.
 * At each barrier (a hook registered by udn_net_init) the model:
 *  1. takes the packets sent since the last barrier in (send cycle, source,
 *     sequence) order, applies network faults (armed and random bit flips,
 *     failed switches and links), and reserves their links in that order:
 *     for hop k (k = 1..H over the H mesh links, then k = H+1 for the
 *     destination's ejection port) t_k = max(t_{k-1} + hop_cycles,
 *     free_k); free_k = t_k + W; arrival = t_{H+1} + W, with t_0 the send
 *     cycle and W the packet's words including the header. Uncontended:
 *     arrival = send + (H + 1) * hop_cycles + W.
 *  2. delivers, in (arrival, source, sequence) order, every packet whose
 *     arrival is at or before the barrier into the demux queue its tag is
 *     bound to, and raises Irq::kUdn on the destination. A packet whose queue
 *     lacks room stays in flight and is retried at the next barrier; later
 *     packets for the same queue wait behind it, so per-source order holds.
 * Nothing is dropped for lack of room: each source has a bounded number of
 * packets in flight and a send beyond it returns kFull; when one of them
 * leaves the network the source gets Irq::kUdn so its driver can retry.
 *
 * Tiles: id = y * cols + x on the profile's grid. Static storage only.
 * See docs/NETWORK.md.
 */
#pragma once

#include "bsp_tile64/memory.hpp"
#include "bsp_tile64/port.hpp"
#include "bsp_tile64/udn_hw.hpp"

#include <cstddef>
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

/** Compile-time capacities of the static storage; NetConfig picks values up to them. */
inline constexpr std::uint32_t kUdnMaxInFlightPerTile = 16U;
inline constexpr std::uint32_t kUdnMaxQueueWords = 512U;
inline constexpr std::uint32_t kUdnTagBindings = 8U;

struct NetConfig {
  std::uint32_t max_in_flight_per_tile = 8U;  ///< 1..kUdnMaxInFlightPerTile
  std::uint32_t queue_words = 256U;           ///< per demux queue, words after the header; kUdnMaxLength..kUdnMaxQueueWords
};

/**
 * Resets the network (queues, pool, links, faults, statistics) for the board's
 * current profile, registers the barrier hook and the handlers of the network
 * fault kinds. Call after board_init() (which clears hooks and handlers); a
 * second call on the same board re-initialises the network (its extra hook
 * does nothing). [host]
 * @return kBadConfig for capacities out of range, kFull if no barrier hook slot is left.
 */
NetError udn_net_init(const NetConfig& config) noexcept;

/** Incremented by every successful udn_net_init(): drivers tell a new board from the last one. [any] */
std::uint32_t udn_net_generation() noexcept;

/** Grid of the network (0 before udn_net_init()). [any] */
std::uint32_t udn_grid_cols() noexcept;
std::uint32_t udn_grid_rows() noexcept;

/** Hop cycles of the current profile: ceil(hop_x16 / 16). [host|task] */
Cycles udn_hop_cycles() noexcept;

/**
 * The X-then-Y path from @p src to @p dst on a cols x rows grid as the tiles
 * visited, source and destination included, into @p out.
 * @return the number of tiles written (hops + 1), 0 if a tile is off the grid
 *         or @p out is too small. [any]
 */
std::size_t udn_route(std::uint32_t cols, std::uint32_t rows, TileId src, TileId dst, std::span<TileId> out) noexcept;

/** Direction of the link from @p from to its neighbour @p to (both on the grid). [any] */
UdnDir udn_dir(std::uint32_t cols, TileId from, TileId to) noexcept;

/**
 * Sends one packet from the current tile: words[0] is the header, words[1] the
 * tag, the rest payload; words.size() must be 1 + the header's length. [task]
 * @return kOk (queued for the next barrier), kFull (back-pressure: retry after
 *         Irq::kUdn), kBadLength, kNotInit.
 */
NetError udn_net_send(std::span<const std::uint32_t> words) noexcept;

/** Sends as tile @p src at cycle @p at, from the host (tests, tools; not during a run). [host] */
NetError udn_net_send_from(TileId src, Cycles at, std::span<const std::uint32_t> words) noexcept;

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

/** Same as udn_net_receive for an explicit tile (tests, host tools). [host] */
NetError udn_net_receive_on(TileId tile, std::uint32_t queue, RxPacket& out, std::span<std::uint32_t> payload) noexcept;

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

/** Sets the random bit-error rate per word per packet in transit (stream kFaults, index 0x0DE). [host] */
void udn_net_set_ber(double per_word_probability) noexcept;

/** Fails a switch or a link at once (the fault handlers call these too). [host] */
NetError udn_net_fail_switch(TileId tile) noexcept;
NetError udn_net_fail_link(TileId tile, UdnDir dir) noexcept;

/** Network statistics since udn_net_init(). */
struct NetStats {
  std::uint64_t sent;
  std::uint64_t delivered;
  std::uint64_t refused_full;      ///< sends refused for back-pressure (kFull)
  std::uint64_t queue_full_retries;///< packet-barriers spent waiting for room in a demux queue
  std::uint64_t lost[static_cast<std::size_t>(UdnLoss::kCount)];
  std::uint64_t bit_flips;         ///< words corrupted in transit (armed or random)
  std::uint64_t words_truncated;   ///< words dropped by a shortened length field
  std::uint64_t words_padded;      ///< zero words added by a lengthened length field
  Cycles latency_min;              ///< arrival - send over delivered packets (0 if none)
  Cycles latency_max;
  std::uint64_t latency_sum;
  [[nodiscard]] double latency_mean() const noexcept {
    return delivered == 0U ? 0.0 : static_cast<double>(latency_sum) / static_cast<double>(delivered);
  }
  [[nodiscard]] std::uint64_t lost_total() const noexcept {
    return lost[0] + lost[1] + lost[2] + lost[3];
  }
};
NetStats udn_net_stats() noexcept;

/** Cycles the link leaving @p tile in @p dir carried words, since init. [host] */
Cycles udn_link_busy_cycles(TileId tile, UdnDir dir) noexcept;

/** Packets in flight (sent, not yet delivered or lost). [host] */
std::uint32_t udn_net_in_flight() noexcept;

}  // namespace bsp
