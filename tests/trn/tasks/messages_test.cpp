/**
 * @file messages_test.cpp
 * @brief Decoders of the TRN tasks' messages (trn/tasks/messages.cpp, filter_tmr.cpp): round
 *        trips against the packers, and malformed messages refused untouched.
 */
#include "trn/tasks/filter/filter_tmr.hpp"
#include "trn/tasks/messages.hpp"

#include <gtest/gtest.h>

#include <array>
#include <cstdint>
#include <vector>

namespace {

namespace tt = trn::tasks;

TEST(TrnMessages, WorkUnitRoundTrips) {
  tt::WorkUnit u{};
  u.frame = 42U;
  u.unit = 3U;
  u.n = 2U;
  u.t_s = 12.5;
  u.ddr_offset = 0x1'0000'1000ULL;
  u.width_px = 640U;
  u.height_px = 480U;
  u.p_m[2] = 1500.0;
  u.landmark[0] = 5U;
  u.radius_px[0] = 20U;
  u.landmark[1] = 9U;
  u.radius_px[1] = 30U;
  std::array<std::uint32_t, tt::kUnitHeaderWords + 2U> w{};
  (void)fdir::msg::encode(tt::kUnitMsg, u, w);
  tt::WorkUnit back{};
  ASSERT_TRUE(fdir::msg::decode(tt::kUnitMsg, w, back));
  EXPECT_EQ(back.ddr_offset, u.ddr_offset);
  EXPECT_EQ(back.height_px, 480U);
  EXPECT_EQ(back.p_m[2], 1500.0);
  EXPECT_EQ(back.radius_px[1], 30U);
  EXPECT_EQ(back.landmark[2], 0U);  // beyond n: zero
  // One landmark word short of what n says: refused.
  EXPECT_FALSE(fdir::msg::decode(tt::kUnitMsg, std::span<const std::uint32_t>(w).first(w.size() - 1U), back));
}

TEST(TrnMessages, MatchPartRefusesAMatchOfAnotherFrameAndABadPartIndex) {
  std::vector<std::uint32_t> w(tt::kMatchHeaderWords + tt::kMatchWords, 0U);
  w[0] = tt::kMsgMatches;
  w[1] = 42U;
  w[2] = 1U | (2U << 16U);
  w[3] = 1U;
  w[4] = 57U;
  w[tt::kMatchHeaderWords + 21U] = 42U;
  tt::MatchPart p{};
  ASSERT_TRUE(fdir::msg::decode(tt::kMatchesMsg, w, p));
  EXPECT_EQ(p.part, 1U);
  EXPECT_EQ(p.parts, 2U);
  EXPECT_EQ(p.apply_job, 57U);
  w[tt::kMatchHeaderWords + 21U] = 41U;
  p = tt::MatchPart{};
  EXPECT_FALSE(fdir::msg::decode(tt::kMatchesMsg, w, p));
  EXPECT_EQ(p.apply_job, 0U);
  w[tt::kMatchHeaderWords + 21U] = 42U;
  w[2] = 2U | (2U << 16U);  // part 2 of 2
  EXPECT_FALSE(fdir::msg::decode(tt::kMatchesMsg, w, p));
}

// The seal a vision tile puts on its result and the coordinator on a batch part: whole words pass,
// every single changed bit anywhere (the tag, the header, the seal itself, a match) is found, and so
// is every burst of up to 32 bits; too few words to hold a seal never pass.
TEST(TrnMessages, ASealFindsEveryChangedBitOfAResultOrAPart) {
  std::vector<std::uint32_t> w(tt::kMatchHeaderWords + 2U * tt::kMatchWords, 0U);
  (void)fdir::msg::encode(tt::kMatchesMsg, tt::MatchPart{42U, 0U, 1U, 2U, 7U, 0U}, w);
  for (std::size_t i = tt::kMatchHeaderWords; i < w.size(); ++i) {
    w[i] = static_cast<std::uint32_t>(0x9E37'79B9ULL * (i + 1U));
  }
  tt::seal_result(w);
  EXPECT_NE(w[tt::kSealWord], 0U);
  EXPECT_TRUE(tt::result_sealed(w));
  for (std::size_t bit = 0; bit < 32U * w.size(); ++bit) {
    w[bit / 32U] ^= 1U << (bit % 32U);
    EXPECT_FALSE(tt::result_sealed(w)) << "bit " << bit;
    w[bit / 32U] ^= 1U << (bit % 32U);
  }
  for (std::size_t word = 0; word + 1U < w.size(); ++word) {  // a 32-bit burst across two words
    w[word] ^= 0xFFFF'0000U;
    w[word + 1U] ^= 0x0000'FFFFU;
    EXPECT_FALSE(tt::result_sealed(w)) << "word " << word;
    w[word] ^= 0xFFFF'0000U;
    w[word + 1U] ^= 0x0000'FFFFU;
  }
  EXPECT_TRUE(tt::result_sealed(w));
  EXPECT_FALSE(tt::result_sealed(std::span<const std::uint32_t>(w).first(tt::kSealWord)));
  std::vector<std::uint32_t> shorter(tt::kSealWord, 1U);
  tt::seal_result(shorter);
  EXPECT_EQ(shorter, std::vector<std::uint32_t>(tt::kSealWord, 1U)) << "nothing written to too few words";
}

TEST(TrnMessages, StatusesAndCommandsCheckTheirRanges) {
  std::array<std::uint32_t, tt::kFilterStatusWords> fs{};
  (void)fdir::msg::encode(tt::kFilterStatusMsg, tt::FilterStatus{10U, tt::kFilterModeTmr, 7U, 1U, 2U}, fs);
  tt::FilterStatus f{};
  ASSERT_TRUE(fdir::msg::decode(tt::kFilterStatusMsg, fs, f));
  EXPECT_EQ(f.mode, tt::kFilterModeTmr);
  fs[2] = tt::kFilterModeStopping + 1U;
  EXPECT_FALSE(fdir::msg::decode(tt::kFilterStatusMsg, fs, f));
  std::array<std::uint32_t, tt::kVisionStatusWords> vs{};
  (void)fdir::msg::encode(tt::kVisionStatusMsg, tt::VisionStatus{1U, 41U, 40U, 0U, 1U}, vs);  // more healthy than listed
  tt::VisionStatus v{};
  EXPECT_FALSE(fdir::msg::decode(tt::kVisionStatusMsg, vs, v));
  std::array<std::uint32_t, tt::kSupCommandWords> sc{};
  (void)fdir::msg::encode(tt::kSupCommandMsg, tt::SupCommand{tt::kCmdPowerSave, 1U}, sc);  // not a filter command
  tt::SupCommand c{};
  EXPECT_FALSE(fdir::msg::decode(tt::kSupCommandMsg, sc, c));
  tt::VisionRate rate{7U};
  EXPECT_FALSE(fdir::msg::decode(tt::kVisionRateMsg, std::array<std::uint32_t, 2>{tt::kMsgVisionRate, 3U}, rate));
  EXPECT_EQ(rate.div, 7U);
}

TEST(TrnMessages, ReplicaMessagesNameOneOfTheThreeReplicas) {
  std::array<std::uint32_t, tt::kReplicaHelloWords> h{};
  (void)fdir::msg::encode(tt::kReplicaHelloMsg, tt::ReplicaHello{2U, 4U}, h);
  tt::ReplicaHello hello{};
  ASSERT_TRUE(fdir::msg::decode(tt::kReplicaHelloMsg, h, hello));
  EXPECT_EQ(hello.epoch, 4U);
  h[1] = tt::kReplicas;
  EXPECT_FALSE(fdir::msg::decode(tt::kReplicaHelloMsg, h, hello));
  std::array<std::uint32_t, tt::kReplicaOutWords> o{};
  trn::filter::NavOutput nav{};
  nav.t_s = 3.25;
  tt::pack_replica_out(tt::ReplicaOut{1U, 100U, 0x1234U}, nav, o);
  tt::ReplicaOut out{};
  ASSERT_TRUE(fdir::msg::decode(tt::kReplicaOutMsg, o, out));
  EXPECT_EQ(out.job, 100U);
  EXPECT_EQ(fdir::msg::read(tt::kNavMsg, std::span<const std::uint32_t>(o).subspan(tt::kReplicaOutHeaderWords).first<tt::kNavWords>()).t_s,
            3.25);
}

// The solution message carries both covariances: the map-relative one the coordinator searches with and
// the position variance against the world that guidance (and the ground's integrity measure) reads.
TEST(TrnMessages, TheNavMessageCarriesTheMapRelativeAndTheWorldVariances) {
  trn::filter::NavOutput nav{};
  nav.flags = 0xA5U;
  nav.t_s = 12.5;
  for (std::size_t i = 0; i < 9U; ++i) {
    nav.var_diag[i] = 0.5 + static_cast<double>(i);
  }
  nav.pos_var_world[0] = 0.25 + 0.1156;
  nav.pos_var_world[1] = 1.25 + 0.1156;
  nav.pos_var_world[2] = 2.25 + 0.0529;
  std::array<std::uint32_t, tt::kNavWords> w{};
  (void)fdir::msg::encode(tt::kNavMsg, nav, w);
  const trn::filter::NavOutput back = fdir::msg::read(tt::kNavMsg, w);
  EXPECT_EQ(back.flags, nav.flags);
  EXPECT_EQ(back.t_s, nav.t_s);
  for (std::size_t i = 0; i < 9U; ++i) {
    EXPECT_EQ(back.var_diag[i], nav.var_diag[i]) << i;
  }
  for (std::size_t i = 0; i < 3U; ++i) {
    EXPECT_EQ(back.pos_var_world[i], nav.pos_var_world[i]) << i;
  }
  trn::filter::NavOutput decoded{};
  ASSERT_TRUE(fdir::msg::decode(tt::kNavMsg, w, decoded));
  EXPECT_EQ(decoded.pos_var_world[2], nav.pos_var_world[2]);
  EXPECT_FALSE(fdir::msg::decode(tt::kNavMsg, std::span<const std::uint32_t>(w).first(42U), decoded))
      << "the message before the world variances (42 words) is refused";
}

TEST(TrnMessages, CoarseBandsRoundTripAndRefuseMalformedWords) {
  const tt::CoarseBand b{7U, 40, 5, 256, 256, 96, 96, 64, 64, 12U};
  std::array<std::uint32_t, tt::kCoarseBandWords> w{};
  (void)fdir::msg::encode(tt::kCoarseBandMsg, b, w);
  tt::CoarseBand got{};
  ASSERT_TRUE(fdir::msg::decode(tt::kCoarseBandMsg, w, got));
  EXPECT_EQ(got.frame, 7U);
  EXPECT_EQ(got.row0, 40);
  EXPECT_EQ(got.rows, 5);
  EXPECT_EQ(got.window_w, 256);
  EXPECT_EQ(got.window_h, 256);
  EXPECT_EQ(got.tmpl_x, 96);
  EXPECT_EQ(got.tmpl_y, 96);
  EXPECT_EQ(got.tmpl_w, 64);
  EXPECT_EQ(got.tmpl_h, 64);
  EXPECT_EQ(got.slot, 12U);
  std::array<std::uint32_t, tt::kCoarseBandWords> bad = w;
  bad[6] = 64U;  // a template of height 0
  EXPECT_FALSE(fdir::msg::decode(tt::kCoarseBandMsg, bad, got));
  EXPECT_FALSE(fdir::msg::decode(tt::kCoarseBandMsg, std::span<const std::uint32_t>(w.data(), w.size() - 1U), got));

  tt::CoarseBandDone d{};
  d.frame = 9U;
  d.row0 = 188;
  d.rows = 5;
  d.flat_windows = 3;
  d.digest = 0x123456789ABCDEF0ULL;
  d.recomputes = 2U;
  d.status = 4U;
  d.check_failed = true;
  d.first_check = 3U;
  std::array<std::uint32_t, tt::kCoarseBandDoneWords> dw{};
  (void)fdir::msg::encode(tt::kCoarseBandDoneMsg, d, dw);
  tt::CoarseBandDone dg{};
  ASSERT_TRUE(fdir::msg::decode(tt::kCoarseBandDoneMsg, dw, dg));
  EXPECT_EQ(dg.frame, 9U);
  EXPECT_EQ(dg.row0, 188);
  EXPECT_EQ(dg.rows, 5);
  EXPECT_EQ(dg.flat_windows, 3);
  EXPECT_EQ(dg.digest, d.digest);
  EXPECT_EQ(dg.recomputes, 2U);
  EXPECT_EQ(dg.status, 4U);
  EXPECT_TRUE(dg.check_failed);
  EXPECT_EQ(dg.first_check, 3U);
  std::array<std::uint32_t, tt::kCoarseBandDoneWords> dbad = dw;
  dbad[8] |= 2U << 8U;  // "failed" is one bit
  EXPECT_FALSE(fdir::msg::decode(tt::kCoarseBandDoneMsg, dbad, dg));
  dbad = dw;
  dbad[0] = tt::kMsgCoarseBand;
  EXPECT_FALSE(fdir::msg::decode(tt::kCoarseBandDoneMsg, dbad, dg));
}

}  // namespace
