/**
 * @file ft_packet_fuzz.cpp
 * @brief libFuzzer target for the fault-tolerant packet receive path (udn::decode_packet).
 *
 * Built by `make fuzz` (mk/fuzz.mk) with clang++ -fsanitize=fuzzer,address,undefined.
 * Two input modes, chosen by the first byte:
 *  - raw: the rest of the input is the received word array, as is;
 *  - structured: the input chooses the fields, length and data of a correct
 *    packet and up to four bit flips; then exact outcomes are known (0 flips:
 *    ok; 1 flip: corrected exactly; 2 flips: corrected exactly or rejected).
 * For every decode: a packet reported valid must be what re-encoding its
 * decoded content gives, differing from the received words in exactly the
 * reported corrected bits (at most one per code); a rejected packet must be
 * left untouched. Any violation aborts.
 */
#include "tests/fuzz/fuzz_check.hpp"
#include "udn/ft_packet.hpp"

#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <vector>

namespace {

using fuzz::Reader;

void require(bool ok) { fuzz::require(ok, "packet codec property"); }

bool is_valid(udn::DecodeStatus s) {
  return s == udn::DecodeStatus::kOk || s == udn::DecodeStatus::kCorrected || s == udn::DecodeStatus::kMisdelivered;
}

/** Decodes a copy of `received` and checks the re-encoding property; returns the result. */
udn::Decoded decode_and_check(const std::vector<std::uint32_t>& received, std::uint16_t my_index,
                              udn::CrcPolicy policy) {
  std::vector<std::uint32_t> w = received;
  const udn::Decoded d = udn::decode_packet(w, my_index, policy);
  if (!is_valid(d.status)) {
    require(w == received);
    return d;
  }
  require(d.fix_count <= 2);
  require((d.status == udn::DecodeStatus::kMisdelivered) == (d.fields.dest_index != my_index));
  require(d.status != udn::DecodeStatus::kOk || d.fix_count == 0);
  const auto data = udn::packet_data(w, d);
  require(data.size() == d.data_words && d.data_words >= 1);
  std::vector<std::uint32_t> again(udn::kFtMaxPacketWords, 0U);
  std::size_t written = 0;
  require(udn::encode_packet(d.fields, data, again, written) == udn::EncodeStatus::kOk);
  again.resize(written);
  require(again == w);  // the corrected image is exactly a correct encoding
  std::vector<std::uint32_t> diff = received;
  for (std::size_t i = 0; i < diff.size(); ++i) {
    diff[i] ^= again[i];
  }
  for (std::size_t i = 0; i < d.fix_count; ++i) {
    const udn::BitFix f = d.fixes[i];
    require(f.word < diff.size() && ((diff[f.word] >> f.bit) & 1U) == 1U);
    diff[f.word] ^= 1U << f.bit;
  }
  for (const std::uint32_t x : diff) {
    require(x == 0U);  // nothing changed but the reported fixes
  }
  return d;
}

void fuzz_raw(const std::uint8_t* data, std::size_t size, std::uint16_t my_index) {
  const std::size_t n = size / 4 < udn::kFtMaxPacketWords + 2 ? size / 4 : udn::kFtMaxPacketWords + 2;
  std::vector<std::uint32_t> words(n);
  if (n > 0) {
    std::memcpy(words.data(), data, n * 4);
  }
  (void)decode_and_check(words, my_index, udn::CrcPolicy::kAsFlagged);
  (void)decode_and_check(words, my_index, udn::CrcPolicy::kRequired);
}

void fuzz_structured(const std::uint8_t* data, std::size_t size, std::uint16_t my_index) {
  Reader r{data, size};
  udn::FtFields f{};
  f.dest_x = static_cast<std::uint8_t>(r.take(1));
  f.dest_y = static_cast<std::uint8_t>(r.take(1));
  f.dest_index = (r.take(1) & 1U) != 0U ? my_index : static_cast<std::uint16_t>(r.take(2));
  f.hw_tag = r.take(4);
  f.channel = r.take(4);
  f.with_crc = (r.take(1) & 1U) != 0U;
  const std::size_t n = 1 + r.take(1) % udn::kFtMaxDataWords;
  const unsigned flips = r.take(1) % 5U;
  std::vector<std::uint32_t> payload(n);
  for (auto& x : payload) {
    x = r.take(4);
  }
  std::vector<std::uint32_t> sent(udn::kFtMaxPacketWords, 0U);
  std::size_t written = 0;
  require(udn::encode_packet(f, payload, sent, written) == udn::EncodeStatus::kOk);
  sent.resize(written);
  std::vector<std::uint32_t> rx = sent;
  std::vector<std::size_t> positions;
  for (unsigned i = 0; i < flips; ++i) {
    const std::size_t pos = r.take(2) % (written * 32);
    bool dup = false;
    for (const std::size_t q : positions) {
      dup = dup || q == pos;
    }
    if (!dup) {
      positions.push_back(pos);
      rx[pos / 32] ^= 1U << (pos % 32);
    }
  }
  const udn::Decoded d = decode_and_check(rx, my_index, udn::CrcPolicy::kAsFlagged);
  if (positions.size() <= 1) {
    require(is_valid(d.status) && d.fix_count == positions.size());
  }
  if (positions.size() <= 2 && is_valid(d.status)) {
    std::vector<std::uint32_t> w = rx;
    (void)udn::decode_packet(w, my_index);
    require(w == sent);  // never valid with wrong content for up to two flips
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 2) {
    return 0;
  }
  const std::uint16_t my_index = static_cast<std::uint16_t>(data[1] & 0x3FU);
  if ((data[0] & 1U) == 0U) {
    fuzz_raw(data + 2, size - 2, my_index);
  } else {
    fuzz_structured(data + 2, size - 2, my_index);
  }
  return 0;
}
