/**
 * @file tile_health_messages_test.cpp
 * @brief The tile-health and supervisor message declarations (fdir/health_messages.hpp,
 *        fdir/supervisor.hpp): round trips, and fields out of range refused untouched.
 */
#include "fdir/supervisor.hpp"
#include "fdir/tile_health.hpp"
#include "udn/ft_link.hpp"

#include <gtest/gtest.h>

#include <array>
#include <cstdint>

namespace {

TEST(TileHealthMessages, EveryMessageRoundTrips) {
  std::array<std::uint32_t, fdir::kBootedWords> b{};
  (void)fdir::msg::encode(fdir::kBootedMsg, fdir::TileBootReport{5U, bsp::BootCause::kWatchdog}, b);
  fdir::TileBootReport boot{};
  ASSERT_TRUE(fdir::msg::decode(fdir::kBootedMsg, b, boot));
  EXPECT_EQ(boot.tile, 5U);
  EXPECT_EQ(boot.cause, bsp::BootCause::kWatchdog);
  EXPECT_FALSE(fdir::msg::decode(fdir::kAliveMsg, b, boot));  // another tag

  std::array<std::uint32_t, fdir::kResultsBadWords> rb{};
  (void)fdir::msg::encode(fdir::kResultsBadMsg, fdir::ResultsBad{1U, 24U, fdir::ResultsAction::kReplace, 8U, 0U}, rb);
  fdir::ResultsBad bad{};
  ASSERT_TRUE(fdir::msg::decode(fdir::kResultsBadMsg, rb, bad));
  EXPECT_EQ(bad.action, fdir::ResultsAction::kReplace);
  EXPECT_EQ(rb[3], fdir::kResultsReplace);
  EXPECT_EQ(bad.worker, 24U);
  EXPECT_EQ(bad.boot_slot, 8U);

  std::array<std::uint32_t, fdir::kParkWords> pk{};
  (void)fdir::msg::encode(fdir::kParkMsg, fdir::ParkRequest{6U, 19U, true, 2U}, pk);
  fdir::ParkRequest park{};
  ASSERT_TRUE(fdir::msg::decode(fdir::kParkMsg, pk, park));
  EXPECT_TRUE(park.off);
  EXPECT_EQ(park.answer_channel, 2U);

  std::array<std::uint32_t, fdir::kReplacedWords> rp{};
  (void)fdir::msg::encode(fdir::kReplacedMsg, fdir::Replaced{24U, bsp::kNoTile}, rp);
  fdir::Replaced replaced{};
  ASSERT_TRUE(fdir::msg::decode(fdir::kReplacedMsg, rp, replaced));
  EXPECT_EQ(replaced.spare, bsp::kNoTile);

  std::array<std::uint32_t, fdir::kHearQueryWords> hq{};
  (void)fdir::msg::encode(fdir::kHearQueryMsg, fdir::HearQuery{9U, 0U}, hq);
  fdir::HearQuery query{};
  ASSERT_TRUE(fdir::msg::decode(fdir::kHearQueryMsg, hq, query));
  EXPECT_EQ(query.asker, 9U);
  EXPECT_EQ(query.subject, 0U);
  std::array<std::uint32_t, fdir::kHearAnswerWords> ha{};
  (void)fdir::msg::encode(fdir::kHearAnswerMsg, fdir::HearAnswer{1U, 0U, udn::Heard::kSilent}, ha);
  fdir::HearAnswer answer{};
  ASSERT_TRUE(fdir::msg::decode(fdir::kHearAnswerMsg, ha, answer));
  EXPECT_EQ(answer.tile, 1U);
  EXPECT_EQ(answer.hearing, udn::Heard::kSilent);

  std::array<std::uint32_t, fdir::kSupMsgWords> sm{};
  (void)fdir::msg::encode(fdir::kEscalateMsg, fdir::SupMessage{1U, 2U, 7U}, sm);
  fdir::SupMessage sup{};
  EXPECT_FALSE(fdir::msg::decode(fdir::kPolicyMsg, sm, sup));  // another tag
  ASSERT_TRUE(fdir::msg::decode(fdir::kEscalateMsg, sm, sup));
  EXPECT_EQ(sup.constraint, 1U);
  EXPECT_EQ(sup.level, 2U);
  EXPECT_EQ(sup.from, 7U);
}

TEST(TileHealthMessages, FieldsOutOfRangeAreRefusedUntouched) {
  fdir::TileBootReport boot{9U, bsp::BootCause::kCommand};
  EXPECT_FALSE(fdir::msg::decode(fdir::kBootedMsg, std::array<std::uint32_t, 3>{fdir::kMsgBooted, 5U, 4U}, boot));  // no such cause
  EXPECT_FALSE(fdir::msg::decode(fdir::kBootedMsg, std::array<std::uint32_t, 3>{fdir::kMsgBooted, bsp::kMaxTiles, 0U}, boot));
  EXPECT_EQ(boot.tile, 9U);
  fdir::ResultsBad bad{};
  bad.worker = 3U;
  EXPECT_FALSE(fdir::msg::decode(fdir::kResultsBadMsg,  // neither reset nor replace
      std::array<std::uint32_t, 6>{fdir::kMsgResultsBad, 1U, 24U, 3U, 8U, 0U}, bad));
  EXPECT_FALSE(fdir::msg::decode(fdir::kResultsBadMsg,  // an answer channel that does not exist
      std::array<std::uint32_t, 6>{fdir::kMsgResultsBad, 1U, 24U, 2U, 8U, udn::kFtAllChannels}, bad));
  EXPECT_FALSE(fdir::msg::decode(fdir::kResultsBadMsg,  // no boot slot
      std::array<std::uint32_t, 6>{fdir::kMsgResultsBad, 1U, 24U, 2U, fdir::kNoSlot, 0U}, bad));
  EXPECT_EQ(bad.worker, 3U);
  fdir::ParkDone done{};
  EXPECT_FALSE(fdir::msg::decode(fdir::kParkDoneMsg, std::array<std::uint32_t, 3>{fdir::kMsgParkDone, 19U, 2U}, done));
  fdir::HearAnswer answer{1U, 0U, udn::Heard::kAnswers};
  EXPECT_FALSE(fdir::msg::decode(fdir::kHearAnswerMsg, std::array<std::uint32_t, 4>{fdir::kMsgHearAnswer, 8U, 0U, 3U}, answer));
  EXPECT_FALSE(fdir::msg::decode(fdir::kHearAnswerMsg, std::array<std::uint32_t, 4>{fdir::kMsgHearAnswer, 8U, bsp::kMaxTiles, 1U}, answer));
  EXPECT_EQ(answer.tile, 1U);
  fdir::HearQuery query{};
  EXPECT_FALSE(fdir::msg::decode(fdir::kHearQueryMsg, std::array<std::uint32_t, 3>{fdir::kMsgHearQuery, bsp::kMaxTiles, 0U}, query));
  fdir::Replaced replaced{1U, 2U};
  EXPECT_FALSE(fdir::msg::decode(fdir::kReplacedMsg,  // a spare neither a tile nor none
                                 std::array<std::uint32_t, 3>{fdir::kMsgReplaced, 24U, bsp::kMaxTiles}, replaced));
  EXPECT_EQ(replaced.spare, 2U);
  fdir::SupMessage sup{};
  EXPECT_FALSE(fdir::msg::decode(fdir::kPolicyMsg, std::array<std::uint32_t, 4>{fdir::kMsgPolicy, fdir::kMaxConstraints, 0U, 0U}, sup));
  EXPECT_FALSE(fdir::msg::decode(fdir::kPolicyMsg, std::array<std::uint32_t, 4>{fdir::kMsgPolicy, 0U, fdir::kMaxLevels, 0U}, sup));
  EXPECT_FALSE(fdir::msg::decode(fdir::kPolicyMsg, std::array<std::uint32_t, 4>{0x12345678U, 0U, 0U, 0U}, sup));
}

}  // namespace
