/**
 * @file ft_packet.hpp
 * @brief Fault-tolerant UDN packet codec (paper Fig. 5): SECDED-protected header and payload.
 *
 * Packet image, 32-bit words (bit 31 = MSB):
 *   word 0  hardware route header: [31..24] reserved (0) | [23..16] dest x |
 *           [15..8] dest y | [7..0] length = words after this one
 *   word 1  hardware tag (selects the receiving demux queue)
 *   word 2  [31..29] 0 | [28..16] data ECC (13 bits) | [15..9] 0 | [8..0] route ECC (9 bits)
 *   word 3  route data: [31..16] destination index | [15..8] flags | [7..0] data length (1..124)
 *           flags: bit 8 (kFlagCrc) = a CRC-32C word follows the data; bits 9..15 are 0
 *           (with kFlagCrc the data ECC is XORed with kCrcFlagEccSalt)
 *   word 4  channel tag
 *   words 5 .. 5+n-1   n data words, 1 <= n <= 124
 *   word 5+n (only with kFlagCrc)  CRC-32C of words 3 .. 5+n-1
 *
 * Codes (udn/ecc.hpp): the route code ("length ECC" in Fig. 5, 9 check bits)
 * covers words 0, 1, 3 and 4; the data code (13 check bits) covers the data
 * words and the CRC word. Every single-bit error in any word is corrected:
 * data and CRC bits by the data code, route and hardware-header bits by the
 * route code, ECC bits by the code they belong to, and a set reserved bit of
 * word 2 by clearing it. One error in each code is corrected together.
 *
 * Why the hardware words are in the route code: the hardware strips words 0
 * and 1, but the receiver knows what they were when they arrived: its own x,y,
 * the number of words delivered and the tag of the queue it read from. It
 * rebuilds them (make_hw_header / the tag) and decodes the full image. If a
 * flipped header bit sent the packet to the wrong tile or queue, the rebuilt
 * word differs from the sent one in exactly that bit: the route code locates
 * it (Decoded::header_hit), so the fault is counted and attributed, and the
 * protected destination index and channel tell where the packet belongs.
 * A forwarder rewrites words 0, 1 and the route ECC (readdress_packet); the
 * data ECC and CRC do not depend on the route and are never recomputed.
 *
 * All functions are bounded (at most kMaxPacketWords words), use no heap and
 * never read beyond the given span.
 */
#pragma once

#include "bsp_tile64/api/work.hpp"

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>

namespace udn {

inline constexpr std::size_t kFtHeaderWords = 5;
inline constexpr std::size_t kFtMinDataWords = 1;
inline constexpr std::size_t kFtMaxDataWords = 124;
/** Largest packet image: header, 124 data words and the CRC word. */
inline constexpr std::size_t kFtMaxPacketWords = kFtHeaderWords + kFtMaxDataWords + 1;
inline constexpr std::size_t kFtMinPacketWords = kFtHeaderWords + kFtMinDataWords;

/** Word indices in the packet image. */
inline constexpr std::size_t kWordHwHeader = 0;
inline constexpr std::size_t kWordHwTag = 1;
inline constexpr std::size_t kWordEcc = 2;
inline constexpr std::size_t kWordRouteData = 3;
inline constexpr std::size_t kWordChannel = 4;
inline constexpr std::size_t kWordData = 5;

/** Word 3 flag: a CRC-32C word follows the data. */
inline constexpr std::uint32_t kFlagCrc = 1U << 8U;
/** Word 2: bits that carry no check bit and must be zero. */
inline constexpr std::uint32_t kEccReservedMask = 0xE000FE00U;
/** Word 0: reserved bits, zero when sent. */
inline constexpr std::uint32_t kHwReservedMask = 0xFF000000U;

/** Hardware route header word (word 0). length_words counts the words after it. */
constexpr std::uint32_t make_hw_header(std::uint8_t dest_x, std::uint8_t dest_y,
                                       std::uint8_t length_words) noexcept {
  return (static_cast<std::uint32_t>(dest_x) << 16U) | (static_cast<std::uint32_t>(dest_y) << 8U) |
         static_cast<std::uint32_t>(length_words);
}

/** Number of words of a packet image with n data words (+1 with CRC). */
constexpr std::size_t ft_packet_words(std::size_t data_words, bool with_crc) noexcept {
  return kFtHeaderWords + data_words + (with_crc ? 1U : 0U);
}

/** What a sender chooses; what a receiver gets back. */
struct FtFields {
  std::uint8_t dest_x = 0;        ///< hardware destination (this leg)
  std::uint8_t dest_y = 0;
  std::uint16_t dest_index = 0;   ///< logical tile index of the final destination
  std::uint32_t hw_tag = 0;       ///< hardware demux tag (word 1)
  std::uint32_t channel = 0;      ///< channel tag (word 4)
  bool with_crc = false;          ///< append the CRC-32C word
};

enum class EncodeStatus : std::uint8_t {
  kOk,
  kBadLength,       ///< data is empty or longer than kFtMaxDataWords
  kBufferTooSmall,  ///< out cannot hold ft_packet_words(data.size(), with_crc)
};

/**
 * Builds the packet image into out[0 .. ft_packet_words(n, with_crc)).
 * written = number of words written (0 on error). out is untouched on error.
 */
EncodeStatus encode_packet(const FtFields& fields, std::span<const std::uint32_t> data,
                           std::span<std::uint32_t> out, std::size_t& written) noexcept;

enum class DecodeStatus : std::uint8_t {
  kOk,             ///< valid, for this tile, no error
  kCorrected,      ///< valid, for this tile, 1 bit (or 1 per code) corrected in place
  kMisdelivered,   ///< valid (maybe corrected) but dest index is another tile: forward it
  kUncorrectable,  ///< an error the codes detect but cannot correct (2+ bits in one code)
  kCrcMismatch,    ///< the codes passed but the CRC-32C word does not match
  kMalformed,      ///< word count out of range or not matching the lengths, reserved bits set
};

/** One corrected bit, in packet-image coordinates. */
struct BitFix {
  std::uint16_t word = 0;
  std::uint8_t bit = 0;
};

struct Decoded {
  DecodeStatus status = DecodeStatus::kMalformed;
  /** Valid for kOk, kCorrected and kMisdelivered. */
  FtFields fields{};
  std::uint16_t data_words = 0;
  /** Bits corrected in place (0..2, at most one per code). */
  std::uint8_t fix_count = 0;
  std::array<BitFix, 2> fixes{};
  /** A hardware-header bit (word 0 or 1) was corrected: misrouted or misqueued in transit. */
  bool header_hit = false;
};

/**
 * Whether the receiver insists on the CRC word. The flag that announces it sits
 * in word 3, which only the route code protects: three or more errors there
 * can be miscorrected into "no CRC, one more data word" with the same word
 * count, and the CRC is then never checked. A system that relies on the CRC
 * (e.g. every channel of a mission image) decodes with kRequired, so such a
 * packet is rejected as kMalformed. (The data ECC is also salted by the flag,
 * which catches most such cases with kAsFlagged.)
 */
enum class CrcPolicy : std::uint8_t { kAsFlagged, kRequired };

/** XORed into the data ECC when the CRC flag is set; even weight, so a flag flip alone reads as a double error. */
inline constexpr std::uint32_t kCrcFlagEccSalt = 0x0003U;

/**
 * Checks and corrects a received packet image in place.
 * words: the full image; words 0 and 1 as the receiver observed them (see the
 * file comment). my_index: this tile's logical index. crc_policy: see CrcPolicy;
 * with kRequired a packet without the CRC flag is kMalformed.
 * Post: on kOk/kCorrected/kMisdelivered the words equal the image as sent
 * (corrections applied) and the data is words[5 .. 5+data_words). On any other
 * status the words are left exactly as given.
 */
Decoded decode_packet(std::span<std::uint32_t> words, std::uint16_t my_index,
                      CrcPolicy crc_policy = CrcPolicy::kAsFlagged) noexcept;

/** The data words of a packet that decoded valid (empty otherwise). */
std::span<const std::uint32_t> packet_data(std::span<const std::uint32_t> words, const Decoded& d) noexcept;

enum class ReaddressStatus : std::uint8_t { kOk, kMalformed };

/**
 * Points a valid (decoded) packet at a new hardware destination for the next
 * leg: rewrites words 0 and 1 and the route ECC; data ECC and CRC are kept.
 * Pre: the words are a correct image (e.g. after decode_packet said valid).
 */
ReaddressStatus readdress_packet(std::span<std::uint32_t> words, std::uint8_t dest_x, std::uint8_t dest_y,
                                 std::uint32_t hw_tag) noexcept;

/** Work charged for encoding or decoding one packet of data_words (+CRC). */
bsp::Work ft_codec_work(std::size_t data_words, bool with_crc) noexcept;

}  // namespace udn
