/**
 * @file match_deal_test.cpp
 * @brief The quadrant deal of a frame's matches (trn/tasks/vision/match_deal.cpp): the order it gives,
 *        that it is a permutation keeping each quadrant's order, the protected head, and refusals.
 */
#include "trn/tasks/vision/match_deal.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cstdint>
#include <vector>

namespace {

namespace tt = trn::tasks;

constexpr double kCx = 512.0;
constexpr double kCy = 512.0;

/** A match in quadrant @p q (0 upper left, 1 upper right, 2 lower left, 3 lower right) tagged @p id. */
trn::Match in_quadrant(std::uint32_t q, std::uint16_t id) {
  trn::Match m{};
  m.u_px = (q & 1U) != 0U ? kCx + 10.0 + id : kCx - 10.0 - id;
  m.v_px = (q & 2U) != 0U ? kCy + 10.0 + id : kCy - 10.0 - id;
  m.landmark = id;
  m.p_m[0] = 100.0 * id;  // more than the tag travels with the match
  return m;
}

std::vector<std::uint16_t> ids(const std::vector<trn::Match>& v) {
  std::vector<std::uint16_t> out;
  out.reserve(v.size());
  for (const trn::Match& m : v) {
    out.push_back(m.landmark);
  }
  return out;
}

bool deal(std::vector<trn::Match>& v, std::uint32_t first) {
  std::array<std::uint16_t, trn::kMaxMatchesPerFrame + 1U> order{};
  std::array<bool, trn::kMaxMatchesPerFrame + 1U> placed{};
  return tt::deal_by_quadrant(v, first, kCx, kCy, order, placed);
}

TEST(MatchDeal, QuadrantsAboutTheOpticalCentre) {
  EXPECT_EQ(tt::match_quadrant(in_quadrant(0U, 1U), kCx, kCy), 0U);
  EXPECT_EQ(tt::match_quadrant(in_quadrant(1U, 1U), kCx, kCy), 1U);
  EXPECT_EQ(tt::match_quadrant(in_quadrant(2U, 1U), kCx, kCy), 2U);
  EXPECT_EQ(tt::match_quadrant(in_quadrant(3U, 1U), kCx, kCy), 3U);
  trn::Match on_centre{};
  on_centre.u_px = kCx;
  on_centre.v_px = kCy;
  EXPECT_EQ(tt::match_quadrant(on_centre, kCx, kCy), 3U) << "the centre lines belong to the right and lower side";
}

TEST(MatchDeal, DealsOneFromEachQuadrantInTurnKeepingEachQuadrantsOrder) {
  // Sorted input as the coordinator has it: three of quadrant 2, two of 0, one of 3, none of 1.
  std::vector<trn::Match> v{in_quadrant(2U, 1U), in_quadrant(2U, 2U), in_quadrant(0U, 3U),
                            in_quadrant(2U, 4U), in_quadrant(0U, 5U), in_quadrant(3U, 6U)};
  ASSERT_TRUE(deal(v, 0U));
  EXPECT_EQ(ids(v), (std::vector<std::uint16_t>{3, 1, 6, 5, 2, 4}));
  for (const trn::Match& m : v) {
    EXPECT_EQ(m.p_m[0], 100.0 * m.landmark) << "a whole match moves, not its tag";
  }
}

TEST(MatchDeal, TheHeadBeforeFirstStays) {
  std::vector<trn::Match> v{in_quadrant(3U, 9U), in_quadrant(1U, 1U), in_quadrant(1U, 2U), in_quadrant(0U, 3U)};
  ASSERT_TRUE(deal(v, 1U));
  EXPECT_EQ(ids(v), (std::vector<std::uint16_t>{9, 3, 1, 2}));
}

TEST(MatchDeal, ManyBatchesArePermutationsWithEveryQuadrantsOrderKept) {
  constexpr std::uint32_t kSeed = 12345U;  // a fixed LCG seed: every failure below names its trial
  std::uint32_t x = kSeed;
  for (std::uint32_t trial = 0; trial < 200U; ++trial) {
    SCOPED_TRACE(::testing::Message() << "seed " << kSeed << ", trial " << trial);
    x = x * 1664525U + 1013904223U;
    const std::uint32_t n = (x >> 8U) % (trn::kMaxMatchesPerFrame + 2U);
    const std::uint32_t first = n > 0U && (x & 1U) != 0U ? 1U : 0U;
    std::vector<trn::Match> v;
    v.reserve(n);
    std::array<std::vector<std::uint16_t>, 4> per_q;
    for (std::uint32_t i = 0; i < n; ++i) {
      x = x * 1664525U + 1013904223U;
      // Skewed draws: some batches leave a quadrant empty or nearly so.
      const std::uint32_t q = (x >> 28U) < 9U ? (x >> 28U) % 2U : (x >> 24U) % 4U;
      v.push_back(in_quadrant(q, static_cast<std::uint16_t>(i)));
      if (i >= first) {
        per_q[q].push_back(static_cast<std::uint16_t>(i));
      }
    }
    const std::vector<trn::Match> before = v;
    ASSERT_TRUE(deal(v, first)) << "n " << n;
    std::vector<std::uint16_t> got = ids(v);
    std::vector<std::uint16_t> want = ids(before);
    std::sort(got.begin(), got.end());
    std::sort(want.begin(), want.end());
    ASSERT_EQ(got, want) << "not a permutation, n " << n;
    if (first == 1U) {
      EXPECT_EQ(v[0].landmark, before[0].landmark);
    }
    // Rebuild the expected deal from the per-quadrant lists and compare place by place.
    std::array<std::size_t, 4> next{};
    std::vector<std::uint16_t> expect;
    expect.reserve(n);
    while (expect.size() + first < n) {
      for (std::uint32_t q = 0; q < 4U; ++q) {
        if (next[q] < per_q[q].size()) {
          expect.push_back(per_q[q][next[q]++]);
        }
      }
    }
    const std::vector<std::uint16_t> dealt = ids(v);
    EXPECT_EQ(std::vector<std::uint16_t>(dealt.begin() + first, dealt.end()), expect) << "n " << n;
  }
}

TEST(MatchDeal, RefusesTooLittleScratchAndAFirstPastTheEndAndMovesNothing) {
  std::vector<trn::Match> v{in_quadrant(2U, 1U), in_quadrant(0U, 2U), in_quadrant(1U, 3U)};
  const std::vector<std::uint16_t> before = ids(v);
  std::array<std::uint16_t, 2> small_order{};
  std::array<bool, 3> placed{};
  EXPECT_FALSE(tt::deal_by_quadrant(v, 0U, kCx, kCy, small_order, placed));
  std::array<std::uint16_t, 3> order{};
  std::array<bool, 2> small_placed{};
  EXPECT_FALSE(tt::deal_by_quadrant(v, 0U, kCx, kCy, order, small_placed));
  EXPECT_FALSE(tt::deal_by_quadrant(v, 4U, kCx, kCy, order, placed));
  EXPECT_EQ(ids(v), before);
  EXPECT_TRUE(tt::deal_by_quadrant(v, 3U, kCx, kCy, order, placed)) << "nothing after first: nothing to do";
  EXPECT_EQ(ids(v), before);
  std::vector<trn::Match> none;
  EXPECT_TRUE(tt::deal_by_quadrant(none, 0U, kCx, kCy, order, placed));
}

}  // namespace
