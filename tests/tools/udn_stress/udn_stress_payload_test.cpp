/**
 * @file udn_stress_payload_test.cpp
 * @brief udn_stress payloads: a stamped payload checks intact at its destination, misdelivered
 *        elsewhere, and corrupted after any single-bit flip of any word (exhaustive for the
 *        self-checked words 0 and 1) or a changed length or source.
 */
#include "tools/common/udn_stress/udn_stress_payload.hpp"

#include <gtest/gtest.h>

#include <array>
#include <cstdint>
#include <span>
#include <vector>

namespace {

using tools::PayloadStamp;
using tools::PayloadVerdict;

PayloadVerdict check(std::span<const std::uint32_t> w, std::uint32_t sent_words, bsp::TileId source, bsp::TileId self) {
  PayloadStamp st{};
  return tools::check_payload(w, static_cast<std::uint32_t>(w.size()), sent_words, source, self, st);
}

TEST(UdnStressPayload, IntactAtItsDestinationMisdeliveredElsewhere) {
  for (const std::uint32_t words : {1U, 2U, 3U, 8U, 128U}) {
    std::vector<std::uint32_t> w(words);
    tools::stamp_payload(PayloadStamp{12U, 45U, 0xBEEFU}, w);
    PayloadStamp st{};
    ASSERT_EQ(tools::check_payload(w, words, words, 12U, 45U, st), PayloadVerdict::kIntact) << words;
    EXPECT_EQ(st.source, 12U);
    EXPECT_EQ(st.dest, 45U);
    EXPECT_EQ(st.number, words >= 2U ? 0xBEEFU : 0U);
    EXPECT_EQ(tools::check_payload(w, words, words, 12U, 44U, st), PayloadVerdict::kMisdelivered) << words;
    EXPECT_EQ(st.dest, 45U);
    EXPECT_EQ(check(w, words, 13U, 45U), PayloadVerdict::kCorrupted) << "another source, " << words;
    EXPECT_EQ(tools::check_payload(w, words + 1U, words, 12U, 45U, st), PayloadVerdict::kCorrupted) << words;
  }
}

TEST(UdnStressPayload, AShorterOrLongerPayloadIsCorrupted) {
  std::array<std::uint32_t, 9> w{};
  tools::stamp_payload(PayloadStamp{1U, 2U, 3U}, w);
  EXPECT_EQ(check(std::span(w.data(), 8U), 9U, 1U, 2U), PayloadVerdict::kCorrupted);  // truncated
  std::array<std::uint32_t, 8> shorter{};
  tools::stamp_payload(PayloadStamp{1U, 2U, 3U}, shorter);
  std::array<std::uint32_t, 9> padded{};
  std::copy(shorter.begin(), shorter.end(), padded.begin());  // lengthened: a zero word after
  EXPECT_EQ(check(padded, 8U, 1U, 2U), PayloadVerdict::kCorrupted);
  EXPECT_EQ(check(std::span<const std::uint32_t>(), 8U, 1U, 2U), PayloadVerdict::kCorrupted);
}

// Word 0 checks itself: every flip of every bit, for every source and destination of an 8x8 grid.
TEST(UdnStressPayload, EverySingleFlipOfWordZeroIsDetected) {
  std::uint64_t checked = 0U;
  for (bsp::TileId s = 0; s < 64U; ++s) {
    for (bsp::TileId d = 0; d < 64U; ++d) {
      std::array<std::uint32_t, 1> w{};
      tools::stamp_payload(PayloadStamp{s, d, 0U}, w);
      for (std::uint32_t bit = 0; bit < 32U; ++bit) {
        const std::array<std::uint32_t, 1> f{w[0] ^ (1U << bit)};
        // Checked at the true destination and at every tile a flip could name.
        ASSERT_EQ(check(f, 1U, s, d), PayloadVerdict::kCorrupted) << s << "->" << d << " bit " << bit;
        ASSERT_EQ(check(f, 1U, s, d ^ (1U << (bit % 6U))), PayloadVerdict::kCorrupted) << s << "->" << d;
        ++checked;
      }
    }
  }
  EXPECT_EQ(checked, 64U * 64U * 32U);
}

// Word 1 checks itself against word 0: every packet number, every bit.
TEST(UdnStressPayload, EverySingleFlipOfWordOneIsDetected) {
  for (const bsp::TileId s : {0U, 9U, 63U}) {
    for (std::uint32_t n = 0; n <= 0xFFFFU; ++n) {
      std::array<std::uint32_t, 2> w{};
      tools::stamp_payload(PayloadStamp{s, 5U, static_cast<std::uint16_t>(n)}, w);
      for (std::uint32_t bit = 0; bit < 32U; ++bit) {
        std::array<std::uint32_t, 2> f = w;
        f[1] ^= 1U << bit;
        ASSERT_EQ(check(f, 2U, s, 5U), PayloadVerdict::kCorrupted) << "number " << n << " bit " << bit;
      }
    }
  }
}

TEST(UdnStressPayload, EverySingleFlipOfALaterWordIsDetected) {
  std::array<std::uint32_t, 16> w{};
  tools::stamp_payload(PayloadStamp{3U, 60U, 777U}, w);
  for (std::size_t i = 2U; i < w.size(); ++i) {
    for (std::uint32_t bit = 0; bit < 32U; ++bit) {
      std::array<std::uint32_t, 16> f = w;
      f[i] ^= 1U << bit;
      ASSERT_EQ(check(f, 16U, 3U, 60U), PayloadVerdict::kCorrupted) << "word " << i << " bit " << bit;
    }
  }
}

TEST(UdnStressPayload, PacketsOfOneSenderDifferInEveryWordPastTheFirst) {
  std::array<std::uint32_t, 4> a{};
  std::array<std::uint32_t, 4> b{};
  tools::stamp_payload(PayloadStamp{3U, 4U, 10U}, a);
  tools::stamp_payload(PayloadStamp{3U, 4U, 11U}, b);
  EXPECT_EQ(a[0], b[0]);
  for (std::size_t i = 1U; i < a.size(); ++i) {
    EXPECT_NE(a[i], b[i]) << i;
  }
}

}  // namespace
