/**
 * @file run_tests_test.cpp
 * @brief tools/build/run_tests.sh: a suite that dies without its report is a loud failure
 *        (named, counted, non-zero exit), alone or beside suites that pass.
 */
#include "build_info.hpp"

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
  /** A suite whose report says two tests ran and passed. */
  std::string passing() const {
    return fake("passing_tests",
                "xml=${1#--gtest_output=xml:}\n"
                "printf '<?xml version=\"1.0\"?>\\n<testsuites tests=\"2\" failures=\"0\" disabled=\"0\" "
                "errors=\"0\" time=\"0\" name=\"AllTests\">\\n</testsuites>\\n' > \"$xml\"\n");
  }
  /** A suite killed by SIGSEGV before it writes its report, as a crash in a test does. */
  std::string crashing() const { return fake("crashing_tests", "kill -SEGV $$\n"); }

  /** Runs run_tests.sh over @p bins; returns (exit status, everything it printed). */
  std::pair<int, std::string> run(const std::string& bins) const {
    const std::string cmd = std::string(build_info::kRepoRoot) + "/tools/build/run_tests.sh " +
                            (dir_ / "results").string() + " " + bins + " 2>&1";
    std::string out;
    FILE* p = ::popen(cmd.c_str(), "r");
    if (p == nullptr) {
      return {-1, out};
    }
    char buf[4096];
    for (std::size_t n = 0; (n = std::fread(buf, 1, sizeof buf, p)) > 0;) {
      out.append(buf, n);
    }
    const int status = ::pclose(p);
    return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, out};
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
  EXPECT_EQ(last_line(out), "tests: 2 passed, 0 failed") << out;
}

TEST_F(RunTests, ASuiteThatCrashesWithoutAReportIsNamedCountedAndFailsTheRun) {
  const auto [rc, out] = run(crashing());
  EXPECT_NE(rc, 0) << out;
  EXPECT_NE(out.find("!!! crashing_tests exited with status 139 and wrote no report"), std::string::npos) << out;
  EXPECT_NE(out.find("broken binaries: crashing_tests"), std::string::npos) << out;
  EXPECT_EQ(last_line(out), "tests: 0 passed, 1 failed") << out;
}

TEST_F(RunTests, ACrashAmongPassingSuitesStillFailsTheRun) {
  const auto [rc, out] = run(passing() + " " + crashing() + " " + passing());
  EXPECT_NE(rc, 0) << out;
  EXPECT_NE(out.find("!!! crashing_tests exited with status 139 and wrote no report"), std::string::npos) << out;
  EXPECT_EQ(last_line(out), "tests: 4 passed, 1 failed") << out;
}

TEST_F(RunTests, ASuiteThatExitsZeroWithoutAReportFails) {
  const auto [rc, out] = run(fake("silent_tests", "exit 0\n"));
  EXPECT_NE(rc, 0) << out;
  EXPECT_NE(out.find("!!! silent_tests exited with status 0 and wrote no report"), std::string::npos) << out;
  EXPECT_EQ(last_line(out), "tests: 0 passed, 1 failed") << out;
}

}  // namespace
