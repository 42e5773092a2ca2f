/**
 * @file trn_campaign_test.cpp
 * @brief trn_campaign as a user runs it: a small campaign in parallel, resumed without flying again,
 *        sharded and merged to the same report, each run replayed bit for bit, a crashed or hung image
 *        an outcome, bad specs refused, and the Slurm array script (docs/CAMPAIGNS.md).
 */
#include "tools/common/mission/image_id.hpp"
#include "build_dirs.hpp"
#include "build_info.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <sys/wait.h>
#include <unistd.h>

namespace {

namespace fs = std::filesystem;

std::string bin(const char* name) { return std::string(build_info::kBinDir) + "/" + name; }
std::string fixture(const char* name) { return std::string(build_info::kRepoRoot) + "/tests/fixtures/campaigns/" + name; }
/** The tests' world cache, shared with the mission tests: a world built once serves every run. */
std::string world() { return std::string(build_info::kBinDir) + "/test-world-cache"; }

/** Runs a command; its exit status (-1 if it did not exit); its output into @p out when given. */
int run(const std::string& cmd, std::string* out = nullptr) {
  const std::string log = fs::temp_directory_path() / ("trn_campaign_test_" + std::to_string(::getpid()) + ".log");
  const int status = std::system((cmd + " >" + log + " 2>&1").c_str());
  if (out != nullptr) {
    std::ifstream in(log);
    std::ostringstream s;
    s << in.rdbuf();
    *out = s.str();
  }
  std::remove(log.c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

nlohmann::json read_json(const fs::path& p) {
  std::ifstream in(p);
  return nlohmann::json::parse(in);
}

class TrnCampaignBinary : public ::testing::Test {
 protected:
  void SetUp() override {
    ASSERT_TRUE(fs::exists(bin("trn_campaign")) && fs::exists(bin("trn_mission")))
        << "trn_campaign or trn_mission is not built (make test builds them)";
    dir_ = fs::temp_directory_path() / ("trn_campaign_test_" + std::to_string(::getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override {
    std::error_code ec;
    fs::remove_all(dir_, ec);
  }
  void shards_merge_into_the_report_of(const fs::path& out) const;
  std::string campaign(const std::string& args) const {
    return bin("trn_campaign") + " run " + fixture("small.toml") + " --world-cache " + world() + " " + args;
  }

  fs::path dir_;
};

/** The class counts over all runs, as the report gives them. */
nlohmann::json classes_of(const fs::path& report) {
  const nlohmann::json r = read_json(report);
  nlohmann::json c = nlohmann::json::object();
  for (const auto& [name, v] : r["classes"].items()) {
    c[name] = v["count"];
  }
  return c;
}

// CMP-04: shards fly disjoint runs; merged, they give the report the whole campaign @p out gave.
// (Called by the parallel test, so the whole campaign is flown once for both.)
void TrnCampaignBinary::shards_merge_into_the_report_of(const fs::path& out) const {
  std::string log;
  ASSERT_EQ(run(campaign("-j 1 --shard 0/2 --out " + (dir_ / "s0").string())), 0);
  ASSERT_EQ(run(campaign("-j 1 --shard 1/2 --out " + (dir_ / "s1").string())), 0);
  EXPECT_TRUE(fs::exists(dir_ / "s0" / "runs" / "000000"));
  EXPECT_FALSE(fs::exists(dir_ / "s0" / "runs" / "000001")) << "shard 0 of 2 flies the even runs";
  ASSERT_EQ(run(bin("trn_campaign") + " merge --out " + (dir_ / "m").string() + " " + (dir_ / "s0").string() + " " +
                    (dir_ / "s1").string(), &log),
            0)
      << log;
  EXPECT_EQ(read_json(dir_ / "m" / "report.json")["runs"], 4);
  EXPECT_EQ(classes_of(dir_ / "m" / "report.json"), classes_of(out / "report.json"));
  for (int i = 0; i < 4; ++i) {
    char name[8];
    std::snprintf(name, sizeof name, "%06d", i);
    const fs::path shard = dir_ / (i % 2 == 0 ? "s0" : "s1") / "runs" / name / "result.json";
    EXPECT_EQ(read_json(shard)["trace_hash"], read_json(out / "runs" / name / "result.json")["trace_hash"])
        << "run " << i << ": the same plan and the same flight in either";
  }
  // Folders of another campaign are not merged.
  ASSERT_EQ(run(bin("trn_campaign") + " run " + fixture("crash.toml") + " --world-cache " + world() +
                " --mission /bin/false --out " + (dir_ / "other").string()),
            1)
      << "the golden run of /bin/false is no flight";
  EXPECT_EQ(run(bin("trn_campaign") + " merge --out " + (dir_ / "m2").string() + " " + (dir_ / "s0").string() + " " +
                    (dir_ / "other").string(), &log),
            2);
  EXPECT_NE(log.find("holds another campaign"), std::string::npos) << log;
  // Shards of the same spec flown by two builds of the image are not merged either.
  fs::copy(dir_ / "s1", dir_ / "s1b", fs::copy_options::recursive);
  {
    std::ofstream(dir_ / "s1b" / "image.stamp") << "1@2\n";
  }
  EXPECT_EQ(run(bin("trn_campaign") + " merge --out " + (dir_ / "m3").string() + " " + (dir_ / "s0").string() + " " +
                    (dir_ / "s1b").string(), &log),
            2);
  EXPECT_NE(log.find("another build of the mission image"), std::string::npos) << log;
}

// CMP-01, CMP-02, CMP-03, CMP-04: a campaign flies its runs in parallel, writes each run's plan and result and
// the report; run again, it flies nothing; a run's plan flies again to the trace hash it recorded; its
// shards, flown apart and merged, give the same report.
TEST_F(TrnCampaignBinary, RunsInParallelResumesReplaysARunAndMergesItsShards) {
  const fs::path out = dir_ / "c";
  std::string log;
  ASSERT_EQ(run(campaign("-j 2 --out " + out.string()), &log), 0) << log;
  const nlohmann::json rep = read_json(out / "report.json");
  EXPECT_EQ(rep["runs"], 4) << rep.dump(2);
  EXPECT_NE(log.find("| outcome |"), std::string::npos) << "the Markdown table on stdout\n" << log;
  for (const char* f : {"report.csv", "report.md", "coverage.csv", "runs.csv", "campaign.toml", "golden/result.json"}) {
    EXPECT_TRUE(fs::exists(out / f)) << f;
  }
  EXPECT_TRUE(rep.contains("coverage") && rep.contains("flags") && rep.contains("roles")) << rep.dump(2);
  // Every run's record carries its target, its counts, its flags and its stream against the golden run's.
  const nlohmann::json golden = read_json(out / "golden" / "result.json");
  EXPECT_EQ(golden["outcome"], "masked") << "the golden run is judged against no stream";
  ASSERT_TRUE(golden["filter_output_crc"].is_number()) << golden.dump(2);
  for (const char* name : {"000000", "000001", "000002", "000003"}) {
    const nlohmann::json r = read_json(out / "runs" / name / "result.json");
    const nlohmann::json sum = read_json(out / "runs" / name / "out" / "summary.json");
    EXPECT_EQ(r["result_format"], 2) << name;
    const std::string role = r["role"].get<std::string>();
    EXPECT_TRUE(role == "filter" || role == "vision_coordinator" || role == "vision" || role == "io") << role;
    for (const char* key : {"not_delivered", "degraded_accepted", "misdiagnosed", "false_alarms",
                            "healthy_tiles_disturbed"}) {
      EXPECT_TRUE(r[key].is_number_unsigned()) << name << " " << key << "\n" << r.dump(2);
    }
    EXPECT_EQ(r["not_delivered"].get<double>(), sum["faults_not_delivered"].get<double>()) << name;
    EXPECT_EQ(r["filter_output_crc"].get<double>(), sum["filter_output_crc"].get<double>()) << name;
    EXPECT_EQ(r["output_as_golden"], r["filter_output_crc"] == golden["filter_output_crc"]) << name;
    const bool reached = r["injected"] != 0 || r["not_delivered"] == 0;
    EXPECT_EQ(r["outcome"] == "no_effect", reached && r["output_as_golden"] == true && r["detected"] == 0)
        << r.dump(2);
    EXPECT_EQ(r["outcome"] == "not_delivered", !reached) << r.dump(2);
  }
  const fs::path r2 = out / "runs" / "000002";
  const nlohmann::json res = read_json(r2 / "result.json");
  const auto written = fs::last_write_time(r2 / "result.json");
  const nlohmann::json classes_before = classes_of(out / "report.json");
  fs::remove(out / "report.json");  // the resume writes the report again from the runs it finds
  ASSERT_EQ(run(campaign("-j 2 --out " + out.string()), &log), 0) << log;
  EXPECT_NE(log.find("4 runs, 4 done before"), std::string::npos) << log;
  EXPECT_EQ(fs::last_write_time(r2 / "result.json"), written) << "a finished run is not flown again";
  EXPECT_EQ(classes_of(out / "report.json"), classes_before) << "the resumed report counts the same runs";
  int counted = 0;
  for (const auto& [name, n] : classes_before.items()) {
    counted += n.get<int>();
  }
  EXPECT_EQ(counted, 4) << classes_before.dump();
  // The replay, as the plan's header says.
  ASSERT_EQ(run(bin("trn_mission") + " --quiet --no-plots --world-cache " + world() + " --seed 1 --duration 5 --faults " +
                (r2 / "plan.toml").string() + " --out " + (dir_ / "replay").string()),
            0);
  EXPECT_EQ(read_json(dir_ / "replay" / "summary.json")["trace_hash"], res["trace_hash"]);
  EXPECT_EQ(read_json(r2 / "out" / "summary.json")["trace_hash"], res["trace_hash"]);
  shards_merge_into_the_report_of(out);
}

// A fault-free seed sweep: run i flies seed + i (its summary says so), and each run's navigation integrity
// is carried from its summary into its result, integrity.csv and the report.
TEST_F(TrnCampaignBinary, ASeedSweepFliesOneSeedPerRunAndReportsItsIntegrity) {
  const fs::path out = dir_ / "sweep";
  std::string log;
  ASSERT_EQ(run(bin("trn_campaign") + " run " + fixture("sweep.toml") + " --world-cache " + world() + " -j 2 --out " +
                    out.string(),
                &log),
            0)
      << log;
  std::vector<std::string> hashes;
  for (int i = 0; i < 2; ++i) {
    const fs::path r = out / "runs" / (i == 0 ? "000000" : "000001");
    const nlohmann::json res = read_json(r / "result.json");
    const nlohmann::json sum = read_json(r / "out" / "summary.json");
    EXPECT_EQ(res["seed"], 2 + i);
    EXPECT_EQ(sum["seed"], 2 + i) << "the image flew the run's own seed";
    EXPECT_EQ(res["kind"], "none");
    EXPECT_EQ(res["role"], "none");
    EXPECT_EQ(res["injected"], 0);
    // Run 0 flies the golden run's seed without faults: bit for bit its stream. Run 1 flies another seed, so
    // its stream is not compared: a correct fault-free run of its own world is masked.
    EXPECT_EQ(res["output_as_golden"], i == 0) << res.dump(2);
    EXPECT_EQ(res["outcome"], i == 0 ? "no_effect" : "masked") << res.dump(2);
    std::ifstream plan(r / "plan.toml");
    std::ostringstream text;
    text << plan.rdbuf();
    EXPECT_NE(text.str().find("--seed " + std::to_string(2 + i)), std::string::npos) << text.str();
    ASSERT_TRUE(res.contains("integrity")) << res.dump(2);
    const nlohmann::json& in = res["integrity"];
    EXPECT_EQ(in["outputs"].get<double>(), sum["integrity_outputs"].get<double>());
    EXPECT_GT(in["outputs"].get<double>(), 0.0) << "the filter converges within 5 s";
    EXPECT_EQ(in["fix_at_s"].get<double>(), sum["fix_at_s"].get<double>());
    EXPECT_EQ(in["converged_at_s"].get<double>(), sum["converged_at_s"].get<double>());
    for (const char* axis : {"x", "y", "z"}) {
      const double f = sum[std::string("integrity_beyond_3sigma_fraction_") + axis].get<double>();
      EXPECT_EQ(in[axis]["beyond_3sigma"].get<double>(), std::round(f * in["outputs"].get<double>())) << axis;
      EXPECT_EQ(in[axis]["beyond_5sigma"].get<double>(), sum[std::string("integrity_beyond_5sigma_") + axis].get<double>());
    }
    hashes.push_back(res["trace_hash"].get<std::string>());
  }
  EXPECT_NE(hashes[0], hashes[1]) << "two seeds, two flights";
  EXPECT_EQ(read_json(out / "golden" / "result.json")["trace_hash"], hashes[0]) << "the golden run flies seed 2 too";
  const nlohmann::json rep = read_json(out / "report.json");
  EXPECT_EQ(rep["integrity"]["runs"], 2) << rep.dump(2);
  std::ifstream csv(out / "integrity.csv");
  std::string line;
  int lines = 0;
  while (std::getline(csv, line)) {
    ++lines;
  }
  EXPECT_EQ(lines, 3) << "the header and one row per run";
}

/** Changes the build ID in @p image's note (the program runs the same): another build, as a rebuild makes. */
void rebuild(const fs::path& image) {
  const std::string id = tools::image_identity(image.string());
  ASSERT_EQ(id.rfind("gnu-", 0), 0U) << id;
  std::string want;
  for (std::size_t i = 4; i + 1 < id.size(); i += 2) {
    want.push_back(static_cast<char>(std::stoi(id.substr(i, 2), nullptr, 16)));
  }
  std::fstream f(image, std::ios::in | std::ios::out | std::ios::binary);
  const std::string bytes((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
  const std::size_t at = bytes.find(want);
  ASSERT_NE(at, std::string::npos) << "the build ID's bytes are in the file";
  f.seekp(static_cast<std::streamoff>(at));
  f.put(static_cast<char>(bytes[at] ^ 0x5A));
  f.close();
  ASSERT_NE(tools::image_identity(image.string()), id);
}

// A campaign folder remembers the build of the image that flew its runs: resumed with a rebuilt image it
// is refused (its report would mix two builds' runs), and so is a folder of runs with no record of it.
TEST_F(TrnCampaignBinary, AFolderFlownByAnotherBuildOfTheImageIsNotResumed) {
  const fs::path image = dir_ / "trn_mission";
  fs::copy_file(bin("trn_mission"), image);
  fs::permissions(image, fs::perms::owner_exec, fs::perm_options::add);
  // A copy is the same build (its build ID): it reads the worlds the tests' cache holds for it.
  ASSERT_EQ(tools::image_identity(image.string()), tools::image_identity(bin("trn_mission")));
  {
    std::ofstream spec(dir_ / "one.toml");
    spec << "name = \"one\"\nfaults_per_run = 0\nruns = 1\nduration_s = 2\npass_bound_m = 5000.0\n"
            "degraded_bound_m = 5000.0\n";
  }
  const fs::path out = dir_ / "one";
  const std::string cmd = bin("trn_campaign") + " run " + (dir_ / "one.toml").string() + " --quiet --mission " +
                          image.string() + " --world-cache " + world() + " --out " + out.string();
  std::string log;
  ASSERT_EQ(run(cmd, &log), 0) << log;
  ASSERT_TRUE(fs::exists(out / "image.stamp"));
  ASSERT_EQ(run(cmd, &log), 0) << "the same build resumes\n" << log;
  fs::last_write_time(image, fs::last_write_time(image) + std::chrono::seconds(5));
  ASSERT_EQ(run(cmd, &log), 0) << "touched, it is the same build\n" << log;
  rebuild(image);  // another build ID: what a rebuild with other code gives
  EXPECT_EQ(run(cmd, &log), 2);
  EXPECT_NE(log.find("another build of the mission image"), std::string::npos) << log;
  fs::remove(out / "image.stamp");
  EXPECT_EQ(run(cmd, &log), 2);
  EXPECT_NE(log.find("did not record"), std::string::npos) << log;
}

// CMP-09: a campaign folder whose results an older trn_campaign wrote (no result_format: classes judged
// without not_delivered and no_effect, no flags) is neither resumed nor merged: the file is named, nothing
// is flown and no report is written from it. A result that is not JSON at all (torn) is flown again.
TEST_F(TrnCampaignBinary, ResultsOfAnOlderCampaignAreRefusedByName) {
  {
    std::ofstream spec(dir_ / "one.toml");
    spec << "name = \"one\"\nfaults_per_run = 0\nruns = 2\nduration_s = 2\npass_bound_m = 5000.0\n"
            "degraded_bound_m = 5000.0\n";
  }
  const fs::path out = dir_ / "one";
  const std::string cmd = bin("trn_campaign") + " run " + (dir_ / "one.toml").string() + " --quiet --world-cache " +
                          world() + " --out " + out.string();
  std::string log;
  ASSERT_EQ(run(cmd, &log), 0) << log;
  const fs::path r1 = out / "runs" / "000001" / "result.json";
  nlohmann::json old = read_json(r1);
  for (const char* key : {"result_format", "role", "not_delivered", "degraded_accepted", "misdiagnosed", "false_alarms",
                          "healthy_tiles_disturbed", "filter_output_crc", "output_as_golden"}) {
    old.erase(key);
  }
  {
    std::ofstream(r1) << old.dump(2);
  }
  const auto written = fs::last_write_time(r1);
  fs::remove(out / "report.json");
  EXPECT_EQ(run(cmd, &log), 2);
  EXPECT_NE(log.find(r1.string() + ": a result of an older trn_campaign"), std::string::npos) << log;
  EXPECT_EQ(fs::last_write_time(r1), written) << "the run is not flown again";
  EXPECT_FALSE(fs::exists(out / "report.json"));
  EXPECT_EQ(run(bin("trn_campaign") + " merge --out " + (dir_ / "m").string() + " " + out.string(), &log), 2);
  EXPECT_NE(log.find(r1.string() + ": a result of an older trn_campaign"), std::string::npos) << log;
  // The golden run's result too: without its stream's CRC no run could be compared with it.
  {
    std::ofstream(r1) << "{\"torn";
  }
  nlohmann::json golden = read_json(out / "golden" / "result.json");
  golden.erase("result_format");
  {
    std::ofstream(out / "golden" / "result.json") << golden.dump(2);
  }
  EXPECT_EQ(run(cmd, &log), 2);
  EXPECT_NE(log.find((out / "golden" / "result.json").string() + ": a result of an older trn_campaign"),
            std::string::npos)
      << log;
  fs::remove(out / "golden" / "result.json");
  ASSERT_EQ(run(cmd, &log), 0) << "the golden run and the torn run are flown again\n" << log;
  EXPECT_EQ(read_json(r1)["result_format"], 2);
  EXPECT_EQ(read_json(out / "report.json")["runs"], 2);
}


// CMP-05: an image that crashes or hangs is the run's outcome (hang_crash), not the campaign's end. The
// fake image crashes run 0 and hangs run 1 until the spec's 2 s timeout kills it; for the golden run and
// run 2 it hands back, at once, the run folder of a real flight of the image flown before the campaign,
// so no real flight has to race the timeout (a loaded machine or a sanitizer build cannot make it flake).
TEST_F(TrnCampaignBinary, ACrashedOrHungImageIsTheRunsOutcome) {
  const fs::path flown = dir_ / "flown";
  ASSERT_EQ(run(bin("trn_mission") + " --quiet --no-plots --seed 1 --duration 5 --world-cache " + world() + " --out " +
                flown.string()),
            0);
  const fs::path fake = dir_ / "fake_mission.sh";
  {
    std::ofstream f(fake);
    f << "#!/bin/bash\nout=; prev=\nfor a in \"$@\"; do [ \"$prev\" = --out ] && out=$a; prev=$a; done\n"
         "case \"$*\" in\n  *000000/plan.toml*) kill -SEGV $$ ;;\n  *000001/plan.toml*) exec sleep 600 ;;\n"
         "  *) mkdir -p \"$out\" && exec cp -r " << flown.string() << "/. \"$out\"/ ;;\nesac\n";
  }
  fs::permissions(fake, fs::perms::owner_all);
  std::string log;
  ASSERT_EQ(run(bin("trn_campaign") + " run " + fixture("crash.toml") + " --world-cache " + world() + " --mission " +
                    fake.string() + " -j 3 --out " + (dir_ / "c").string(), &log),
            0)
      << log;
  const nlohmann::json r0 = read_json(dir_ / "c" / "runs" / "000000" / "result.json");
  const nlohmann::json r1 = read_json(dir_ / "c" / "runs" / "000001" / "result.json");
  const nlohmann::json r2 = read_json(dir_ / "c" / "runs" / "000002" / "result.json");
  EXPECT_EQ(r0["outcome"], "hang_crash");
  EXPECT_EQ(r0["signal"], 11);
  EXPECT_EQ(r1["outcome"], "hang_crash");
  EXPECT_EQ(r1["timed_out"], true);
  EXPECT_EQ(r2["outcome"], "no_effect") << "the fake hands back the golden run's own flight";
  EXPECT_EQ(r2["timed_out"], false);
  EXPECT_EQ(r0["filter_output_crc"], nullptr) << "no summary, no stream";
  EXPECT_EQ(read_json(dir_ / "c" / "report.json")["classes"]["hang_crash"]["count"], 2);
}

// CMP-08: shrink finds the one guilty fault among six: a plan whose fault at 3.25 s crashes the (fake)
// image reduces to that fault alone, written beside the plan; a run that did not fail is refused.
TEST_F(TrnCampaignBinary, ShrinkFindsTheOneGuiltyFaultAmongMany) {
  const fs::path c = dir_ / "c";
  const fs::path r = c / "runs" / "000000";
  fs::create_directories(r);
  fs::copy_file(fixture("small.toml"), c / "campaign.toml");
  {
    std::ofstream plan(r / "plan.toml");
    plan << "name = \"guilty\"\n";
    for (const double t : {2.1, 2.3, 2.5, 2.7, 3.25, 3.9}) {
      plan << "\n[[fault]]\nt_s = " << t << "\nkind = \"packet_bit_flip\"\ntile = 24\nword = 5\nbit = 3\n";
    }
    std::ofstream res(r / "result.json");
    res << R"({"result_format": 2, "index": 0, "kind": "packet_bit_flip", "role": "io", "outcome": "hang_crash",
               "final_error_m": 0, "max_error_m": 0, "host_s": 0, "injected": 0, "not_delivered": 0, "detected": 0,
               "recovered": 0, "degraded_accepted": 0, "misdiagnosed": 0, "false_alarms": 0,
               "healthy_tiles_disturbed": 0, "filter_output_crc": null, "output_as_golden": false})";
  }
  const fs::path fake = dir_ / "fake_mission.sh";
  {
    std::ofstream f(fake);
    f << "#!/bin/bash\nplan=\nfor a in \"$@\"; do case \"$a\" in *plan.toml) plan=$a ;; esac; done\n"
         "if [ -n \"$plan\" ] && grep -q '3.25' \"$plan\"; then kill -SEGV $$; fi\nexec "
      << bin("trn_mission") << " \"$@\"\n";
  }
  fs::permissions(fake, fs::perms::owner_all);
  std::string log;
  ASSERT_EQ(run(bin("trn_campaign") + " shrink " + r.string() + " --world-cache " + world() + " --mission " +
                    fake.string(), &log),
            0)
      << log;
  EXPECT_NE(log.find("1 of 6 faults still end hang_crash"), std::string::npos) << log;
  std::ifstream in(r / "plan.min.toml");
  std::ostringstream t;
  t << in.rdbuf();
  EXPECT_NE(t.str().find("t_s = 3.25"), std::string::npos) << t.str();
  EXPECT_EQ(t.str().find("t_s = 2.1"), std::string::npos) << t.str();
  // The shrunk plan is a plan the image takes.
  EXPECT_EQ(run(bin("trn_mission") + " --quiet --no-plots --world-cache " + world() + " --duration 5 --faults " +
                (r / "plan.min.toml").string() + " --out " + (dir_ / "min").string()),
            0);
  // A run that ended well has nothing to shrink.
  {
    std::ofstream res(r / "result.json");
    res << R"({"result_format": 2, "index": 0, "kind": "x", "role": "io", "outcome": "masked", "final_error_m": 0,
               "max_error_m": 0, "host_s": 0, "injected": 1, "not_delivered": 0, "detected": 0, "recovered": 0,
               "degraded_accepted": 0, "misdiagnosed": 0, "false_alarms": 0, "healthy_tiles_disturbed": 0,
               "filter_output_crc": 7, "output_as_golden": false})";
  }
  EXPECT_EQ(run(bin("trn_campaign") + " shrink " + r.string(), &log), 2);
  EXPECT_NE(log.find("nothing failed to shrink"), std::string::npos) << log;
  // Nor does a result an older trn_campaign wrote: its class is not read as one of today's.
  {
    std::ofstream res(r / "result.json");
    res << R"({"index": 0, "kind": "x", "outcome": "sdc", "final_error_m": 0, "max_error_m": 0, "host_s": 0,
               "injected": 1, "detected": 0, "recovered": 0})";
  }
  EXPECT_EQ(run(bin("trn_campaign") + " shrink " + r.string(), &log), 2);
  EXPECT_NE(log.find((r / "result.json").string() + ": a result of an older trn_campaign"), std::string::npos) << log;
}

TEST_F(TrnCampaignBinary, BadInputIsRefusedWithExitStatusTwo) {
  const fs::path spec = dir_ / "bad.toml";
  {
    std::ofstream f(spec);
    f << "name = \"bad\"\nruns = 2\nkinds = [\"core_hang\"]\nroles = [\"filter\"]\nwindow_s = [1.0, 2.0]\ncolour = 3\n";
  }
  std::string log;
  EXPECT_EQ(run(bin("trn_campaign") + " run " + spec.string() + " --out " + (dir_ / "b").string(), &log), 2);
  EXPECT_NE(log.find("bad.toml: unknown key colour"), std::string::npos) << log;
  EXPECT_FALSE(fs::exists(dir_ / "b")) << "nothing written for a spec that is refused";
  EXPECT_EQ(run(campaign("--shard 2/2 --out " + (dir_ / "s").string()), &log), 2);
  EXPECT_NE(log.find("--shard 2/2: expected i/N"), std::string::npos) << log;
  EXPECT_EQ(run(bin("trn_campaign") + " run " + (dir_ / "none.toml").string(), &log), 2);
  EXPECT_NE(log.find("cannot read the campaign spec"), std::string::npos) << log;
}

// The runs a margin needs, as Leveugle et al. (DATE 2009) give them: 9604 for 1 % at 95 %.
TEST_F(TrnCampaignBinary, TheRunsForAMarginArePrinted) {
  std::string log;
  ASSERT_EQ(run(bin("trn_campaign") + " margin --margin 0.01", &log), 0) << log;
  EXPECT_NE(log.find("9604 runs for a margin of 1 % at 95 % confidence"), std::string::npos) << log;
  EXPECT_EQ(run(bin("trn_campaign") + " margin --margin 0.9", &log), 2) << "a margin above one half is refused";
}

// CMP-06: the Slurm array script flies shard i of N in array task i, all sharing one world cache.
TEST_F(TrnCampaignBinary, TheSlurmScriptIsAnArrayOfShards) {
  std::string log;
  ASSERT_EQ(run(bin("trn_campaign") + " sbatch " + fixture("small.toml") + " --tasks 3 --out " + (dir_ / "s").string(),
                &log),
            0)
      << log;
  std::ifstream in(dir_ / "s" / "campaign.sbatch");
  std::ostringstream t;
  t << in.rdbuf();
  const std::string s = t.str();
  for (const char* want : {"#SBATCH --array=0-2", "--shard \"${SLURM_ARRAY_TASK_ID}/3\"", "/shard-${SLURM_ARRAY_TASK_ID}",
                           "--world-cache ", "#SBATCH --output=", " merge --out "}) {
    EXPECT_NE(s.find(want), std::string::npos) << want << "\n" << s;
  }
}

}  // namespace
