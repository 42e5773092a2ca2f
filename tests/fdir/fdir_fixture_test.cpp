/**
 * @file fdir_fixture_test.cpp
 * @brief The fixture that runs a test's body as a task on tile 0 fails the test when the body does not
 *        run to its end, so assertions placed inside a body cannot pass by never being reached.
 */
#include "tests/fdir/fdir_fixture.hpp"

#include <gtest/gtest-spi.h>
#include <gtest/gtest.h>

namespace {

/** A body that blocks past the fixture's 10 ticks, as a body waiting for an event that never comes does. */
void blocks_past_the_run() { k::sleep(1000U); }

int g_reached = 0;
void returns() { ++g_reached; }

TEST(FdirFixture, ABodyThatDoesNotReturnFailsTheTest) {
  EXPECT_NONFATAL_FAILURE(fdir_test::run_on_tile0(&blocks_past_the_run), "did not run to its end");
}

TEST(FdirFixture, ABodyThatReturnsPasses) {
  g_reached = 0;
  fdir_test::run_on_tile0(&returns);
  EXPECT_EQ(g_reached, 1);
}

}  // namespace
