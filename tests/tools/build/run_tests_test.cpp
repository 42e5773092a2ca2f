/**
 * @file run_tests_test.cpp
 * @brief tools/build/run_tests.sh: counts come from a real GoogleTest program's report, test case by
 *        test case (passed, failed, skipped); a skip, a binary that ran no test, and a suite that dies
 *        without its report are loud failures (named, counted, non-zero exit).
 */
#include "build_dirs.hpp"
#include "build_info.hpp"
#include "tests/support/run_command.hpp"

#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <utility>

#include <sys/wait.h>

namespace {

namespace fs = std::filesystem;

/** Fake test binaries (shell scripts taking --gtest_output=xml:PATH) in a fresh temporary folder. */
class RunTests : public ::testing::Test {
 protected:
  void SetUp() override {
    std::string tmpl = (fs::temp_directory_path() / "run_tests_XXXXXX").string();
    ASSERT_NE(::mkdtemp(tmpl.data()), nullptr);
    dir_ = tmpl;
  }
  void TearDown() override {
    std::error_code ec;
    fs::remove_all(dir_, ec);
  }

  /** Writes an executable script @p name with @p body after the shebang; returns its path. */
  std::string fake(const std::string& name, const std::string& body) const {
    const fs::path p = dir_ / name;
    std::ofstream(p) << "#!/bin/sh\n" << body;
    fs::permissions(p, fs::perms::owner_all);
    return p.string();
  }
  /**
   * The real GoogleTest program tests/fixtures/gtest_sample (Sample.Passes, AlsoPasses, Fails, Skips and a
   * disabled test), run with @p filter as GTEST_FILTER, through a script named @p name.
   */
  std::string sample(const std::string& name, const std::string& filter) const {
    return fake(name, "GTEST_FILTER='" + filter + "' exec " + std::string(build_info::kBinDir) +
                          "/tests/fixtures/gtest_sample \"$@\"\n");
  }
  /** The real program with its two passing tests only. */
  std::string passing() const { return sample("passing_tests", "Sample.Passes:Sample.AlsoPasses"); }
  /** A suite killed by SIGSEGV before it writes its report, as a crash in a test does. */
  std::string crashing() const { return fake("crashing_tests", "kill -SEGV $$\n"); }

  /** Runs run_tests.sh over @p bins with TEST_FILTERS=@p filters; returns (exit status, everything it printed). */
  std::pair<int, std::string> run(const std::string& bins, const std::string& filters = "") const {
    const std::string cmd = "TEST_FILTERS='" + filters + "' " + std::string(build_info::kRepoRoot) +
                            "/tools/build/run_tests.sh " + (dir_ / "results").string() + " " + bins + " 2>&1";
    return test_support::run_command(cmd);
  }

  fs::path dir_;
};

/** The last line printed: run_tests.sh's summary. */
std::string last_line(std::string out) {
  while (!out.empty() && out.back() == '\n') {
    out.pop_back();
  }
  return out.substr(out.rfind('\n') + 1);  // npos + 1 is 0: a single line is the whole text
}

TEST_F(RunTests, PassingSuitesCountTheirTestsAndExitZero) {
  const auto [rc, out] = run(passing());
  EXPECT_EQ(rc, 0) << out;
  EXPECT_EQ(last_line(out), "tests: 2 passed, 0 failed, 0 skipped") << out;
}

// The counts of a real GoogleTest report (Debian's GoogleTest writes `skipped` on each <testsuite>, not
// on the root): each kind of test case counted as what it is, a disabled one not at all.
TEST_F(RunTests, ARealSuitesPassedFailedAndSkippedTestsAreEachCounted) {
  const auto [rc, out] = run(sample("mixed_tests", "Sample.*:Sample.DISABLED_IsDisabled"));
  EXPECT_NE(rc, 0) << out;
  EXPECT_EQ(last_line(out), "tests: 2 passed, 1 failed, 1 skipped") << out;
  EXPECT_NE(out.find("!!! skipped: Sample.Skips"), std::string::npos) << out;
}

// A skip is a test that did not run: it fails the run although nothing failed.
TEST_F(RunTests, ASkippedTestFailsTheRunAndIsNamed) {
  const auto [rc, out] = run(sample("skipping_tests", "Sample.Passes:Sample.Skips"));
  EXPECT_NE(rc, 0) << out;
  EXPECT_EQ(last_line(out), "tests: 1 passed, 0 failed, 1 skipped") << out;
  EXPECT_NE(out.find("!!! skipped: Sample.Skips"), std::string::npos) << out;
}

// A binary whose tests all are filtered out or disabled writes a valid report and exits 0, and tested nothing.
TEST_F(RunTests, ABinaryThatRanNoTestFails) {
  const auto [rc, out] = run(sample("empty_tests", "NoSuchTest.*"));
  EXPECT_NE(rc, 0) << out;
  EXPECT_NE(out.find("!!! empty_tests ran no test"), std::string::npos) << out;
  EXPECT_EQ(last_line(out), "tests: 0 passed, 1 failed, 0 skipped") << out;
}

// TEST_FILTERS runs the named tests of one binary only (CI's sanitizer stage flies a subset this way).
TEST_F(RunTests, AFilterRunsTheTestsItNamesOfItsBinaryOnly) {
  const auto [rc, out] = run(sample("filtered_tests", "Sample.*") + " " + passing(),
                             "filtered_tests=Sample.Passes:Sample.AlsoPasses");
  EXPECT_EQ(rc, 0) << out;
  EXPECT_EQ(last_line(out), "tests: 4 passed, 0 failed, 0 skipped") << "Fails and Skips filtered out\n" << out;
}

// A filter of whole names that holds a name no test has (a test renamed since) fails the run.
TEST_F(RunTests, AFilterNamingATestThatDoesNotExistFails) {
  const auto [rc, out] = run(sample("filtered_tests", "Sample.*"), "filtered_tests=Sample.Passes:Sample.Renamed");
  EXPECT_NE(rc, 0) << out;
  EXPECT_NE(out.find("!!! filtered_tests ran 1 of the 2 tests its filter names"), std::string::npos) << out;
}

// A report cut short (a crash while writing it) cannot be read: a failure, not a count of zero.
TEST_F(RunTests, AReportThatIsNotWellFormedIsAFailure) {
  const auto [rc, out] = run(fake("truncated_tests", R"(xml=${1#--gtest_output=xml:}
printf '<?xml version="1.0"?>\n<testsuites tests="2">\n<testsuite ' > "$xml"
)"));
  EXPECT_NE(rc, 0) << out;
  EXPECT_NE(out.find("!!! truncated_tests exited with status 0 and its report cannot be read"), std::string::npos)
      << out;
  EXPECT_EQ(last_line(out), "tests: 0 passed, 1 failed, 0 skipped") << out;
}

TEST_F(RunTests, ASuiteThatCrashesWithoutAReportIsNamedCountedAndFailsTheRun) {
  const auto [rc, out] = run(crashing());
  EXPECT_NE(rc, 0) << out;
  EXPECT_NE(out.find("!!! crashing_tests exited with status 139 and wrote no report"), std::string::npos) << out;
  EXPECT_NE(out.find("broken binaries: crashing_tests"), std::string::npos) << out;
  EXPECT_EQ(last_line(out), "tests: 0 passed, 1 failed, 0 skipped") << out;
}

TEST_F(RunTests, ACrashAmongPassingSuitesStillFailsTheRun) {
  const auto [rc, out] = run(passing() + " " + crashing() + " " + passing());
  EXPECT_NE(rc, 0) << out;
  EXPECT_NE(out.find("!!! crashing_tests exited with status 139 and wrote no report"), std::string::npos) << out;
  EXPECT_EQ(last_line(out), "tests: 4 passed, 1 failed, 0 skipped") << out;
}

TEST_F(RunTests, ASuiteThatExitsZeroWithoutAReportFails) {
  const auto [rc, out] = run(fake("silent_tests", "exit 0\n"));
  EXPECT_NE(rc, 0) << out;
  EXPECT_NE(out.find("!!! silent_tests exited with status 0 and wrote no report"), std::string::npos) << out;
  EXPECT_EQ(last_line(out), "tests: 0 passed, 1 failed, 0 skipped") << out;
}

}  // namespace
