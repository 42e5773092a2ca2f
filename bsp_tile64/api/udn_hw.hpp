/**
 * @file udn_hw.hpp
 * @brief UDN hardware vocabulary: the route header word, link directions, demux queues, limits.
 *
 * Header word (word 0 of every packet), bit 31 = MSB:
 *   [31..24] reserved (0) | [23..16] dest x | [15..8] dest y | [7..0] length
 * where length counts the words after the header: the tag word (word 1) and
 * the payload. This is the layout udn/ft_packet.hpp builds on; the board keeps
 * its own copy so it never includes a layer above it.
 *
 * The largest length the model accepts is kUdnMaxLength = 129 words (tag and
 * up to 128 payload words, so a fault-tolerant packet of 3 + 124 + CRC fits).
 * The real TILE64 limit is not confirmed (FACTS.md: "at most 126 data words
 * [U]"): treat it as a configurable default, not a fact.
 */
#pragma once

#include <cstdint>

namespace bsp {

/** Largest length field (words after the header) the network carries. Configurable default. */
inline constexpr std::uint32_t kUdnMaxLength = 129U;
/** Largest packet: header word plus kUdnMaxLength words. */
inline constexpr std::uint32_t kUdnMaxPacketWords = kUdnMaxLength + 1U;
/** Smallest length of a packet that software sends: the tag word alone. */
inline constexpr std::uint32_t kUdnMinLength = 1U;

/** Demux queues selected by tag binding, plus the catch-all queue for unbound tags. */
inline constexpr std::uint32_t kUdnDemuxQueues = 4U;
inline constexpr std::uint32_t kUdnCatchAll = kUdnDemuxQueues;
inline constexpr std::uint32_t kUdnQueues = kUdnDemuxQueues + 1U;

/** Output directions of a switch. y grows southwards (row index), x eastwards (column). */
enum class UdnDir : std::uint8_t { kEast = 0, kWest = 1, kNorth = 2, kSouth = 3 };
inline constexpr std::uint32_t kUdnDirs = 4U;

/** Builds a header word. */
constexpr std::uint32_t udn_make_header(std::uint32_t dest_x, std::uint32_t dest_y, std::uint32_t length) noexcept {
  return ((dest_x & 0xFFU) << 16U) | ((dest_y & 0xFFU) << 8U) | (length & 0xFFU);
}
constexpr std::uint32_t udn_header_x(std::uint32_t header) noexcept { return (header >> 16U) & 0xFFU; }
constexpr std::uint32_t udn_header_y(std::uint32_t header) noexcept { return (header >> 8U) & 0xFFU; }
constexpr std::uint32_t udn_header_length(std::uint32_t header) noexcept { return header & 0xFFU; }

static_assert(udn_header_x(udn_make_header(7U, 3U, 129U)) == 7U, "header x");
static_assert(udn_header_y(udn_make_header(7U, 3U, 129U)) == 3U, "header y");
static_assert(udn_header_length(udn_make_header(7U, 3U, 129U)) == 129U, "header length");
static_assert(kUdnMaxLength <= 0xFFU, "the length field is 8 bits");

}  // namespace bsp
