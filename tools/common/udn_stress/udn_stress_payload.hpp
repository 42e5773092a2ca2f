/**
 * @file udn_stress_payload.hpp
 * @brief udn_stress payloads: what a sender writes and how a receiver tells an intact, corrupted or misdelivered one.
 *
 * Both runs (raw and --ft on) stamp every payload the same way, so their
 * reports count the same things:
 *  - word 0: destination (bits 0..7), source (bits 8..15), a 16-bit check of
 *    those two fields (bits 16..31);
 *  - word 1 (words >= 2): the sender's packet number modulo 2^16 (bits 0..15)
 *    and a 16-bit check of it and word 0 (bits 16..31);
 *  - words 2..: a hash of words 0 and 1 and the word's index.
 * The checks are the top half of a CRC-32C over the field and a salt, so the
 * receiver detects every single-bit flip of word 0 and word 1 on its own
 * (tests/tools/udn_stress/udn_stress_payload_test.cpp checks every one);
 * a flip in a later word changes it from its hash. A payload whose words
 * check but whose destination is another tile arrived at the wrong tile (a
 * flipped header routed it there).
 */
#pragma once

#include "bsp_tile64/api/port.hpp"

#include <cstdint>
#include <span>

namespace tools {

/** What a payload says about its packet. */
struct PayloadStamp {
  bsp::TileId source = 0U;
  bsp::TileId dest = 0U;
  std::uint16_t number = 0U;  ///< the sender's packet number modulo 2^16 (0 when the payload has one word)
};

enum class PayloadVerdict : std::uint8_t {
  kIntact,        ///< every word as sent, at the tile it was sent to
  kCorrupted,     ///< a word differs from what the sender wrote, or the length does
  kMisdelivered,  ///< every word as sent, at another tile than its destination
};

/** Writes the payload of @p stamp into every word of @p out (1 or more words; tiles below 256). */
void stamp_payload(const PayloadStamp& stamp, std::span<std::uint32_t> out) noexcept;

/**
 * Checks a received payload.
 * @param words         the words received (at most the receiver's buffer)
 * @param received_words the packet's payload length as received (may exceed words.size())
 * @param sent_words    the length every sender uses
 * @param source        the tile the packet came from, as the network or the layer reports it
 * @param self          the receiving tile
 * @param out           the stamp read, filled when the verdict is not kCorrupted
 */
[[nodiscard]] PayloadVerdict check_payload(std::span<const std::uint32_t> words, std::uint32_t received_words,
                                           std::uint32_t sent_words, bsp::TileId source, bsp::TileId self,
                                           PayloadStamp& out) noexcept;

}  // namespace tools
