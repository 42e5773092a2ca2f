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
 *
 * This header is the model's control and observation side (initialisation,
 * faults, sending or receiving as any tile, statistics), for images, tests and
 * tools. What a tile's software may do with the network is udn_driver.hpp,
 * which this header includes; flight code includes only that one.
 */
#pragma once

#include "bsp_tile64/api/memory.hpp"
#include "bsp_tile64/api/port.hpp"
#include "bsp_tile64/api/udn_driver.hpp"
#include "bsp_tile64/api/udn_hw.hpp"

#include <cstddef>
#include <cstdint>
#include <span>

namespace bsp {

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

/** Sends as tile @p src at cycle @p at, from the host (tests, tools; not during a run). [host] */
NetError udn_net_send_from(TileId src, Cycles at, std::span<const std::uint32_t> words) noexcept;

/** Same as udn_net_receive for an explicit tile (tests, host tools). [host] */
NetError udn_net_receive_on(TileId tile, std::uint32_t queue, RxPacket& out, std::span<std::uint32_t> payload) noexcept;

/** Sets the random bit-error rate per word per packet in transit (stream kFaults, index 0x0DE). [host] */
void udn_net_set_ber(double per_word_probability) noexcept;

/** Fails a switch or a link at once (the fault handlers call these too). [host] */
NetError udn_net_fail_switch(TileId tile) noexcept;
NetError udn_net_fail_link(TileId tile, UdnDir dir) noexcept;

/**
 * Network trace kinds, inside the board's range (0x0000-0x0FFF) above BoardEvent.
 * Time is the barrier cycle, tile the source tile.
 */
enum class UdnTrace : std::uint16_t {
  kLost = 0x0100,       ///< a = UdnLoss cause, b = (sequence << 8) | destination tile (or 0xFF off grid)
  kBitFlip = 0x0101,    ///< a = word index, b = bit
  kSwitchFail = 0x0102, ///< a = failed tile
  kLinkFail = 0x0103,   ///< a = tile, b = UdnDir
  kResized = 0x0104,    ///< a = sent length, b = length after a header flip
};

/** Why a packet was lost (statistics and trace): the model's truth, which a tile only sees as a missing packet. */
enum class UdnLoss : std::uint8_t {
  kOffGrid = 0,       ///< the (corrupted) header names a tile outside the grid
  kFailedSwitch = 1,  ///< the X-then-Y path crosses a failed switch (source and destination included)
  kFailedLink = 2,    ///< the path crosses a failed link
  kBadLength = 3,     ///< a corrupted length of 0 or above kUdnMaxLength
  kCount = 4,
};

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
