/**
 * @file ft_packet_test.cpp
 * @brief Fault-tolerant packets: layout, every single error corrected, every double
 *        error detected, misdelivery recognised, and measured behaviour beyond that.
 */
#include "udn/ft_packet.hpp"

#include "bsp_tile64/emu/rng.hpp"
#include "udn/crc32c.hpp"
#include "udn/ecc.hpp"

#include <gtest/gtest.h>

#include <cstdint>
#include <cstdio>
#include <vector>

namespace {

constexpr std::uint64_t kSeed = 0xF7BAC7E75EEDULL;
constexpr std::uint16_t kDestIndex = 0x002A;
constexpr std::uint16_t kOtherIndex = 0x0007;

udn::FtFields make_fields(bool crc) {
  udn::FtFields f{};
  f.dest_x = 5;
  f.dest_y = 3;
  f.dest_index = kDestIndex;
  f.hw_tag = 0x00000002U;
  f.channel = 0x00C0FFEEU;
  f.with_crc = crc;
  return f;
}

struct Packet {
  std::vector<std::uint32_t> data;
  std::vector<std::uint32_t> words;
};

Packet make_packet(std::size_t n, bool crc, std::uint64_t salt = 0) {
  bsp::Rng rng(kSeed, bsp::StreamId::kTest, n * 2 + (crc ? 1 : 0) + salt * 1000);
  Packet p;
  p.data.resize(n);
  for (auto& w : p.data) {
    w = static_cast<std::uint32_t>(rng.next());
  }
  p.words.assign(udn::kFtMaxPacketWords, 0U);
  std::size_t written = 0;
  const udn::EncodeStatus st = udn::encode_packet(make_fields(crc), p.data, p.words, written);
  EXPECT_EQ(st, udn::EncodeStatus::kOk);
  p.words.resize(written);
  return p;
}

void flip(std::vector<std::uint32_t>& w, std::size_t pos) { w[pos / 32] ^= 1U << (pos % 32); }

bool is_valid(udn::DecodeStatus s) {
  return s == udn::DecodeStatus::kOk || s == udn::DecodeStatus::kCorrected || s == udn::DecodeStatus::kMisdelivered;
}

TEST(FtPacket, EncodeLaysOutTheFigure5Words) {
  const Packet p = make_packet(3, true);
  ASSERT_EQ(p.words.size(), 9U);
  EXPECT_EQ(p.words[udn::kWordHwHeader], udn::make_hw_header(5, 3, 8));
  EXPECT_EQ(p.words[udn::kWordHwHeader], 0x00050308U);
  EXPECT_EQ(p.words[udn::kWordHwTag], 2U);
  EXPECT_EQ(p.words[udn::kWordRouteData], (std::uint32_t{kDestIndex} << 16U) | udn::kFlagCrc | 3U);
  EXPECT_EQ(p.words[udn::kWordChannel], 0x00C0FFEEU);
  EXPECT_EQ(p.words[udn::kWordEcc] & udn::kEccReservedMask, 0U);
  for (std::size_t i = 0; i < 3; ++i) {
    EXPECT_EQ(p.words[udn::kWordData + i], p.data[i]);
  }
  EXPECT_EQ(p.words[8], udn::crc32c_words(std::span<const std::uint32_t>(p.words).subspan(3, 5)));
}

TEST(FtPacket, EncodeRejectsBadLengthsAndSmallBuffers) {
  std::vector<std::uint32_t> data(125, 1U);
  std::vector<std::uint32_t> out(udn::kFtMaxPacketWords, 0xAAAAAAAAU);
  std::size_t written = 99;
  const std::span<const std::uint32_t> d(data);
  EXPECT_EQ(udn::encode_packet(make_fields(false), d.subspan(0, 0), out, written), udn::EncodeStatus::kBadLength);
  EXPECT_EQ(written, 0U);
  EXPECT_EQ(udn::encode_packet(make_fields(false), d, out, written), udn::EncodeStatus::kBadLength);
  EXPECT_EQ(udn::encode_packet(make_fields(true), d.subspan(0, 124), std::span(out).subspan(0, 129), written),
            udn::EncodeStatus::kBufferTooSmall);
  EXPECT_EQ(out[0], 0xAAAAAAAAU);
  EXPECT_EQ(udn::encode_packet(make_fields(true), d.subspan(0, 124), out, written), udn::EncodeStatus::kOk);
  EXPECT_EQ(written, 130U);
}

TEST(FtPacket, CleanPacketDecodesOkForMeAndMisdeliveredElsewhere) {
  for (const bool crc : {false, true}) {
    Packet p = make_packet(62, crc);
    const udn::Decoded d = udn::decode_packet(p.words, kDestIndex);
    ASSERT_EQ(d.status, udn::DecodeStatus::kOk);
    EXPECT_EQ(d.fix_count, 0U);
    EXPECT_EQ(d.fields.channel, 0x00C0FFEEU);
    EXPECT_EQ(d.fields.with_crc, crc);
    const auto data = udn::packet_data(p.words, d);
    EXPECT_EQ(std::vector<std::uint32_t>(data.begin(), data.end()), p.data);
    EXPECT_EQ(udn::decode_packet(p.words, kOtherIndex).status, udn::DecodeStatus::kMisdelivered);
  }
}

/** Every bit of every word: corrected in place, data exact; header bits also forwardable. */
void expect_every_single_flip_recovered(std::size_t n, bool crc) {
  const Packet p = make_packet(n, crc);
  for (std::size_t pos = 0; pos < p.words.size() * 32; ++pos) {
    const std::size_t word = pos / 32;
    auto w = p.words;
    flip(w, pos);
    const udn::Decoded d = udn::decode_packet(w, kDestIndex);
    ASSERT_EQ(d.status, udn::DecodeStatus::kCorrected) << "n " << n << " crc " << crc << " pos " << pos;
    ASSERT_EQ(w, p.words) << "image not restored, pos " << pos;
    ASSERT_EQ(d.fix_count, 1U);
    ASSERT_EQ(d.fixes[0].word * 32U + d.fixes[0].bit, pos);
    ASSERT_EQ(d.header_hit, word <= udn::kWordHwTag);
    ASSERT_EQ(d.data_words, n);
    const auto data = udn::packet_data(w, d);
    ASSERT_EQ(std::vector<std::uint32_t>(data.begin(), data.end()), p.data);
    if (word <= udn::kWordHwTag) {
      // The flip sent the packet to another tile or queue: there it is recognised
      // as not its own, with the true destination and intact data.
      auto w2 = p.words;
      flip(w2, pos);
      const udn::Decoded m = udn::decode_packet(w2, kOtherIndex);
      ASSERT_EQ(m.status, udn::DecodeStatus::kMisdelivered) << "pos " << pos;
      ASSERT_EQ(m.fields.dest_index, kDestIndex);
      ASSERT_EQ(w2, p.words);
    }
  }
}

TEST(FtPacket, EverySingleBitFlipInEveryWordIsCorrectedExactly) {
  for (const std::size_t n : {1U, 2U, 62U, 124U}) {
    expect_every_single_flip_recovered(n, false);
    expect_every_single_flip_recovered(n, true);
  }
}

/** A valid decode must restore the exact image; otherwise the input is left untouched. */
void expect_double_handled(const Packet& p, std::size_t a, std::size_t b, std::uint64_t seed,
                           std::size_t& detected) {
  auto w = p.words;
  flip(w, a);
  flip(w, b);
  const auto corrupted = w;
  const udn::Decoded d = udn::decode_packet(w, kDestIndex);
  if (is_valid(d.status)) {
    // Only possible with one error in each code: both corrected.
    ASSERT_EQ(w, p.words) << "seed " << seed << " bits " << a << "," << b;
    ASSERT_EQ(d.status, udn::DecodeStatus::kCorrected);
    ASSERT_EQ(d.fix_count, 2U);
  } else {
    ASSERT_EQ(w, corrupted) << "rejected packet was modified, bits " << a << "," << b;
    ++detected;
  }
}

TEST(FtPacket, EveryDoubleBitFlipOfShortPacketsIsDetectedOrExactlyCorrected) {
  for (const std::size_t n : {1U, 2U}) {
    for (const bool crc : {false, true}) {
      const Packet p = make_packet(n, crc);
      const std::size_t bits = p.words.size() * 32;
      std::size_t detected = 0;
      for (std::size_t a = 0; a < bits; ++a) {
        for (std::size_t b = a + 1; b < bits; ++b) {
          expect_double_handled(p, a, b, kSeed, detected);
        }
      }
      std::printf("double flips n=%zu crc=%d: %zu pairs, %zu detected, rest corrected exactly\n", n, crc ? 1 : 0,
                  bits * (bits - 1) / 2, detected);
      EXPECT_GT(detected, 0U);
    }
  }
}

TEST(FtPacket, RandomDoubleBitFlipsOfLongPacketsAreDetectedOrExactlyCorrected) {
  const std::uint64_t seed = kSeed + 2;
  std::printf("seed %llu\n", static_cast<unsigned long long>(seed));
  bsp::Rng rng(seed, bsp::StreamId::kTest, 0);
  for (const std::size_t n : {62U, 124U}) {
    for (const bool crc : {false, true}) {
      const Packet p = make_packet(n, crc);
      const std::size_t bits = p.words.size() * 32;
      std::size_t detected = 0;
      for (int i = 0; i < 100000; ++i) {
        const std::size_t a = rng.below(bits);
        const std::size_t b = (a + 1 + rng.below(bits - 1)) % bits;
        expect_double_handled(p, a, b, seed, detected);
      }
      EXPECT_GT(detected, 0U);
    }
  }
}

// ---------------------------------------------------------------- beyond two errors

enum class Outcome { kDetected, kRecovered, kHeaderOnly, kSilentCorrupt };

/** How a decoded packet compares with what was sent (payload = words 3.. and the data). */
Outcome classify(const Packet& p, const std::vector<std::uint32_t>& w, const udn::Decoded& d) {
  if (!is_valid(d.status)) {
    return Outcome::kDetected;
  }
  for (std::size_t i = udn::kWordRouteData; i < p.words.size(); ++i) {
    if (i != udn::kWordEcc && w[i] != p.words[i]) {
      return Outcome::kSilentCorrupt;
    }
  }
  const bool header_same = w[udn::kWordHwHeader] == p.words[udn::kWordHwHeader] &&
                           w[udn::kWordHwTag] == p.words[udn::kWordHwTag];
  return header_same ? Outcome::kRecovered : Outcome::kHeaderOnly;
}

struct Tally {
  std::size_t trials = 0;
  std::size_t detected = 0;
  std::size_t recovered = 0;
  std::size_t header_only = 0;
  std::size_t silent = 0;
};

/** Error pattern: k distinct random bits (burst_len == 0) or a burst of burst_len bits. */
void inject(std::vector<std::uint32_t>& w, bsp::Rng& rng, int k, std::size_t burst_len) {
  const std::size_t bits = w.size() * 32;
  if (burst_len == 0) {
    std::vector<std::size_t> used;
    while (used.size() < static_cast<std::size_t>(k)) {
      const std::size_t pos = rng.below(bits);
      bool dup = false;
      for (const std::size_t u : used) {
        dup = dup || u == pos;
      }
      if (!dup) {
        used.push_back(pos);
        flip(w, pos);
      }
    }
    return;
  }
  // A burst of length L: first and last bit wrong, the ones between at random.
  const std::size_t start = rng.below(bits - burst_len + 1);
  flip(w, start);
  flip(w, start + burst_len - 1);
  for (std::size_t i = 1; i + 1 < burst_len; ++i) {
    if ((rng.next() & 1U) != 0U) {
      flip(w, start + i);
    }
  }
}

Tally measure(std::size_t n, bool crc, udn::CrcPolicy policy, int k, std::size_t burst_len, int trials,
              std::uint64_t seed) {
  const Packet p = make_packet(n, crc);
  bsp::Rng rng(seed, bsp::StreamId::kTest, n * 1000 + (crc ? 500 : 0) + static_cast<std::uint64_t>(k) * 64 + burst_len);
  Tally t;
  for (int i = 0; i < trials; ++i) {
    auto w = p.words;
    inject(w, rng, k, burst_len);
    const udn::Decoded d = udn::decode_packet(w, kDestIndex, policy);
    ++t.trials;
    switch (classify(p, w, d)) {
      case Outcome::kDetected: ++t.detected; break;
      case Outcome::kRecovered: ++t.recovered; break;
      case Outcome::kHeaderOnly: ++t.header_only; break;
      case Outcome::kSilentCorrupt: ++t.silent; break;
    }
  }
  return t;
}

/** Silent-corruption bounds, per error kind and packet size, as documented in docs/UDN_PACKETS.md. */
constexpr double kSilentBoundNoCrc = 0.95;
constexpr double kSilentBoundCrcAsFlagged = 1e-3;

TEST(FtPacket, MeasuredThreeFourBitAndBurstErrorsCrcRequiredLeavesNoSilentCorruption) {
  const std::uint64_t seed = kSeed + 3;
  constexpr int kTrials = 40000;
  struct Kind {
    const char* name;
    int k;
    std::size_t burst;
  };
  struct Mode {
    const char* name;
    bool crc;
    udn::CrcPolicy policy;
  };
  const Kind kinds[] = {{"3-bit", 3, 0}, {"4-bit", 4, 0}, {"burst8", 0, 8}, {"burst16", 0, 16}, {"burst32", 0, 32}};
  const Mode modes[] = {{"none", false, udn::CrcPolicy::kAsFlagged},
                        {"flagged", true, udn::CrcPolicy::kAsFlagged},
                        {"required", true, udn::CrcPolicy::kRequired}};
  std::printf("seed %llu, %d trials per row\n", static_cast<unsigned long long>(seed), kTrials);
  std::printf("| words | crc | errors | detected | recovered | header only | silent corrupt |\n");
  for (const std::size_t n : {1U, 16U, 124U}) {
    for (const Mode& mode : modes) {
      for (const Kind& kind : kinds) {
        const Tally t = measure(n, mode.crc, mode.policy, kind.k, kind.burst, kTrials, seed);
        const double tr = static_cast<double>(t.trials);
        const double silent = static_cast<double>(t.silent) / tr;
        std::printf("| %zu | %s | %s | %.5f | %.5f | %.5f | %.5f |\n", n, mode.name, kind.name,
                    static_cast<double>(t.detected) / tr, static_cast<double>(t.recovered) / tr,
                    static_cast<double>(t.header_only) / tr, silent);
        ASSERT_EQ(t.detected + t.recovered + t.header_only + t.silent, t.trials);
        if (mode.policy == udn::CrcPolicy::kRequired) {
          EXPECT_EQ(t.silent, 0U) << "seed " << seed << " n " << n << " " << kind.name;
        } else {
          const double bound = mode.crc ? kSilentBoundCrcAsFlagged : kSilentBoundNoCrc;
          EXPECT_LE(silent, bound) << "seed " << seed << " n " << n << " " << mode.name << " " << kind.name;
        }
      }
    }
  }
}

TEST(FtPacket, WrongWordCountsAndReservedBitsAreMalformed) {
  Packet p = make_packet(4, false);
  auto shorter = p.words;
  shorter.pop_back();
  EXPECT_EQ(udn::decode_packet(shorter, kDestIndex).status, udn::DecodeStatus::kMalformed);
  auto longer = p.words;
  longer.push_back(0U);
  EXPECT_EQ(udn::decode_packet(longer, kDestIndex).status, udn::DecodeStatus::kMalformed);
  std::vector<std::uint32_t> tiny(5, 0U);
  EXPECT_EQ(udn::decode_packet(tiny, kDestIndex).status, udn::DecodeStatus::kMalformed);
  std::vector<std::uint32_t> huge(udn::kFtMaxPacketWords + 1, 0U);
  EXPECT_EQ(udn::decode_packet(huge, kDestIndex).status, udn::DecodeStatus::kMalformed);
  // Correctly coded but impossible route data: length 0, unknown flag.
  for (const std::uint32_t route_data : {0x002A0000U, 0x002A0204U}) {
    auto w = p.words;
    w[udn::kWordRouteData] = route_data;
    const std::array<std::uint32_t, 4> rw = {w[0], w[1], w[3], w[4]};
    w[udn::kWordEcc] = (w[udn::kWordEcc] & ~udn::RouteCode::kCheckMask) | udn::RouteCode::encode(rw);
    const auto before = w;
    EXPECT_EQ(udn::decode_packet(w, kDestIndex).status, udn::DecodeStatus::kMalformed) << route_data;
    EXPECT_EQ(w, before);
  }
}

TEST(FtPacket, CodedButWrongCrcIsReportedAndLeavesWordsUntouched) {
  Packet p = make_packet(10, true);
  auto w = p.words;
  w[udn::kWordData + 10] ^= 0x00010001U;  // two CRC bits: the data code sees a double
  EXPECT_EQ(udn::decode_packet(w, kDestIndex).status, udn::DecodeStatus::kUncorrectable);
  // Re-code the data so the ECC is consistent with the wrong CRC word.
  const std::uint32_t dc = udn::DataCode::encode(std::span<const std::uint32_t>(w).subspan(udn::kWordData, 11));
  w[udn::kWordEcc] = (w[udn::kWordEcc] & 0xFFFFU) | ((dc ^ udn::kCrcFlagEccSalt) << 16U);
  auto flipped = w;
  flip(flipped, 32 * 7 + 3);  // and one correctable data error on top: the fix is undone
  const auto before = flipped;
  EXPECT_EQ(udn::decode_packet(flipped, kDestIndex).status, udn::DecodeStatus::kCrcMismatch);
  EXPECT_EQ(flipped, before);
}

TEST(FtPacket, CrcFlagStrippedByRouteMiscorrectionIsCaughtBySaltAndPolicy) {
  // The case a 32-bit burst produced in measurement: word 3 miscorrected from
  // "16 words + CRC" to "17 words, no CRC", same word count.
  Packet p = make_packet(16, true);
  auto w = p.words;
  w[udn::kWordRouteData] = (std::uint32_t{kDestIndex} << 16U) | 17U;
  const std::array<std::uint32_t, 4> rw = {w[0], w[1], w[3], w[4]};
  w[udn::kWordEcc] = (w[udn::kWordEcc] & ~udn::RouteCode::kCheckMask) | udn::RouteCode::encode(rw);
  auto w2 = w;
  EXPECT_EQ(udn::decode_packet(w, kDestIndex).status, udn::DecodeStatus::kUncorrectable);
  EXPECT_EQ(udn::decode_packet(w2, kDestIndex, udn::CrcPolicy::kRequired).status, udn::DecodeStatus::kMalformed);
  Packet plain = make_packet(4, false);
  EXPECT_EQ(udn::decode_packet(plain.words, kDestIndex, udn::CrcPolicy::kRequired).status,
            udn::DecodeStatus::kMalformed);
  EXPECT_EQ(udn::decode_packet(plain.words, kDestIndex, udn::CrcPolicy::kAsFlagged).status, udn::DecodeStatus::kOk);
}

TEST(FtPacket, ReaddressKeepsDataCodeAndDecodesAtTheNewTile) {
  Packet p = make_packet(16, true);
  const std::uint32_t data_ecc = p.words[udn::kWordEcc] >> 16U;
  ASSERT_EQ(udn::readdress_packet(p.words, 7, 1, 3U), udn::ReaddressStatus::kOk);
  EXPECT_EQ(p.words[udn::kWordEcc] >> 16U, data_ecc);
  const udn::Decoded d = udn::decode_packet(p.words, kDestIndex);
  ASSERT_EQ(d.status, udn::DecodeStatus::kOk);
  EXPECT_EQ(d.fields.dest_x, 7U);
  EXPECT_EQ(d.fields.dest_y, 1U);
  EXPECT_EQ(d.fields.hw_tag, 3U);
  std::vector<std::uint32_t> tiny(3, 0U);
  EXPECT_EQ(udn::readdress_packet(tiny, 0, 0, 0), udn::ReaddressStatus::kMalformed);
}

TEST(FtPacket, CodecWorkGrowsWithPayloadAndCrc) {
  const bsp::Work a = udn::ft_codec_work(1, false);
  const bsp::Work b = udn::ft_codec_work(124, false);
  const bsp::Work c = udn::ft_codec_work(124, true);
  EXPECT_GT(a.int_ops, 0U);
  EXPECT_GT(b.int_ops, a.int_ops);
  EXPECT_GT(c.int_ops, b.int_ops);
  EXPECT_GT(c.mem_words, b.mem_words);
}

}  // namespace
