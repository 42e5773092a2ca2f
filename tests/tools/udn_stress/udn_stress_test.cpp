/**
 * @file udn_stress_test.cpp
 * @brief udn_stress: argument parsing and exit status, the JSON report's keys, complete and
 *        deterministic runs, failed switches; the built binary when it is present.
 */
#include "tools/common/udn_stress.hpp"

#include "build_info.hpp"

#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <sstream>
#include <string>
#include <vector>

namespace {

int parse(std::vector<const char*> args, tools::StressOptions& opts, std::string& message) {
  args.insert(args.begin(), "udn_stress");
  return tools::parse_stress_args(static_cast<int>(args.size()), args.data(), opts, message);
}

TEST(UdnStressArgs, DefaultsAndEveryOption) {
  tools::StressOptions o;
  std::string msg;
  ASSERT_EQ(parse({}, o, msg), -1) << msg;
  EXPECT_EQ(o.pattern, tools::TrafficPattern::kUniform);
  EXPECT_EQ(o.profile, "tile64");
  ASSERT_EQ(parse({"--pattern", "hotspot", "--rate", "0.5", "--packets", "99", "--words", "12", "--seed", "7",
                   "--failed-switches", "3,9,48", "--profile", "maestro", "--quantum-us", "10"},
                  o, msg),
            -1)
      << msg;
  EXPECT_EQ(o.pattern, tools::TrafficPattern::kHotspot);
  EXPECT_DOUBLE_EQ(o.rate_per_us, 0.5);
  EXPECT_EQ(o.packets, 99U);
  EXPECT_EQ(o.words, 12U);
  EXPECT_EQ(o.seed, 7U);
  EXPECT_EQ(o.failed_switches, (std::vector<std::uint32_t>{3U, 9U, 48U}));
  EXPECT_EQ(o.profile, "maestro");
  EXPECT_DOUBLE_EQ(o.quantum_us, 10.0);
}

TEST(UdnStressArgs, BadArgumentsGiveStatus2AndAMessage) {
  const std::vector<std::vector<const char*>> bad{
      {"--pattern", "diagonal"}, {"--rate", "0"},          {"--rate", "abc"},
      {"--packets", "0"},        {"--words", "0"},         {"--words", "129"},
      {"--profile", "tile128"},  {"--failed-switches", "3,x"}, {"--failed-switches", "64"},
      {"--no-such-option"},      {"--profile", "maestro", "--failed-switches", "49"},
      {"--quantum-us", "0.5"},   {"--quantum-us", "2000"},
  };
  for (const auto& args : bad) {
    tools::StressOptions o;
    std::string msg;
    EXPECT_EQ(parse(args, o, msg), 2) << args[0];
    EXPECT_FALSE(msg.empty()) << args[0];
  }
  tools::StressOptions o;
  std::string msg;
  EXPECT_EQ(parse({"--help"}, o, msg), 0);
  EXPECT_NE(msg.find("--failed-switches"), std::string::npos);
}

const char* const kKeys[] = {"\"sent\":",
                             "\"delivered\":",
                             "\"lost_offgrid\":",
                             "\"lost_failed_switch\":",
                             "\"latency_cycles_min\":",
                             "\"latency_cycles_mean\":",
                             "\"latency_cycles_max\":",
                             "\"emulated_s\":",
                             "\"host_s\":"};

void expect_keys(const std::string& json) {
  ASSERT_FALSE(json.empty());
  EXPECT_EQ(json.front(), '{');
  EXPECT_EQ(json.substr(json.size() - 2U), "}\n");
  for (const char* k : kKeys) {
    EXPECT_NE(json.find(k), std::string::npos) << k << " in " << json;
  }
}

tools::StressResult small_run(std::uint64_t seed, std::vector<std::uint32_t> failed = {}) {
  tools::StressOptions o;
  o.packets = 1280U;
  o.rate_per_us = 0.2;
  o.seed = seed;
  o.failed_switches = std::move(failed);
  return tools::run_stress(o, bsp::heap::SealMode::kCount);
}

TEST(UdnStressRun, EveryPacketIsDeliveredAndReadWithoutHeapUse) {
  const tools::StressResult r = small_run(5U);
  EXPECT_TRUE(r.completed);
  EXPECT_EQ(r.net.sent, 1280U);
  EXPECT_EQ(r.net.delivered, 1280U);
  EXPECT_EQ(r.received, 1280U);
  EXPECT_EQ(r.send_errors, 0U);
  EXPECT_EQ(r.heap_allocs_during_run, 0U);
  EXPECT_GT(r.net.latency_min, 0U);
  EXPECT_GE(r.net.latency_max, r.net.latency_min);
  std::ostringstream out;
  tools::write_stress_json(out, tools::StressOptions{}, r);
  expect_keys(out.str());
}

TEST(UdnStressRun, SameSeedSameStatisticsOtherSeedDiffers) {
  const tools::StressResult a = small_run(11U);
  const tools::StressResult b = small_run(11U);
  const tools::StressResult c = small_run(12U);
  EXPECT_EQ(a.net.latency_sum, b.net.latency_sum);
  EXPECT_EQ(a.net.latency_max, b.net.latency_max);
  EXPECT_DOUBLE_EQ(a.emulated_s, b.emulated_s);
  EXPECT_DOUBLE_EQ(a.link_utilisation_max, b.link_utilisation_max);
  EXPECT_NE(a.net.latency_sum, c.net.latency_sum);
}

TEST(UdnStressRun, TheQuantumChangesWhenSoftwareSeesPacketsNotTheirModelledLatency) {
  tools::StressOptions o;
  o.packets = 640U;
  o.rate_per_us = 0.05;
  const tools::StressResult fine = tools::run_stress(o, bsp::heap::SealMode::kCount);
  o.quantum_us = 50.0;
  const tools::StressResult coarse = tools::run_stress(o, bsp::heap::SealMode::kCount);
  ASSERT_TRUE(fine.completed);
  ASSERT_TRUE(coarse.completed);
  EXPECT_EQ(fine.net.latency_sum, coarse.net.latency_sum);
  EXPECT_EQ(fine.net.delivered, coarse.net.delivered);
}

TEST(UdnStressRun, FailedSwitchesLoseTheirPacketsAndTheRestArrives) {
  const tools::StressResult r = small_run(5U, {0U, 27U});
  EXPECT_TRUE(r.completed);
  const std::uint64_t lost = r.net.lost[static_cast<std::size_t>(bsp::UdnLoss::kFailedSwitch)];
  // Tiles 0 and 27 lose all they send (40 packets) at least, and the others lose some.
  EXPECT_GT(lost, 40U);
  EXPECT_EQ(r.net.delivered + lost, 1280U);
  EXPECT_EQ(r.received, r.net.delivered);
}

/** Runs a command, returns (exit status, stdout). */
std::pair<int, std::string> run_command(const std::string& cmd) {
  std::string out;
  FILE* p = popen((cmd + " 2>/dev/null").c_str(), "r");
  if (p == nullptr) {
    return {-1, out};
  }
  char buf[4096];
  for (std::size_t n = 0; (n = std::fread(buf, 1, sizeof buf, p)) > 0;) {
    out.append(buf, n);
  }
  const int status = pclose(p);
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, out};
}

TEST(UdnStressBinary, PrintsJsonAndExits2OnBadArguments) {
  const std::string bin = std::string(build_info::kRepoRoot) + "/build/udn_stress";
  if (!std::filesystem::exists(bin)) {
    GTEST_SKIP() << bin << " is not built (make build/udn_stress); the library tests above cover it";
  }
  const auto ok = run_command(bin + " --packets 640 --rate 0.2 --seed 3");
  EXPECT_EQ(ok.first, 0);
  expect_keys(ok.second);
  EXPECT_EQ(run_command(bin + " --pattern nope").first, 2);
  EXPECT_EQ(run_command(bin + " --failed-switches 99").first, 2);
}

}  // namespace
