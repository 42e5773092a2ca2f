/**
 * @file trn_mission_test.cpp
 * @brief The mission image as a user runs it: same inputs, same trace hash and outputs;
 *        bad inputs give exit status 2 and leave no run folder behind.
 */
#include "build_info.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

#include <sys/wait.h>
#include <unistd.h>

namespace {

namespace fs = std::filesystem;

std::string binary() { return std::string(build_info::kRepoRoot) + "/build/trn_mission"; }

/** Runs a command; returns its exit status (-1 if it did not exit). */
int run(const std::string& cmd) {
  const int status = std::system((cmd + " >/dev/null 2>&1").c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

class TrnMissionBinary : public ::testing::Test {
 protected:
  void SetUp() override {
    if (!fs::exists(binary())) {
      GTEST_SKIP() << binary() << " is not built (make test builds it)";
    }
    dir_ = fs::temp_directory_path() / ("trn_mission_test_" + std::to_string(::getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override {
    std::error_code ec;
    fs::remove_all(dir_, ec);
  }

  fs::path dir_;
};

nlohmann::json read_json(const fs::path& p) {
  std::ifstream in(p);
  return nlohmann::json::parse(in);
}

TEST_F(TrnMissionBinary, SameInputsGiveTheSameTraceHashAndAFullRunFolder) {
  const std::string common = binary() + " --duration 3 --quiet --demo-faults --seed 4 --out ";
  ASSERT_EQ(run(common + (dir_ / "a").string()), 0);
  ASSERT_EQ(run(common + (dir_ / "b").string()), 0);
  for (const char* f : {"summary.json", "nav.csv", "events.log", "tile_map.csv"}) {
    EXPECT_TRUE(fs::exists(dir_ / "a" / f)) << f;
  }
  const nlohmann::json a = read_json(dir_ / "a" / "summary.json");
  const nlohmann::json b = read_json(dir_ / "b" / "summary.json");
  EXPECT_EQ(a["trace_hash"], b["trace_hash"]);
  EXPECT_EQ(a["final_position_error_m"], b["final_position_error_m"]);
  EXPECT_EQ(a["heap_allocs_after_init"], 0);
  EXPECT_EQ(a["deadline_misses"], 0);
  EXPECT_EQ(a["seed"], 4);
  for (const char* key : {"scenario", "emulated_s", "host_s", "realtime_factor", "max_position_error_after_convergence_m",
                          "final_velocity_error_mps", "final_attitude_error_deg", "frames", "matches_per_frame_mean",
                          "faults_injected", "faults_detected", "faults_recovered"}) {
    EXPECT_TRUE(a.contains(key)) << key;
  }
  // Another seed flies another run.
  ASSERT_EQ(run(binary() + " --duration 3 --quiet --seed 5 --out " + (dir_ / "c").string()), 0);
  EXPECT_NE(read_json(dir_ / "c" / "summary.json")["trace_hash"], a["trace_hash"]);
}

TEST_F(TrnMissionBinary, BadInputsExit2AndWriteNothing) {
  const std::string out = " --out " + (dir_ / "run").string();
  {
    std::ofstream bad(dir_ / "bad_plan.toml");
    bad << "name = \"x\"\n[[fault]]\nkind = \"switch_fail\"\ntile = 99\n";
    std::ofstream bad_scenario(dir_ / "bad_scenario.toml");
    bad_scenario << "[terrain]\nno_such_key = 1\n";
  }
  EXPECT_EQ(run(binary() + " --scenario " + (dir_ / "missing.toml").string() + out), 2);
  EXPECT_EQ(run(binary() + " --scenario " + (dir_ / "bad_scenario.toml").string() + out), 2);
  EXPECT_EQ(run(binary() + " --faults " + (dir_ / "bad_plan.toml").string() + out), 2);
  EXPECT_EQ(run(binary() + " --faults " + (dir_ / "bad_plan.toml").string() + " --demo-faults" + out), 2);
  EXPECT_EQ(run(binary() + " --duration 999" + out), 2);
  EXPECT_EQ(run(binary() + " --no-such-option" + out), 2);
  EXPECT_EQ(run(binary() + " --out /proc/trn_mission_cannot_write_here"), 2);
  fs::remove(dir_ / "bad_plan.toml");
  fs::remove(dir_ / "bad_scenario.toml");
  // No run folder and no staging folder left behind.
  EXPECT_TRUE(fs::is_empty(dir_));
}

}  // namespace
