/**
 * @file udn_stress_payload.cpp
 * @brief udn_stress payloads: stamping and checking (see udn_stress_payload.hpp for the layout).
 */
#include "tools/common/udn_stress/udn_stress_payload.hpp"

#include "udn/crc32c.hpp"

#include <array>

namespace tools {
namespace {

constexpr std::uint32_t kLow16 = 0xFFFFU;
constexpr std::uint32_t kSaltFields = 0x5354'0000U;  // any constant: keeps word 0's check apart from word 1's

/** Top half of the CRC-32C of (value, salt): CRC is linear, so a flip in value always moves it (tested). */
std::uint32_t check16(std::uint32_t value, std::uint32_t salt) noexcept {
  const std::array<std::uint32_t, 2> w{value, salt};
  return udn::crc32c_words(w) >> 16U;
}

std::uint32_t filler(std::uint32_t w0, std::uint32_t w1, std::uint32_t i) noexcept {
  std::uint32_t h = (w0 * 0x9E3779B1U) ^ (w1 * 0x85EBCA77U) ^ (i * 0xC2B2AE3DU);
  h ^= h >> 15U;
  h *= 0x2C1B3C6DU;
  return h ^ (h >> 12U);
}

std::uint32_t word0(const PayloadStamp& s) noexcept {
  const std::uint32_t fields = (s.dest & 0xFFU) | ((s.source & 0xFFU) << 8U);
  return fields | (check16(fields, kSaltFields) << 16U);
}

std::uint32_t word1(std::uint32_t w0, std::uint16_t number) noexcept {
  return number | (check16(number, w0) << 16U);
}

}  // namespace

void stamp_payload(const PayloadStamp& stamp, std::span<std::uint32_t> out) noexcept {
  if (out.empty()) {
    return;
  }
  const std::uint32_t w0 = word0(stamp);
  out[0] = w0;
  const std::uint32_t w1 = out.size() > 1U ? word1(w0, stamp.number) : 0U;
  if (out.size() > 1U) {
    out[1] = w1;
  }
  for (std::size_t i = 2U; i < out.size(); ++i) {
    out[i] = filler(w0, w1, static_cast<std::uint32_t>(i));
  }
}

PayloadVerdict check_payload(std::span<const std::uint32_t> words, std::uint32_t received_words,
                             std::uint32_t sent_words, bsp::TileId source, bsp::TileId self,
                             PayloadStamp& out) noexcept {
  if (received_words != sent_words || words.size() != sent_words || words.empty()) {
    return PayloadVerdict::kCorrupted;
  }
  const std::uint32_t w0 = words[0];
  if ((w0 >> 16U) != check16(w0 & kLow16, kSaltFields) || ((w0 >> 8U) & 0xFFU) != (source & 0xFFU)) {
    return PayloadVerdict::kCorrupted;
  }
  out.source = source;
  out.dest = w0 & 0xFFU;
  out.number = 0U;
  if (words.size() > 1U) {
    const std::uint32_t w1 = words[1];
    if ((w1 >> 16U) != check16(w1 & kLow16, w0)) {
      return PayloadVerdict::kCorrupted;
    }
    out.number = static_cast<std::uint16_t>(w1 & kLow16);
    for (std::size_t i = 2U; i < words.size(); ++i) {
      if (words[i] != filler(w0, w1, static_cast<std::uint32_t>(i))) {
        return PayloadVerdict::kCorrupted;
      }
    }
  }
  return out.dest == (self & 0xFFU) ? PayloadVerdict::kIntact : PayloadVerdict::kMisdelivered;
}

}  // namespace tools
