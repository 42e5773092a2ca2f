/**
 * @file crc32c.hpp
 * @brief CRC-32C (Castagnoli, reflected polynomial 0x82F63B78), table-driven, over words.
 *
 * Used as the optional trailing check word of fault-tolerant packets: SECDED
 * alone can deliver a corrupt packet without notice when three or more bits
 * are wrong; CRC-32C detects every burst of up to 32 bits and every error of
 * up to 5 bits in packets of this size (Hamming distance 6 up to 5243 bytes).
 * Standard parameters: init 0xFFFFFFFF, final XOR 0xFFFFFFFF, reflected;
 * crc32c("123456789") = 0xE3069283. A 32-bit word is fed as its four bytes
 * in little-endian order (the TILE64 and host byte order).
 */
#pragma once

#include <cstdint>
#include <span>

namespace udn {

/** CRC-32C of bytes. Bounded: one table step per byte. */
std::uint32_t crc32c_bytes(std::span<const std::uint8_t> bytes) noexcept;

/**
 * CRC-32C of words taken as little-endian bytes; equal to crc32c_bytes of the
 * same memory on a little-endian machine. Slicing-by-4: one 4-lookup step per word.
 */
std::uint32_t crc32c_words(std::span<const std::uint32_t> words) noexcept;

/** Continues a CRC over more words: pass the previous result; same final value as one call. */
std::uint32_t crc32c_words_continue(std::uint32_t crc, std::span<const std::uint32_t> words) noexcept;

}  // namespace udn
