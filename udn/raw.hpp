/**
 * @file raw.hpp
 * @brief The raw UDN messaging API in the style of the TILE library: activate, headers, send, receive, bind.
 *
 * One instance per tile, used by that tile's tasks. activate() installs the
 * kernel interrupt hook of Irq::kUdn; the hook gives a binary semaphore per
 * demux queue that holds packets and one for "the network takes sends
 * again", so blocking calls sleep in the kernel (with a timeout in ticks)
 * instead of polling. One receiving task per queue is assumed (a second one
 * would only see spurious wake-ups, never lose a packet).
 *
 * The network model is bsp_tile64/emu/udn_net.hpp; see docs/NETWORK.md.
 */
#pragma once

#include "bsp_tile64/api/udn_hw.hpp"
#include "bsp_tile64/api/udn_driver.hpp"
#include "kernel/types.hpp"

#include <cstdint>
#include <span>

namespace udn {

enum class RawError : std::uint8_t {
  kOk,
  kNotActive,   ///< activate() was not called on this tile, or the network is not initialised
  kBadTile,     ///< destination off the grid
  kBadLength,   ///< 0 or more than kMaxDataWords data words
  kBadQueue,    ///< queue index out of range (bind: >= kDemuxQueues; receive: >= kQueues)
  kTimeout,     ///< the timeout expired (send: the network kept refusing; receive: nothing came)
  kWouldBlock,  ///< kNoWait and the call would have had to wait
  kFull,        ///< bind: the tile's tag table is full
  kKernel,      ///< the kernel refused a call (not on a task, ISR hook not installed)
};

inline constexpr std::uint32_t kDemuxQueues = bsp::kUdnDemuxQueues;
inline constexpr std::uint32_t kCatchAll = bsp::kUdnCatchAll;
inline constexpr std::uint32_t kQueues = bsp::kUdnQueues;
/** Data words in one send: the length field also counts the tag. */
inline constexpr std::uint32_t kMaxDataWords = bsp::kUdnMaxLength - 1U;

/** Header word for tile (x, y) and @p data_words data words (the tag is added to the length). [any] */
constexpr std::uint32_t header_xy(std::uint32_t x, std::uint32_t y, std::uint32_t data_words) noexcept {
  return bsp::udn_make_header(x, y, data_words + 1U);
}

/**
 * Header word for tile index @p dest on the current board's grid. [task|host]
 * @return kBadTile off the grid, kBadLength for 0 or > kMaxDataWords words.
 */
RawError header_for(bsp::TileId dest, std::uint32_t data_words, std::uint32_t& header) noexcept;

/**
 * Makes the current tile's UDN usable from its tasks: clears its semaphores and
 * installs the ISR hook. Idempotent on one board: every task of the tile may
 * call it. [task]
 */
RawError activate() noexcept;

/**
 * Sends @p data (1..kMaxDataWords words) with @p tag to tile @p dest. While
 * the network refuses for back-pressure the task sleeps until the network
 * frees a slot, at most @p to ticks in all. [task]
 * @return kOk, kWouldBlock (kNoWait and refused), kTimeout, kBadTile, kBadLength, kNotActive.
 */
RawError send(bsp::TileId dest, std::uint32_t tag, std::span<const std::uint32_t> data, k::Timeout to) noexcept;

/** What came with a received packet. */
struct RxInfo {
  bsp::TileId source;
  std::uint32_t tag;
  std::uint32_t data_words;  ///< words of the packet (may exceed what fitted in the buffer)
  bsp::Cycles send_cycle;
  bsp::Cycles arrival_cycle;
};

/**
 * Receives the oldest packet of demux queue @p queue (kCatchAll for unbound
 * tags), copying at most data.size() words. Waits up to @p to ticks;
 * k::kNoWait makes it non-blocking. [task]
 * @return kOk, kWouldBlock, kTimeout, kBadQueue, kNotActive.
 */
RawError receive(std::uint32_t queue, RxInfo& info, std::span<std::uint32_t> data, k::Timeout to) noexcept;

/** Binds @p tag to demux queue @p queue (< kDemuxQueues) on the current tile. [task] */
RawError bind(std::uint32_t tag, std::uint32_t queue) noexcept;

}  // namespace udn
