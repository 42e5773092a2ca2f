/**
 * @file ecc_bench.cpp
 * @brief Fault-tolerant packet codec throughput (encode + decode, payload bytes/s)
 *        against a naive bit-by-bit SECDED reference.
 *
 * Run: make build/bench/ecc_bench && build/bench/ecc_bench
 * Bytes counted are payload bytes (4 per data word) per encode+decode round.
 */
#include "bsp_tile64/emu/rng.hpp"
#include "udn/ecc.hpp"
#include "udn/ft_packet.hpp"

#include <benchmark/benchmark.h>

#include <bit>
#include <cstdint>
#include <vector>

namespace {

std::vector<std::uint32_t> make_data(std::size_t n) {
  bsp::Rng rng(17, bsp::StreamId::kTest, n);
  std::vector<std::uint32_t> d(n);
  for (auto& w : d) {
    w = static_cast<std::uint32_t>(rng.next());
  }
  return d;
}

udn::FtFields fields(bool crc) {
  udn::FtFields f{};
  f.dest_x = 3;
  f.dest_y = 4;
  f.dest_index = 9;
  f.hw_tag = 1;
  f.channel = 77;
  f.with_crc = crc;
  return f;
}

void fast_codec(benchmark::State& state, bool crc) {
  const auto n = static_cast<std::size_t>(state.range(0));
  const auto data = make_data(n);
  std::vector<std::uint32_t> words(udn::kFtMaxPacketWords);
  for (auto _ : state) {
    std::size_t written = 0;
    benchmark::DoNotOptimize(udn::encode_packet(fields(crc), data, words, written));
    const udn::Decoded d = udn::decode_packet(std::span(words).subspan(0, written), 9);
    benchmark::DoNotOptimize(d);
  }
  state.SetBytesProcessed(static_cast<std::int64_t>(state.iterations()) * static_cast<std::int64_t>(n * 4));
}

void BM_FastCodec(benchmark::State& state) { fast_codec(state, false); }
void BM_FastCodecCrc(benchmark::State& state) { fast_codec(state, true); }

/** Naive Hsiao code: the same columns, applied one bit at a time. */
struct NaiveCode {
  std::vector<std::uint32_t> cols;
  explicit NaiveCode(unsigned r, std::size_t bits) {
    for (int weight = 3; weight <= static_cast<int>(r); weight += 2) {
      for (std::uint32_t v = 0; v < (1U << r); ++v) {
        if (std::popcount(v) == weight && cols.size() < bits) {
          cols.push_back(v);
        }
      }
    }
  }
  std::uint32_t encode(const std::uint32_t* w, std::size_t n) const {
    std::uint32_t c = 0;
    for (std::size_t i = 0; i < n * 32; ++i) {
      if (((w[i / 32] >> (i % 32)) & 1U) != 0U) {
        c ^= cols[i];
      }
    }
    return c;
  }
  /** Returns the bit position matching the syndrome by linear search, or -1. */
  long locate(std::uint32_t syndrome, std::size_t n) const {
    for (std::size_t i = 0; i < n * 32; ++i) {
      if (cols[i] == syndrome) {
        return static_cast<long>(i);
      }
    }
    return -1;
  }
};

void BM_NaiveCodec(benchmark::State& state) {
  static const NaiveCode data_code(udn::kDataCodeCheckBits, udn::kDataCodeMaxWords * 32);
  static const NaiveCode route_code(udn::kRouteCodeCheckBits, udn::kRouteCodeWords * 32);
  const auto n = static_cast<std::size_t>(state.range(0));
  const auto data = make_data(n);
  std::vector<std::uint32_t> words(udn::kFtHeaderWords + n);
  for (auto _ : state) {
    // Encode: header words, then both codes bit by bit.
    words[0] = udn::make_hw_header(3, 4, static_cast<std::uint8_t>(words.size() - 1));
    words[1] = 1;
    words[3] = (9U << 16U) | static_cast<std::uint32_t>(n);
    words[4] = 77;
    for (std::size_t i = 0; i < n; ++i) {
      words[5 + i] = data[i];
    }
    const std::uint32_t rw[4] = {words[0], words[1], words[3], words[4]};
    words[2] = (data_code.encode(&words[5], n) << 16U) | route_code.encode(rw, 4);
    // Decode: recompute both syndromes bit by bit, search the columns on error.
    const std::uint32_t rs = route_code.encode(rw, 4) ^ (words[2] & 0x1FFU);
    const std::uint32_t ds = data_code.encode(&words[5], n) ^ (words[2] >> 16U);
    benchmark::DoNotOptimize(rs == 0U ? 0 : route_code.locate(rs, 4));
    benchmark::DoNotOptimize(ds == 0U ? 0 : data_code.locate(ds, n));
  }
  state.SetBytesProcessed(static_cast<std::int64_t>(state.iterations()) * static_cast<std::int64_t>(n * 4));
}

/** Decode of a packet with one corrected data error (syndrome lookup path). */
void BM_FastDecodeWithOneError(benchmark::State& state) {
  const auto n = static_cast<std::size_t>(state.range(0));
  const auto data = make_data(n);
  std::vector<std::uint32_t> sent(udn::kFtMaxPacketWords);
  std::size_t written = 0;
  if (udn::encode_packet(fields(false), data, sent, written) != udn::EncodeStatus::kOk) {
    state.SkipWithError("encode failed");
    return;
  }
  sent.resize(written);
  std::vector<std::uint32_t> rx = sent;
  for (auto _ : state) {
    rx[udn::kWordData + n / 2] ^= 1U << 7U;
    benchmark::DoNotOptimize(udn::decode_packet(rx, 9));  // corrects in place, so rx is clean again
  }
  state.SetBytesProcessed(static_cast<std::int64_t>(state.iterations()) * static_cast<std::int64_t>(n * 4));
}

BENCHMARK(BM_FastCodec)->Arg(1)->Arg(16)->Arg(124);
BENCHMARK(BM_FastCodecCrc)->Arg(1)->Arg(16)->Arg(124);
BENCHMARK(BM_NaiveCodec)->Arg(1)->Arg(16)->Arg(124);
BENCHMARK(BM_FastDecodeWithOneError)->Arg(1)->Arg(16)->Arg(124);

}  // namespace

BENCHMARK_MAIN();
