/**
 * @file nav_integrity_test.cpp
 * @brief The integrity measure: per-axis error against the reported 3-sigma, counted and its worst ratio kept.
 */
#include "tools/common/mission/nav_integrity.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace {

TEST(NavIntegrity, CountsEachAxisBeyondItsOwnBoundAndKeepsTheWorstRatio) {
  tools::NavIntegrity n;
  EXPECT_EQ(n.fraction_beyond_3sigma(0), 0.0) << "no output yet";
  n.add(1.0, {1.0, -2.0, 0.5}, {3.0, 3.0, 3.0});    // inside on every axis
  n.add(2.0, {-4.0, 0.0, 0.0}, {3.0, 3.0, 3.0});    // x beyond 3 sigma (ratio 4/3), inside 5 sigma
  n.add(3.0, {0.0, 6.0, 0.0}, {3.0, 3.0, 3.0});     // y beyond 5 sigma (ratio 2)
  n.add(4.0, {0.0, 0.0, -5.0}, {3.0, 3.0, 3.0});    // z exactly at 5 sigma: beyond 3, not beyond 5
  EXPECT_EQ(n.outputs, 4U);
  EXPECT_EQ(n.beyond_3sigma[0], 1U);
  EXPECT_EQ(n.beyond_3sigma[1], 1U);
  EXPECT_EQ(n.beyond_3sigma[2], 1U);
  EXPECT_EQ(n.beyond_5sigma[0], 0U);
  EXPECT_EQ(n.beyond_5sigma[1], 1U);
  EXPECT_EQ(n.beyond_5sigma[2], 0U);
  EXPECT_DOUBLE_EQ(n.worst_ratio[0], 4.0 / 3.0);
  EXPECT_DOUBLE_EQ(n.worst_ratio[1], 2.0);
  EXPECT_DOUBLE_EQ(n.worst_ratio[2], 5.0 / 3.0);
  EXPECT_EQ(n.worst_at_s, 3.0) << "the largest ratio of any axis";
  EXPECT_DOUBLE_EQ(n.fraction_beyond_3sigma(1), 0.25);
  EXPECT_EQ(n.fraction_beyond_3sigma(3), 0.0);
  EXPECT_EQ(n.bad_sigma, 0U);
}

TEST(NavIntegrity, ABoundThatIsNotPositiveAndFiniteCountsAsExceeded) {
  tools::NavIntegrity n;
  n.add(1.0, {0.0, 1.0, 1.0}, {0.0, NAN, 3.0});
  EXPECT_EQ(n.outputs, 1U);
  EXPECT_EQ(n.bad_sigma, 1U);
  EXPECT_EQ(n.beyond_3sigma[0], 1U);
  EXPECT_EQ(n.beyond_5sigma[1], 1U);
  EXPECT_EQ(n.beyond_3sigma[2], 0U);
  EXPECT_EQ(n.worst_ratio[0], 0.0) << "no ratio from a bound that is not one";
  n.add(2.0, {NAN, 0.0, 0.0}, {3.0, 3.0, 3.0});
  EXPECT_EQ(n.bad_sigma, 2U);
  EXPECT_EQ(n.beyond_3sigma[0], 2U) << "a non-finite error is beyond any bound";
}

}  // namespace
