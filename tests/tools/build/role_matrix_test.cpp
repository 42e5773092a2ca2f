/**
 * @file role_matrix_test.cpp
 * @brief tools/study/role_matrix.py (docs/FDIR.md, "What each role's failure does"): one row per role
 *        and kind, counted from the runs' result.json, faults.csv and events.log as the join wrote them.
 */
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

constexpr const char* kHeader =
    "t_s,kind,tile,role,delivered,carve,crashed,effect,accusing_event,accusing_tile,latency_ms,diagnosis,"
    "wrong_accusations,first_wrong_event,first_wrong_tile,recovery,recovery_by,recovery_ms,service_gap_ms,upset\n";

class RoleMatrix : public ::testing::Test {
 protected:
  void SetUp() override {
    std::string tmpl = (fs::temp_directory_path() / "role_matrix_XXXXXX").string();
    ASSERT_NE(::mkdtemp(tmpl.data()), nullptr);
    dir_ = tmpl;
  }
  void TearDown() override {
    std::error_code ec;
    fs::remove_all(dir_, ec);
  }

  /** One run folder: its result, its faults.csv row and its events. */
  void add_run(const std::string& name, const std::string& result, const std::string& row, const std::string& events) {
    const fs::path run = dir_ / "runs" / name;
    fs::create_directories(run / "out");
    std::ofstream(run / "result.json") << result;
    std::ofstream(run / "out" / "faults.csv") << kHeader << row << "\n";
    std::ofstream(run / "out" / "events.log") << events;
  }

  std::pair<int, std::string> table(const fs::path& folder) const {
    const std::string cmd = "python3 " + std::string(build_info::kRepoRoot) + "/tools/study/role_matrix.py " +
                            folder.string() + " 2>&1";
    return test_support::run_command(cmd);
  }

  fs::path dir_;
};

TEST_F(RoleMatrix, CountsEachRoleAndKindFromTheJoinsVerdicts) {
  // Two hangs of the filter: one restarted in place, one moved to spare 22; and a lost I/O switch.
  add_run("000000", R"({"role": "filter", "kind": "core_hang", "outcome": "detected_recovered", "misdiagnosed": 0})",
          "10.0,core_hang,18,filter,1,,0,detected,watchdog_expired,18,40.000,right,0,,,recovered,filter_outputs,"
          "60.000,70.000,",
          "   10.040000  DETECT   tile 18  watchdog_expired: ...\n");
  add_run("000001", R"({"role": "filter", "kind": "core_hang", "outcome": "detected_recovered", "misdiagnosed": 0})",
          "12.0,core_hang,18,filter,1,,0,detected,watchdog_expired,18,20.000,right,0,,,recovered,filter_outputs,"
          "300.000,310.000,",
          "   12.300000  ISOLATE  tile  0  role_moved: role slot 3 moves from retired tile 18 to spare 22 "
          "(directory version 2)\n");
  add_run("000002", R"({"role": "io", "kind": "switch_fail", "outcome": "detected_lost", "misdiagnosed": 1})",
          "6.0,switch_fail,9,io,1,,0,detected,switch_failed,10,900.000,wrong,1,switch_failed,10,none,,,,", "");
  // Named right and wrongly as well: detected right, and misdiagnosed.
  add_run("000003", R"({"role": "vision", "kind": "switch_fail", "outcome": "detected_recovered", "misdiagnosed": 1})",
          "20.0,switch_fail,36,vision,1,,0,detected,switch_failed,36,37.000,right_and_wrong,1,worker_silent,36,"
          "recovered,frame_done,900.000,,",
          "");
  const auto [status, out] = table(dir_);
  ASSERT_EQ(status, 0) << out;
  EXPECT_NE(out.find("| filter | core_hang | 2 | 2 | 0 | 30 (40) | 2 | filter_outputs 2 | 190 (310) | no move 1x, "
                     "spare 22 1x | - |"),
            std::string::npos)
      << out;
  EXPECT_NE(out.find("| io | switch_fail | 1 | 0 | 1 | - | 0 | - | - | - | detected_lost 1 |"), std::string::npos)
      << out;
  EXPECT_NE(out.find("| vision | switch_fail | 1 | 1 | 1 | 37 (37) | 1 | frame_done 1 | - | no move 1x | - |"),
            std::string::npos)
      << out;
}

TEST_F(RoleMatrix, AFolderWithoutRunsIsRefused) {
  const auto [status, out] = table(dir_);
  EXPECT_EQ(status, 2) << out;
  EXPECT_NE(out.find("usage"), std::string::npos) << out;
}

}  // namespace
