/**
 * @file run_folder_test.cpp
 * @brief The run folder is complete or absent (commit replaces, abandon leaves nothing, bad folders are errors);
 *        summary.json parses back; nav.csv and events.log have their layout; plots with and without gnuplot.
 */
#include "tools/common/mission/run_folder.hpp"

#include "tests/support/folder_permissions.hpp"
#include "tests/support/heap_probe.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

#include <sys/stat.h>
#include <unistd.h>

namespace {

namespace fs = std::filesystem;

/** A fresh temporary folder, removed (made writable first) at the end of the test. */
class TempDir {
 public:
  TempDir() {
    std::string tmpl = (fs::temp_directory_path() / "mission_io_XXXXXX").string();
    const char* made = ::mkdtemp(tmpl.data());
    EXPECT_NE(made, nullptr);
    path_ = tmpl;
  }
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;
  TempDir(TempDir&&) = delete;
  TempDir& operator=(TempDir&&) = delete;
  ~TempDir() {
    std::error_code ec;
    fs::permissions(path_, fs::perms::owner_all, fs::perm_options::add, ec);
    fs::remove_all(path_, ec);
  }
  const std::string& path() const { return path_; }
  std::string operator/(const std::string& name) const { return path_ + "/" + name; }

 private:
  std::string path_;
};

std::string read_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

void write_file(const std::string& path, const std::string& text) {
  std::ofstream out(path, std::ios::binary);
  out << text;
}

std::vector<std::string> entries(const std::string& dir) {
  std::vector<std::string> out;
  for (const fs::directory_entry& e : fs::directory_iterator(dir)) {
    out.push_back(e.path().filename().string());
  }
  std::sort(out.begin(), out.end());
  return out;
}

std::vector<std::string> lines_of(const std::string& text) {
  std::vector<std::string> out;
  std::stringstream ss(text);
  for (std::string l; std::getline(ss, l);) {
    out.push_back(l);
  }
  return out;
}

std::vector<std::string> split(const std::string& line, char sep) {
  std::vector<std::string> out;
  std::stringstream ss(line);
  for (std::string f; std::getline(ss, f, sep);) {
    out.push_back(f);
  }
  return out;
}

// ------------------------------------------------------------------ RunFolder

TEST(RunFolder, NothingAppearsAtTheDestinationBeforeCommit) {
  TempDir tmp;
  const std::string dir = tmp / "out/run1";  // the parent "out" does not exist yet
  std::string error;
  std::optional<tools::RunFolder> rf = tools::RunFolder::open(dir, error);
  ASSERT_TRUE(rf.has_value()) << error;
  write_file(rf->staging_path("summary.json"), "{}\n");
  EXPECT_FALSE(fs::exists(dir));
  EXPECT_TRUE(fs::exists(rf->staging_path("summary.json")));
  EXPECT_EQ(fs::path(rf->staging_dir()).parent_path(), fs::path(tmp / "out")) << "staged next to the destination";
  ASSERT_TRUE(rf->commit(error)) << error;
  EXPECT_TRUE(rf->committed());
  EXPECT_EQ(read_file(dir + "/summary.json"), "{}\n");
  EXPECT_EQ(entries(tmp / "out"), std::vector<std::string>{"run1"}) << "no staging folder left";
}

TEST(RunFolder, CommitReplacesThePreviousRunWhole) {
  TempDir tmp;
  const std::string dir = tmp / "run";
  std::string error;
  {
    std::optional<tools::RunFolder> a = tools::RunFolder::open(dir, error);
    ASSERT_TRUE(a.has_value()) << error;
    write_file(a->staging_path("a.txt"), "first");
    ASSERT_TRUE(a->commit(error)) << error;
  }
  std::optional<tools::RunFolder> b = tools::RunFolder::open(dir + "/", error);  // a trailing slash is the same folder
  ASSERT_TRUE(b.has_value()) << error;
  write_file(b->staging_path("b.txt"), "second");
  EXPECT_TRUE(fs::exists(dir + "/a.txt")) << "the previous run stays until the commit";
  ASSERT_TRUE(b->commit(error)) << error;
  EXPECT_FALSE(fs::exists(dir + "/a.txt")) << "nothing of the previous run is mixed in";
  EXPECT_EQ(read_file(dir + "/b.txt"), "second");
  EXPECT_EQ(entries(tmp.path()), std::vector<std::string>{"run"});
  EXPECT_FALSE(b->commit(error)) << "a second commit is refused";
}

TEST(RunFolder, AnEmptyFolderIsReplaced) {
  TempDir tmp;
  fs::create_directory(tmp / "empty");
  std::string error;
  std::optional<tools::RunFolder> rf = tools::RunFolder::open(tmp / "empty", error);
  ASSERT_TRUE(rf.has_value()) << error;
  write_file(rf->staging_path("x"), "x");
  ASSERT_TRUE(rf->commit(error)) << error;
  EXPECT_TRUE(fs::exists(tmp / "empty/x"));
}

TEST(RunFolder, AbandonAndTheDestructorLeaveNothing) {
  TempDir tmp;
  std::string error;
  {
    std::optional<tools::RunFolder> rf = tools::RunFolder::open(tmp / "run", error);
    ASSERT_TRUE(rf.has_value()) << error;
    write_file(rf->staging_path("nav.csv"), "t_s\n1\n");
    fs::create_directory(rf->staging_path("sub"));
    write_file(rf->staging_path("sub/deep"), "x");
    rf->abandon();
    EXPECT_TRUE(entries(tmp.path()).empty());
  }
  {
    std::optional<tools::RunFolder> rf = tools::RunFolder::open(tmp / "run", error);
    ASSERT_TRUE(rf.has_value()) << error;
    write_file(rf->staging_path("nav.csv"), "t_s\n1\n");
    // Moving keeps one owner: only the last one cleans up.
    tools::RunFolder moved = std::move(*rf);
    rf.reset();
    EXPECT_TRUE(fs::exists(moved.staging_path("nav.csv")));
  }  // destroyed without commit
  EXPECT_TRUE(entries(tmp.path()).empty());
}

TEST(RunFolder, AbandonedRunKeepsThePreviousRun) {
  TempDir tmp;
  const std::string dir = tmp / "run";
  std::string error;
  {
    std::optional<tools::RunFolder> a = tools::RunFolder::open(dir, error);
    ASSERT_TRUE(a.has_value()) << error;
    write_file(a->staging_path("a.txt"), "first");
    ASSERT_TRUE(a->commit(error)) << error;
  }
  {
    std::optional<tools::RunFolder> b = tools::RunFolder::open(dir, error);
    ASSERT_TRUE(b.has_value()) << error;
    write_file(b->staging_path("b.txt"), "half");
  }
  EXPECT_EQ(read_file(dir + "/a.txt"), "first");
  EXPECT_FALSE(fs::exists(dir + "/b.txt"));
  EXPECT_EQ(entries(tmp.path()), std::vector<std::string>{"run"});
}

TEST(RunFolder, AFolderThatIsNotARunFolderIsNeverReplaced) {
  TempDir tmp;
  fs::create_directory(tmp / "home");
  write_file(tmp / "home/precious.txt", "keep me");
  std::string error;
  EXPECT_FALSE(tools::RunFolder::open(tmp / "home", error).has_value());
  EXPECT_NE(error.find("home: exists and is not a run folder (not empty, no .trn_run marker): refusing to replace it"),
            std::string::npos)
      << error;
  EXPECT_EQ(read_file(tmp / "home/precious.txt"), "keep me");
  EXPECT_EQ(entries(tmp.path()), std::vector<std::string>{"home"});
  write_file(tmp / "file", "x");
  EXPECT_FALSE(tools::RunFolder::open(tmp / "file", error).has_value());
  EXPECT_NE(error.find("file: exists and is not a folder"), std::string::npos) << error;
  EXPECT_FALSE(tools::RunFolder::open("", error).has_value());
  EXPECT_NE(error.find("not a usable folder name"), std::string::npos) << error;
}

TEST(RunFolder, AParentThatIsAFileIsAnError) {
  TempDir tmp;
  write_file(tmp / "blocker", "x");
  std::string error;
  EXPECT_FALSE(tools::RunFolder::open(tmp / "blocker/run", error).has_value());
  EXPECT_NE(error.find("blocker/run: cannot create the parent folder"), std::string::npos) << error;
  EXPECT_EQ(entries(tmp.path()), std::vector<std::string>{"blocker"});
}

TEST(RunFolder, AnUnwritableParentIsAnError) {
  TempDir tmp;
  fs::create_directory(tmp / "ro");
  fs::permissions(tmp / "ro", fs::perms::owner_read | fs::perms::owner_exec);
  std::string error;
  {
    // Root writes through permission bits unless this thread lowers the capabilities that let it.
    const test_support::PermissionBitsHold bits;
    const std::string probe = tmp / "ro/probe";
    ASSERT_NE(::mkdir(probe.c_str(), 0755), 0) << "the folder's permission bits do not stop this process";
    EXPECT_FALSE(tools::RunFolder::open(tmp / "ro/run", error).has_value());
  }
  EXPECT_NE(error.find("ro/run: the folder"), std::string::npos) << error;
  EXPECT_NE(error.find("is not writable: Permission denied"), std::string::npos) << error;
  EXPECT_TRUE(entries(tmp / "ro").empty());
}

// ------------------------------------------------------------------ summary.json

tools::Summary sample_summary() {
  tools::Summary s;
  s.scenario = "quote \" backslash \\ newline \n unicode \xc3\xa9";
  s.fault_plan = "demo";
  s.seed = 9007199254740993ULL;  // beyond 2^53: must stay exact
  s.emulated_s = 60.0;
  s.host_s = 2.5;
  s.realtime_factor = 24.0;
  s.final_position_error_m = 3.25;
  s.max_position_error_after_convergence_m = 7.5;
  s.final_velocity_error_mps = 0.05;
  s.final_attitude_error_deg = std::numeric_limits<double>::quiet_NaN();
  s.frames = 60U;
  s.matches_per_frame_mean = 142.5;
  s.deadline_misses = 0U;
  s.heap_allocs_after_init = 0U;
  s.faults_injected = 9U;
  s.faults_detected = 9U;
  s.faults_recovered = 8U;
  s.trace_hash = tools::trace_hash_hex(0x0123456789ABCDEFULL);
  s.extra = {{"net_bit_flips", 8.0}, {"infinite", std::numeric_limits<double>::infinity()}};
  return s;
}

TEST(Summary, JsonParsesBackWithEveryKey) {
  TempDir tmp;
  const tools::Summary s = sample_summary();
  std::string error;
  ASSERT_TRUE(tools::write_summary_json(tmp / "summary.json", s, error)) << error;
  const nlohmann::json j = nlohmann::json::parse(read_file(tmp / "summary.json"));
  for (const char* key :
       {"scenario", "seed", "emulated_s", "host_s", "realtime_factor", "final_position_error_m",
        "max_position_error_after_convergence_m", "final_velocity_error_mps", "final_attitude_error_deg", "frames",
        "matches_per_frame_mean", "deadline_misses", "heap_allocs_after_init", "faults_injected", "faults_detected",
        "faults_recovered", "trace_hash"}) {
    EXPECT_TRUE(j.contains(key)) << key;
  }
  EXPECT_EQ(j["scenario"].get<std::string>(), s.scenario);
  EXPECT_EQ(j["fault_plan"].get<std::string>(), "demo");
  EXPECT_EQ(j["seed"].get<std::uint64_t>(), 9007199254740993ULL);
  EXPECT_DOUBLE_EQ(j["realtime_factor"].get<double>(), 24.0);
  EXPECT_DOUBLE_EQ(j["final_position_error_m"].get<double>(), 3.25);
  EXPECT_TRUE(j["final_attitude_error_deg"].is_null()) << "NaN is written as null";
  EXPECT_EQ(j["frames"].get<std::uint64_t>(), 60U);
  EXPECT_EQ(j["faults_recovered"].get<std::uint64_t>(), 8U);
  EXPECT_EQ(j["trace_hash"].get<std::string>(), "0123456789abcdef");
  EXPECT_DOUBLE_EQ(j["net_bit_flips"].get<double>(), 8.0);
  EXPECT_TRUE(j["infinite"].is_null());
}

TEST(Summary, ExtraKeysMayNotRepeatAKey) {
  tools::Summary s = sample_summary();
  s.extra.emplace_back("frames", 1.0);
  std::string json;
  std::string error;
  EXPECT_FALSE(tools::summary_json(s, json, error));
  EXPECT_NE(error.find("extra key 'frames' is empty or repeats a key"), std::string::npos) << error;
  TempDir tmp;
  EXPECT_FALSE(tools::write_summary_json(tmp / "summary.json", s, error));
  EXPECT_FALSE(fs::exists(tmp / "summary.json")) << "nothing half-written";
}

TEST(Summary, ObjectsAreWrittenAsNestedObjectsOfNumbers) {
  tools::Summary s = sample_summary();
  s.objects.push_back({"energy_j_by_phase", {{"descent", 12.5}, {"landing", std::numeric_limits<double>::quiet_NaN()}}});
  s.objects.push_back({"empty", {}});
  std::string json;
  std::string error;
  ASSERT_TRUE(tools::summary_json(s, json, error)) << error;
  const nlohmann::ordered_json j = nlohmann::ordered_json::parse(json);
  ASSERT_TRUE(j["energy_j_by_phase"].is_object());
  EXPECT_DOUBLE_EQ(j["energy_j_by_phase"]["descent"].get<double>(), 12.5);
  EXPECT_TRUE(j["energy_j_by_phase"]["landing"].is_null());
  EXPECT_EQ(j["energy_j_by_phase"].begin().key(), "descent") << "in the given order";
  EXPECT_TRUE(j["empty"].is_object());
  EXPECT_TRUE(j["empty"].empty());
  EXPECT_EQ((--j.end()).key(), "empty") << "after the extras";
  s.objects.push_back({"frames", {}});
  EXPECT_FALSE(tools::summary_json(s, json, error));
  EXPECT_NE(error.find("object 'frames' is empty or repeats a key"), std::string::npos) << error;
  s.objects.back() = {"by_role", {{"vision", 1.0}, {"vision", 2.0}}};
  EXPECT_FALSE(tools::summary_json(s, json, error));
  EXPECT_NE(error.find("key 'vision' of 'by_role' is empty or repeated"), std::string::npos) << error;
}

TEST(Summary, UnwritablePathIsAnError) {
  std::string error;
  EXPECT_FALSE(tools::write_summary_json("/nonexistent-folder/summary.json", sample_summary(), error));
  EXPECT_NE(error.find("/nonexistent-folder/summary.json: cannot create"), std::string::npos) << error;
}

// ------------------------------------------------------------------ nav.csv

tools::NavRow nav_row(double t) {
  tools::NavRow r;
  r.t_s = t;
  r.truth_p_m = {100.0 + t, -200.0, 4000.0 - 80.0 * t};
  r.est_p_m = {103.0 + t, -196.0, 4000.0 - 80.0 * t};  // 3-4-0: error 5 m
  r.truth_v_mps = {1.0, 0.0, -80.0};
  r.est_v_mps = {1.1, 0.0, -80.0};
  r.sigma3_p_m = {9.0, 9.0, 12.0};
  r.attitude_error_deg = 0.0125;
  return r;
}

TEST(NavCsv, HeaderThenOneRowPerSample) {
  TempDir tmp;
  tools::NavCsv csv;
  std::string error;
  ASSERT_TRUE(csv.open(tmp / "nav.csv", error)) << error;
  for (int i = 0; i < 3; ++i) {
    EXPECT_TRUE(csv.write(nav_row(0.01 * i)));
  }
  tools::NavRow bad = nav_row(0.03);
  bad.sigma3_p_m[0] = std::numeric_limits<double>::quiet_NaN();
  EXPECT_TRUE(csv.write(bad));
  ASSERT_TRUE(csv.close(error)) << error;
  EXPECT_EQ(csv.rows(), 4U);
  const std::vector<std::string> lines = lines_of(read_file(tmp / "nav.csv"));
  ASSERT_EQ(lines.size(), 5U);
  EXPECT_EQ(lines[0], tools::NavCsv::kHeader);
  const std::vector<std::string> head = split(lines[0], ',');
  ASSERT_EQ(head.size(), 18U);
  EXPECT_EQ(head[0], "t_s");
  EXPECT_EQ(head[13], "pos_err_m");
  EXPECT_EQ(head[17], "att_err_deg");
  for (std::size_t i = 1; i < lines.size(); ++i) {
    EXPECT_EQ(split(lines[i], ',').size(), head.size()) << lines[i];
  }
  const std::vector<std::string> row1 = split(lines[2], ',');
  EXPECT_DOUBLE_EQ(std::stod(row1[0]), 0.01);
  EXPECT_DOUBLE_EQ(std::stod(row1[1]), 100.01);
  EXPECT_DOUBLE_EQ(std::stod(row1[13]), 5.0) << "position error is the norm of estimate - truth";
  EXPECT_DOUBLE_EQ(std::stod(row1[16]), 12.0);
  EXPECT_DOUBLE_EQ(std::stod(row1[17]), 0.0125);
  EXPECT_EQ(split(lines[4], ',')[14], "nan");
  EXPECT_EQ(tools::NavCsv::format_row(nav_row(0.01)), lines[2]);
}

TEST(NavCsv, WritingRowsAllocatesNothing) {
  TempDir tmp;
  tools::NavCsv csv;
  std::string error;
  ASSERT_TRUE(csv.open(tmp / "nav.csv", error)) << error;
  bool all_written = true;
  // 3000 rows of about 170 bytes: several flushes of the 64 KiB buffer.
  const std::uint64_t allocs = test_support::count_allocs([&] {
    for (int i = 0; i < 3000; ++i) {
      all_written = csv.write(nav_row(0.01 * i)) && all_written;
    }
  });
  EXPECT_EQ(allocs, 0U);
  EXPECT_TRUE(all_written);
  ASSERT_TRUE(csv.close(error)) << error;
  EXPECT_EQ(lines_of(read_file(tmp / "nav.csv")).size(), 3001U);
}

TEST(NavCsv, OpenErrorsAreNamed) {
  tools::NavCsv csv;
  std::string error;
  EXPECT_FALSE(csv.open("/nonexistent-folder/nav.csv", error));
  EXPECT_NE(error.find("/nonexistent-folder/nav.csv: cannot create"), std::string::npos) << error;
  EXPECT_FALSE(csv.write(nav_row(0.0))) << "nothing is written when not open";
}

// ------------------------------------------------------------------ events.log

TEST(EventLog, WrittenSortedByTimeWithArrivalOrderForTies) {
  tools::EventLog log(16U);
  EXPECT_TRUE(log.add(20.0, tools::EventCategory::kInject, 44U, "switch_fail (planned)"));
  EXPECT_TRUE(log.add(5.0, tools::EventCategory::kInject, 1U, "packet_bit_flip word 5 bit 3"));
  EXPECT_TRUE(log.addf(5.0, tools::EventCategory::kDetect, 2U, "corrected packet from tile %u", 1U));
  EXPECT_TRUE(log.add(20.5, tools::EventCategory::kRecover, bsp::kNoTile, "routes around tile 44\nre-planned"));
  EXPECT_TRUE(log.add(0.0, tools::EventCategory::kInfo, 0U, "boot"));
  EXPECT_TRUE(log.add(20.1, tools::EventCategory::kDetect, 36U, "neighbour 44 suspect"));
  EXPECT_FALSE(log.add(std::nan(""), tools::EventCategory::kInfo, 0U, "no time"));
  EXPECT_EQ(log.size(), 6U);
  EXPECT_EQ(log.dropped(), 1U);
  EXPECT_EQ(log.count(tools::EventCategory::kInject), 2U);
  EXPECT_EQ(log.count(tools::EventCategory::kDetect), 2U);
  EXPECT_EQ(log.count(tools::EventCategory::kRecover), 1U);

  TempDir tmp;
  std::string error;
  ASSERT_TRUE(log.write(tmp / "events.log", error)) << error;
  const std::vector<std::string> lines = lines_of(read_file(tmp / "events.log"));
  ASSERT_EQ(lines.size(), 8U);  // comment, 6 events, dropped note
  EXPECT_EQ(lines[0][0], '#');
  EXPECT_EQ(lines[1], "    0.000000  INFO     tile  0  boot");
  EXPECT_EQ(lines[2], "    5.000000  INJECT   tile  1  packet_bit_flip word 5 bit 3");
  EXPECT_EQ(lines[3], "    5.000000  DETECT   tile  2  corrected packet from tile 1");
  EXPECT_EQ(lines[4], "   20.000000  INJECT   tile 44  switch_fail (planned)");
  EXPECT_EQ(lines[5], "   20.100000  DETECT   tile 36  neighbour 44 suspect");
  EXPECT_EQ(lines[6], "   20.500000  RECOVER  tile  -  routes around tile 44 re-planned");
  EXPECT_EQ(lines[7], "# 1 events dropped (log full, or a time that is not finite)");
  double last = -1.0;
  for (std::size_t i = 1; i + 1 < lines.size(); ++i) {
    const double t = std::stod(lines[i]);
    EXPECT_GE(t, last) << lines[i];
    last = t;
  }
}

TEST(EventLog, AddingAllocatesNothingAndAFullLogCounts) {
  tools::EventLog log(4U);
  bool ok = true;
  const std::uint64_t allocs = test_support::count_allocs([&] {
    for (int i = 0; i < 4; ++i) {
      ok = log.addf(4.0 - i, tools::EventCategory::kDetect, 3U, "event %d of a long run", i) && ok;
    }
  });
  EXPECT_EQ(allocs, 0U);
  EXPECT_TRUE(ok);
  EXPECT_FALSE(log.add(9.0, tools::EventCategory::kInfo, 0U, "one too many"));
  EXPECT_EQ(log.dropped(), 1U);
  const std::string long_text(500U, 'x');
  tools::EventLog small(1U);
  EXPECT_TRUE(small.add(1.0, tools::EventCategory::kInfo, 0U, long_text));
  EXPECT_EQ(std::string(small.sorted()[0].text.data()).size(), tools::kEventTextBytes - 1U) << "long texts are cut";
}

// A log the flight filled still takes the injections' lines after it: grown, nothing dropped, the
// flight's drops still counted (a run whose events flooded the log once lost its ground truth).
TEST(EventLog, AFullLogGrowsForTheLinesAddedAfterTheFlight) {
  tools::EventLog log(2U);
  EXPECT_TRUE(log.add(1.0, tools::EventCategory::kDetect, 1U, "flight"));
  EXPECT_TRUE(log.add(2.0, tools::EventCategory::kDetect, 1U, "flight"));
  EXPECT_FALSE(log.add(3.0, tools::EventCategory::kDetect, 1U, "flood"));
  log.grow(2U);
  EXPECT_TRUE(log.add(0.5, tools::EventCategory::kInject, 9U, "switch_fail (planned) -> not detected"));
  EXPECT_TRUE(log.add(0.7, tools::EventCategory::kInject, 9U, "second"));
  EXPECT_FALSE(log.add(4.0, tools::EventCategory::kInfo, 0U, "beyond the room grown"));
  EXPECT_EQ(log.size(), 4U);
  EXPECT_EQ(log.dropped(), 2U);
  EXPECT_EQ(std::string(log.sorted()[0].text.data()), "switch_fail (planned) -> not detected");
}

// ------------------------------------------------------------------ tile map and plots

std::vector<tools::TileInfo> default_tiles() {
  std::vector<tools::TileInfo> t(64U);
  t[0].role = "trn_supervisor";
  t[1].role = "vision_coordinator";
  t[2].role = "filter_supervisor";
  t[9].role = "io";
  t[18].role = "filter";
  for (std::size_t i = 24; i < 64U; ++i) {
    t[i].role = "vision";
  }
  t[44].health = "failed";
  t[44].faults_injected = 1U;
  t[24].health = "recovered";
  t[24].faults_injected = 2U;
  t[24].faults_detected = 2U;
  t[24].faults_recovered = 2U;
  t[63].role = "spare";
  t[63].health = "off";
  for (std::size_t i = 0; i < 64U; ++i) {
    t[i].power = i == 63U ? "off" : "idle";
    t[i].energy_j = 0.125 * static_cast<double>(i);
  }
  t[44].power = "active";
  return t;
}

TEST(TileMapCsv, OneLinePerTileWithRoleColourHealthEnergyAndPowerState) {
  TempDir tmp;
  std::string error;
  ASSERT_TRUE(tools::write_tile_map_csv(tmp / "tile_map.csv", 8U, 8U, default_tiles(), error)) << error;
  const std::vector<std::string> lines = lines_of(read_file(tmp / "tile_map.csv"));
  ASSERT_EQ(lines.size(), 65U);
  EXPECT_EQ(lines[0],
            "tile,x,y,role,code,health,role_rgb,health_code,faults_injected,faults_detected,faults_recovered,resets,"
            "deadline_misses,energy_j,power_state");
  EXPECT_EQ(lines[45], "44,4,5,vision,VI,failed," + std::to_string(tools::tile_role_rgb("vision")) +
                           ",2,1,0,0,0,0,5.500000,active");
  EXPECT_EQ(lines[25], "24,0,3,vision,VI,recovered," + std::to_string(tools::tile_role_rgb("vision")) +
                           ",3,2,2,2,0,0,3.000000,idle");
  EXPECT_TRUE(lines[64].ends_with(",0,0,0,0,0,7.875000,off")) << lines[64];
  const std::vector<tools::TileInfo> unknown(1U);
  ASSERT_TRUE(tools::write_tile_map_csv(tmp / "u.csv", 8U, 8U, unknown, error)) << error;
  const std::string row = lines_of(read_file(tmp / "u.csv")).at(1);
  EXPECT_TRUE(row.ends_with(",0,0,0,0,0,0.000000,-")) << "a power state not known is '-': " << row;
  EXPECT_FALSE(tools::write_tile_map_csv(tmp / "x.csv", 4U, 4U, default_tiles(), error));
  EXPECT_NE(error.find("64 tiles do not fit a 4x4 grid"), std::string::npos) << error;
}

/** Writes the data files the plots read. */
void write_plot_data(const TempDir& tmp) {
  tools::NavCsv csv;
  std::string error;
  ASSERT_TRUE(csv.open(tmp / "nav.csv", error)) << error;
  for (int i = 0; i < 200; ++i) {
    tools::NavRow r = nav_row(0.1 * i);
    r.est_p_m[0] += 3000.0 * std::exp(-0.1 * i / 4.0);
    r.sigma3_p_m = {9000.0 * std::exp(-0.1 * i / 4.0) + 10.0, 9.0, 12.0};
    ASSERT_TRUE(csv.write(r));
  }
  ASSERT_TRUE(csv.close(error)) << error;
  ASSERT_TRUE(tools::write_tile_map_csv(tmp / "tile_map.csv", 8U, 8U, default_tiles(), error)) << error;
}

bool is_png(const std::string& path) {
  const std::string s = read_file(path);
  return s.size() > 1000U && s.compare(0, 8, "\x89PNG\r\n\x1a\n") == 0;
}

TEST(Plots, GnuplotMakesBothPngs) {
  TempDir tmp;
  write_plot_data(tmp);
  std::string error;
  std::string note;
  ASSERT_TRUE(tools::write_plots(tmp.path(), error, note)) << error;
  EXPECT_TRUE(fs::exists(tmp / "position_error.gp"));
  EXPECT_TRUE(fs::exists(tmp / "tile_map.gp"));
  // `make deps` installs gnuplot; the no-gnuplot case has its own test.
  ASSERT_EQ(note.find("gnuplot is not installed"), std::string::npos) << note << " (make deps installs it)";
  EXPECT_TRUE(note.empty()) << note << "\n" << read_file(tmp / "plots.log");
  EXPECT_TRUE(is_png(tmp / "position_error.png"));
  EXPECT_TRUE(is_png(tmp / "tile_map.png"));
  EXPECT_NE(read_file(tmp / "tile_map.gp").find("title 'vision'"), std::string::npos) << "legend of the roles present";
  for (const char* power : {"power: active", "power: idle", "power: booting", "power: off"}) {
    EXPECT_NE(read_file(tmp / "tile_map.gp").find(power), std::string::npos) << "legend of the power marks: " << power;
  }
  EXPECT_NE(read_file(tmp / "tile_map.gp").find("column('energy_j')"), std::string::npos) << "energy in the labels";
}

/** Sets PATH for one scope. */
class PathOverride {
 public:
  explicit PathOverride(const std::string& path) : old_(std::getenv("PATH") != nullptr ? std::getenv("PATH") : "") {
    ::setenv("PATH", path.c_str(), 1);
  }
  PathOverride(const PathOverride&) = delete;
  PathOverride& operator=(const PathOverride&) = delete;
  PathOverride(PathOverride&&) = delete;
  PathOverride& operator=(PathOverride&&) = delete;
  ~PathOverride() { ::setenv("PATH", old_.c_str(), 1); }

 private:
  std::string old_;
};

TEST(Plots, WithoutGnuplotTheScriptsStayAndANoteSaysSo) {
  TempDir tmp;
  write_plot_data(tmp);
  fs::create_directory(tmp / "empty_bin");
  std::string error;
  std::string note;
  bool ok = false;
  {
    const PathOverride path(tmp / "empty_bin");
    ok = tools::write_plots(tmp.path(), error, note);
  }
  ASSERT_TRUE(ok) << error;
  EXPECT_NE(note.find("gnuplot is not installed"), std::string::npos) << note;
  EXPECT_TRUE(fs::exists(tmp / "position_error.gp"));
  EXPECT_TRUE(fs::exists(tmp / "tile_map.gp"));
  EXPECT_FALSE(fs::exists(tmp / "position_error.png"));
}

TEST(Plots, AGnuplotThatFailsIsANoteNotAHang) {
  TempDir tmp;
  write_plot_data(tmp);
  fs::create_directory(tmp / "bin");
  // A stand-in gnuplot that fails at once; the data files stay valid.
  write_file(tmp / "bin/gnuplot", "#!/bin/sh\necho broken >&2\nexit 3\n");
  fs::permissions(tmp / "bin/gnuplot", fs::perms::owner_all);
  std::string error;
  std::string note;
  bool ok = false;
  {
    const PathOverride path(tmp / "bin");
    ok = tools::write_plots(tmp.path(), error, note);
  }
  ASSERT_TRUE(ok) << error;
  EXPECT_NE(note.find("gnuplot position_error.gp failed (exit status 3; see plots.log)"), std::string::npos) << note;
  EXPECT_NE(read_file(tmp / "plots.log").find("broken"), std::string::npos);
}

TEST(Plots, MissingDataIsAnError) {
  TempDir tmp;
  std::string error;
  std::string note;
  EXPECT_FALSE(tools::write_plots(tmp.path(), error, note));
  EXPECT_NE(error.find("nav.csv: missing (write it before the plots)"), std::string::npos) << error;
}

}  // namespace
