/**
 * @file ft_packet.cpp
 * @brief Encode, check/correct and re-address fault-tolerant UDN packets (Fig. 5).
 */
#include "udn/ft_packet.hpp"

#include "udn/crc32c.hpp"
#include "udn/ecc.hpp"

#include <bit>

namespace udn {
namespace {

/** Packet words covered by the route code, in code order. */
constexpr std::array<std::size_t, kRouteCodeWords> kRouteWordIndex = {kWordHwHeader, kWordHwTag, kWordRouteData,
                                                                      kWordChannel};
constexpr std::uint32_t kLengthMask = 0xFFU;
constexpr std::uint32_t kFlagsMask = 0xFF00U;
constexpr unsigned kDataEccShift = 16U;
constexpr std::size_t kRouteData = 2;  // index of word 3 in the route-code array
constexpr std::size_t kRouteHw = 0;    // index of word 0 in the route-code array

std::array<std::uint32_t, kRouteCodeWords> route_words(std::span<const std::uint32_t> words) noexcept {
  std::array<std::uint32_t, kRouteCodeWords> r{};
  for (std::size_t i = 0; i < kRouteCodeWords; ++i) {
    r[i] = words[kRouteWordIndex[i]];
  }
  return r;
}

std::size_t coded_data_words(std::uint32_t route_data) noexcept {
  return (route_data & kLengthMask) + (((route_data & kFlagCrc) != 0U) ? 1U : 0U);
}

void add_fix(Decoded& d, std::size_t word, unsigned bit) noexcept {
  if (d.fix_count < d.fixes.size()) {
    d.fixes[d.fix_count] = BitFix{static_cast<std::uint16_t>(word), static_cast<std::uint8_t>(bit)};
    ++d.fix_count;
  }
}

/** Records a route-code correction and applies it to the local route copy. */
void take_route_fix(const EccCheck& c, std::array<std::uint32_t, kRouteCodeWords>& route, Decoded& d) noexcept {
  if (c.status == EccStatus::kCorrectedData) {
    route[c.word] ^= 1U << c.bit;
    const std::size_t word = kRouteWordIndex[c.word];
    add_fix(d, word, c.bit);
    d.header_hit = word == kWordHwHeader || word == kWordHwTag;
  } else if (c.status == EccStatus::kCorrectedCheck) {
    add_fix(d, kWordEcc, c.bit);
  }
}

void take_data_fix(const EccCheck& c, Decoded& d) noexcept {
  if (c.status == EccStatus::kCorrectedData) {
    add_fix(d, kWordData + c.word, c.bit);
  } else if (c.status == EccStatus::kCorrectedCheck) {
    add_fix(d, kWordEcc, kDataEccShift + c.bit);
  }
}

/** Lengths, flags and reserved bits of the (corrected) route words against the word count. */
bool shape_ok(const std::array<std::uint32_t, kRouteCodeWords>& route, std::size_t count) noexcept {
  const std::uint32_t hw = route[kRouteHw];
  const std::uint32_t rd = route[kRouteData];
  const std::uint32_t n = rd & kLengthMask;
  const bool flags_ok = (rd & kFlagsMask & ~kFlagCrc) == 0U;
  const bool length_ok = n >= kFtMinDataWords && n <= kFtMaxDataWords;
  const bool count_ok = count == kFtHeaderWords + coded_data_words(rd);
  const bool hw_ok = (hw & kHwReservedMask) == 0U && (hw & kLengthMask) == count - 1U;
  return flags_ok && length_ok && count_ok && hw_ok;
}

void apply_fixes(std::span<std::uint32_t> words, const Decoded& d) noexcept {
  for (std::size_t i = 0; i < d.fix_count && i < d.fixes.size(); ++i) {
    words[d.fixes[i].word] ^= 1U << d.fixes[i].bit;
  }
}

bool crc_ok(std::span<const std::uint32_t> words, std::size_t data_words) noexcept {
  const std::uint32_t crc = crc32c_words(words.subspan(kWordRouteData, 2U + data_words));
  return crc == words[kWordData + data_words];
}

FtFields fields_of(std::span<const std::uint32_t> words) noexcept {
  const std::uint32_t hw = words[kWordHwHeader];
  const std::uint32_t rd = words[kWordRouteData];
  FtFields f{};
  f.dest_x = static_cast<std::uint8_t>((hw >> 16U) & 0xFFU);
  f.dest_y = static_cast<std::uint8_t>((hw >> 8U) & 0xFFU);
  f.dest_index = static_cast<std::uint16_t>(rd >> 16U);
  f.hw_tag = words[kWordHwTag];
  f.channel = words[kWordChannel];
  f.with_crc = (rd & kFlagCrc) != 0U;
  return f;
}

/** A set reserved bit of word 2 is corrected only when it is the packet's one error. */
bool take_reserved_fix(std::uint32_t ecc_word, Decoded& d) noexcept {
  const std::uint32_t reserved = ecc_word & kEccReservedMask;
  if (reserved == 0U) {
    return true;
  }
  if (std::popcount(reserved) != 1 || d.fix_count != 0U) {
    return false;
  }
  add_fix(d, kWordEcc, static_cast<unsigned>(std::countr_zero(reserved)));
  return true;
}

}  // namespace

EncodeStatus encode_packet(const FtFields& fields, std::span<const std::uint32_t> data,
                           std::span<std::uint32_t> out, std::size_t& written) noexcept {
  written = 0;
  const std::size_t n = data.size();
  if (n < kFtMinDataWords || n > kFtMaxDataWords) {
    return EncodeStatus::kBadLength;
  }
  const std::size_t total = ft_packet_words(n, fields.with_crc);
  if (out.size() < total) {
    return EncodeStatus::kBufferTooSmall;
  }
  out[kWordHwHeader] = make_hw_header(fields.dest_x, fields.dest_y, static_cast<std::uint8_t>(total - 1U));
  out[kWordHwTag] = fields.hw_tag;
  out[kWordRouteData] = (static_cast<std::uint32_t>(fields.dest_index) << 16U) |
                        (fields.with_crc ? kFlagCrc : 0U) | static_cast<std::uint32_t>(n);
  out[kWordChannel] = fields.channel;
  for (std::size_t i = 0; i < n; ++i) {
    out[kWordData + i] = data[i];
  }
  if (fields.with_crc) {
    out[kWordData + n] = crc32c_words(out.subspan(kWordRouteData, 2U + n));
  }
  const std::uint32_t route_check = RouteCode::encode(route_words(out));
  const std::uint32_t data_check =
      DataCode::encode(out.subspan(kWordData, total - kWordData)) ^ (fields.with_crc ? kCrcFlagEccSalt : 0U);
  out[kWordEcc] = (data_check << kDataEccShift) | route_check;
  written = total;
  return EncodeStatus::kOk;
}

Decoded decode_packet(std::span<std::uint32_t> words, std::uint16_t my_index, CrcPolicy crc_policy) noexcept {
  Decoded d{};
  if (words.size() < kFtMinPacketWords || words.size() > kFtMaxPacketWords) {
    return d;  // kMalformed: nothing beyond the given count is read
  }
  std::array<std::uint32_t, kRouteCodeWords> route = route_words(words);
  const std::uint32_t ecc = words[kWordEcc];
  const EccCheck rc = RouteCode::check(route, ecc & RouteCode::kCheckMask);
  if (rc.status == EccStatus::kUncorrectable) {
    d.status = DecodeStatus::kUncorrectable;
    return d;
  }
  take_route_fix(rc, route, d);
  const bool has_crc = (route[kRouteData] & kFlagCrc) != 0U;
  if (!shape_ok(route, words.size()) || (crc_policy == CrcPolicy::kRequired && !has_crc)) {
    d = Decoded{};  // kMalformed; fixes are discarded, words untouched
    return d;
  }
  const std::size_t coded = coded_data_words(route[kRouteData]);
  const std::uint32_t salt = has_crc ? kCrcFlagEccSalt : 0U;
  const EccCheck dc =
      DataCode::check(words.subspan(kWordData, coded), ((ecc >> kDataEccShift) ^ salt) & DataCode::kCheckMask);
  if (dc.status == EccStatus::kUncorrectable) {
    d = Decoded{};
    d.status = DecodeStatus::kUncorrectable;
    return d;
  }
  take_data_fix(dc, d);
  if (!take_reserved_fix(ecc, d)) {
    d = Decoded{};
    d.status = DecodeStatus::kUncorrectable;
    return d;
  }
  apply_fixes(words, d);
  const std::size_t n = route[kRouteData] & kLengthMask;
  if (has_crc && !crc_ok(words, n)) {
    apply_fixes(words, d);  // flips are involutions: this restores the input
    d = Decoded{};
    d.status = DecodeStatus::kCrcMismatch;
    return d;
  }
  d.fields = fields_of(words);
  d.data_words = static_cast<std::uint16_t>(n);
  if (d.fields.dest_index != my_index) {
    d.status = DecodeStatus::kMisdelivered;
  } else {
    d.status = d.fix_count == 0U ? DecodeStatus::kOk : DecodeStatus::kCorrected;
  }
  return d;
}

std::span<const std::uint32_t> packet_data(std::span<const std::uint32_t> words, const Decoded& d) noexcept {
  const bool valid = d.status == DecodeStatus::kOk || d.status == DecodeStatus::kCorrected ||
                     d.status == DecodeStatus::kMisdelivered;
  if (!valid || words.size() < kWordData + d.data_words) {
    return {};
  }
  return words.subspan(kWordData, d.data_words);
}

ReaddressStatus readdress_packet(std::span<std::uint32_t> words, std::uint8_t dest_x, std::uint8_t dest_y,
                                 std::uint32_t hw_tag) noexcept {
  if (words.size() < kFtMinPacketWords || words.size() > kFtMaxPacketWords) {
    return ReaddressStatus::kMalformed;
  }
  words[kWordHwHeader] = make_hw_header(dest_x, dest_y, static_cast<std::uint8_t>(words.size() - 1U));
  words[kWordHwTag] = hw_tag;
  const std::uint32_t route_check = RouteCode::encode(route_words(words));
  words[kWordEcc] = (words[kWordEcc] & ~RouteCode::kCheckMask) | route_check;
  return ReaddressStatus::kOk;
}

bsp::Work ft_codec_work(std::size_t data_words, bool with_crc) noexcept {
  // Per coded word: 16 AND/XOR lanes and a load; per code: R popcounts and a
  // table lookup; CRC: about 8 operations per word (4 lookups, shifts, XOR).
  const std::size_t coded = data_words + (with_crc ? 1U : 0U);
  bsp::Work w{};
  w.int_ops = (coded + kRouteCodeWords) * 2U * detail::kEccLanes + std::size_t{64};
  w.int_ops += with_crc ? (data_words + 2U) * 8U : 0U;
  w.mem_words = ft_packet_words(data_words, with_crc) + (with_crc ? (data_words + 2U) * 4U : 0U);
  return w;
}

}  // namespace udn
