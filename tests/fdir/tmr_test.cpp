/**
 * @file tmr_test.cpp
 * @brief The generic 2-of-3 vote and the replica counts that decide exclusion (fdir/tmr.hpp).
 */
#include "fdir/tmr.hpp"

#include <gtest/gtest.h>

namespace {

fdir::TmrRecord rec(std::uint32_t job, std::uint32_t seed, std::uint32_t words = 8U) {
  fdir::TmrRecord r{};
  r.job = job;
  r.words = words;
  for (std::uint32_t i = 0; i < words; ++i) {
    r.w[i] = seed * 7919U + i;
  }
  return r;
}

using Recs = std::array<const fdir::TmrRecord*, fdir::kTmrReplicas>;

TEST(TmrVote, ThreeEqualAgree) {
  const fdir::TmrRecord a = rec(5, 1), b = rec(5, 1), c = rec(5, 1);
  const fdir::TmrVote v = fdir::tmr_vote(Recs{&a, &b, &c}, fdir::kTmrAllReplicas);
  EXPECT_EQ(v.verdict, fdir::TmrVerdict::kAgree);
  EXPECT_EQ(v.winner, 0U);
  EXPECT_EQ(v.differ_mask | v.missing_mask, 0U);
}

// FDIR-TMR-01: one flipped bit in one replica's record is outvoted, whichever replica it is.
TEST(TmrVote, OneFlippedBitIsOutvotedOnAnyReplica) {
  for (std::uint32_t bad = 0; bad < fdir::kTmrReplicas; ++bad) {
    std::array<fdir::TmrRecord, 3> r{rec(9, 2), rec(9, 2), rec(9, 2)};
    r[bad].w[7] ^= 1U << 31U;
    const fdir::TmrVote v = fdir::tmr_vote(Recs{&r[0], &r[1], &r[2]}, fdir::kTmrAllReplicas);
    EXPECT_EQ(v.verdict, fdir::TmrVerdict::kOutvoted);
    EXPECT_EQ(v.differ_mask, 1U << bad);
    EXPECT_NE(v.winner, bad);
    EXPECT_TRUE(fdir::tmr_same(r[v.winner], rec(9, 2)));
  }
}

TEST(TmrVote, ARecordOfAnotherJobOrLengthDiffers) {
  const fdir::TmrRecord a = rec(9, 2), b = rec(9, 2), late = rec(8, 2), short_one = rec(9, 2, 7);
  EXPECT_EQ(fdir::tmr_vote(Recs{&a, &b, &late}, fdir::kTmrAllReplicas).differ_mask, 4U);
  EXPECT_EQ(fdir::tmr_vote(Recs{&short_one, &a, &b}, fdir::kTmrAllReplicas).differ_mask, 1U);
}

TEST(TmrVote, AMissingReplicaIsOutvotedByTheTwoOthers) {
  const fdir::TmrRecord a = rec(3, 4), c = rec(3, 4);
  const fdir::TmrVote v = fdir::tmr_vote(Recs{&a, nullptr, &c}, fdir::kTmrAllReplicas);
  EXPECT_EQ(v.verdict, fdir::TmrVerdict::kOutvoted);
  EXPECT_EQ(v.missing_mask, 2U);
  EXPECT_EQ(v.differ_mask, 0U);
}

// Two different records and no third: no majority, nothing to pass on.
TEST(TmrVote, TwoCorruptedInTheSameJobIsNoMajority) {
  const fdir::TmrRecord a = rec(3, 4), b = rec(3, 5), c = rec(3, 6);
  const fdir::TmrVote v = fdir::tmr_vote(Recs{&a, &b, &c}, fdir::kTmrAllReplicas);
  EXPECT_EQ(v.verdict, fdir::TmrVerdict::kNoMajority);
  EXPECT_EQ(v.differ_mask, 7U);
  const fdir::TmrVote alone = fdir::tmr_vote(Recs{&a, nullptr, nullptr}, fdir::kTmrAllReplicas);
  EXPECT_EQ(alone.verdict, fdir::TmrVerdict::kNoMajority);
  EXPECT_EQ(alone.differ_mask, 0U) << "a record alone differs from nothing: not named";
  EXPECT_EQ(alone.missing_mask, 6U);
}

// Records their receiver found corrupted never win, even two alike: they differ, and a good record
// alone is not named.
TEST(TmrVote, BadRecordsNeverWinEvenTwoAlike) {
  const fdir::TmrRecord good = rec(3, 4), bad = rec(3, 5);
  fdir::TmrVote v = fdir::tmr_vote(Recs{&bad, &good, &bad}, fdir::kTmrAllReplicas, 0b101U);
  EXPECT_EQ(v.verdict, fdir::TmrVerdict::kNoMajority);
  EXPECT_EQ(v.differ_mask, 0b101U);
  EXPECT_EQ(v.missing_mask, 0U);
  const fdir::TmrRecord same = rec(3, 4);
  v = fdir::tmr_vote(Recs{&good, &same, &same}, fdir::kTmrAllReplicas, 0b100U);
  EXPECT_EQ(v.verdict, fdir::TmrVerdict::kOutvoted) << "equal to the vote, but found corrupted";
  EXPECT_EQ(v.differ_mask, 0b100U);
  EXPECT_LT(v.winner, 2U);
}

// Duplex: two replicas expected (the third excluded, its stale record ignored).
TEST(TmrVote, DuplexComparesTheTwoItExpects) {
  const fdir::TmrRecord a = rec(3, 4), b = rec(3, 4), stale = rec(3, 9), wrong = rec(3, 5);
  EXPECT_EQ(fdir::tmr_vote(Recs{&a, &stale, &b}, 0b101U).verdict, fdir::TmrVerdict::kAgree);
  EXPECT_EQ(fdir::tmr_vote(Recs{&a, &stale, &wrong}, 0b101U).verdict, fdir::TmrVerdict::kNoMajority);
}

TEST(TmrGroup, OneOddOutputIsCountedNotExcluded) {
  fdir::TmrGroup g;
  ASSERT_TRUE(g.configure(fdir::TmrGroupConfig{2U, 3U}));
  for (std::uint32_t i = 0; i < 3U; ++i) {
    g.admit(i);
  }
  fdir::TmrVote odd{fdir::TmrVerdict::kOutvoted, 0U, 0b010U, 0U};
  EXPECT_EQ(g.account(odd), 0U);
  fdir::TmrVote agree{fdir::TmrVerdict::kAgree, 0U, 0U, 0U};
  EXPECT_EQ(g.account(agree), 0U);
  EXPECT_EQ(g.account(odd), 0U) << "not in a row";
  EXPECT_EQ(g.count(1).disagreements, 2U);
  EXPECT_EQ(g.active_mask(), 7U);
}

// A replica whose state is wrong disagrees job after job: excluded at the threshold, readmitted later.
TEST(TmrGroup, DisagreeingOrSilentReplicasAreExcludedAtTheirThresholds) {
  fdir::TmrGroup g;
  ASSERT_TRUE(g.configure(fdir::TmrGroupConfig{2U, 3U}));
  for (std::uint32_t i = 0; i < 3U; ++i) {
    g.admit(i);
  }
  const fdir::TmrVote odd2{fdir::TmrVerdict::kOutvoted, 0U, 0b100U, 0U};
  EXPECT_EQ(g.account(odd2), 0U);
  EXPECT_EQ(g.account(odd2), 0b100U);
  EXPECT_EQ(g.active_mask(), 0b011U);
  EXPECT_EQ(g.active_count(), 2U);
  EXPECT_EQ(g.count(2).exclusions, 1U);
  const fdir::TmrVote silent1{fdir::TmrVerdict::kOutvoted, 0U, 0U, 0b010U};
  EXPECT_EQ(g.account(silent1), 0U);
  EXPECT_EQ(g.account(silent1), 0U);
  EXPECT_EQ(g.account(silent1), 0b010U);
  EXPECT_EQ(g.active_mask(), 0b001U);
  g.admit(2U);
  EXPECT_EQ(g.active_mask(), 0b101U);
  EXPECT_EQ(g.count(2).disagree_in_row, 0U);
  // No majority says nothing about who is wrong.
  EXPECT_EQ(g.account(fdir::TmrVote{fdir::TmrVerdict::kNoMajority, 3U, 0b101U, 0U}), 0U);
  EXPECT_EQ(g.count(0).disagreements, 0U);
}

TEST(TmrGroup, ZeroThresholdsAreRefused) {
  fdir::TmrGroup g;
  EXPECT_FALSE(g.configure(fdir::TmrGroupConfig{0U, 3U}));
  EXPECT_FALSE(g.configure(fdir::TmrGroupConfig{2U, 0U}));
}

}  // namespace
