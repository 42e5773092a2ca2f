/**
 * @file udn_stress_test.cpp
 * @brief udn_stress: argument parsing and exit statuses, the JSON report's keys, complete and
 *        deterministic raw runs, failed switches and tiles, a run stopped by its bound; the built
 *        binary when it is present.
 */
#include "tools/common/udn_stress/udn_stress.hpp"

#include "build_dirs.hpp"
#include "build_info.hpp"

#include <gtest/gtest.h>

#include <algorithm>
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
      // An unsigned option read "-1" as 2^64 - 1 without a word before.
      {"--seed", "-1"},          {"--failed-switches", "3,-4"}, {"--failed-tiles", "-2"},
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
  for (const char* status : {"Exit status: 0", "1 internal error", "2 bad arguments", "3 stopped by the --max-ms"}) {
    EXPECT_NE(msg.find(status), std::string::npos) << status << " in " << msg;
  }
}

TEST(UdnStressArgs, AnOptionTheModeCannotUseIsRefusedByName) {
  struct Case {
    std::vector<const char*> args;
    const char* named;
  };
  const std::vector<Case> cases{
      {{"--ft", "on", "--words", "125"}, "--words"},
      {{"--failed-tiles", "0,1,2,3,4,5,6,7,8,9,10,11,12,13,14,15,16,17,18,19,20,21,22,23,24,25,26,27,28,29,"
                          "30,31,32,33,34,35,36,37,38,39,40,41,42,43,44,45,46,47,48,49,50,51,52,53,54,55,56,57,58,59,"
                          "60,61,62,63"},
       "--failed-tiles"},
      {{"--ft", "on", "--profile", "maestro", "--failed-tiles", "0,1,2,3,4,5,6,7,8,9,10,11,12,13,14,15,16,17,18,19",
        "--failed-switches", "20,21,22,23,24,25,26,27,28,29,30,31,32,33,34,35,36,37,38,39,40,41,42,43,44,45,46,47,48"},
       "--failed-switches"},
  };
  for (const Case& c : cases) {
    tools::StressOptions o;
    std::string msg;
    EXPECT_EQ(parse(c.args, o, msg), 2) << c.named;
    EXPECT_NE(msg.find(c.named), std::string::npos) << msg;
  }
  // The same values where the mode can use them.
  tools::StressOptions o;
  std::string msg;
  EXPECT_EQ(parse({"--words", "128"}, o, msg), -1) << msg;
  EXPECT_EQ(parse({"--ft", "on", "--words", "124"}, o, msg), -1) << msg;
}

const char* const kKeys[] = {"\"sent\":",
                             "\"delivered\":",
                             "\"lost\":",
                             "\"corrupted_delivered\":",
                             "\"misdelivered\":",
                             "\"bound_ms\":",
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
  EXPECT_TRUE(r.completed());
  EXPECT_EQ(r.net.sent, 1280U);
  EXPECT_EQ(r.net.delivered, 1280U);
  EXPECT_EQ(r.delivery.sent, 1280U);
  EXPECT_EQ(r.delivery.delivered, 1280U);
  EXPECT_EQ(r.delivery.lost, 0U);
  EXPECT_EQ(r.delivery.corrupted_delivered, 0U);
  EXPECT_EQ(r.delivery.misdelivered, 0U);
  EXPECT_EQ(r.delivery.duplicated, 0U);
  EXPECT_EQ(r.delivery.misordered, 0U);
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
  ASSERT_TRUE(fine.completed());
  ASSERT_TRUE(coarse.completed());
  EXPECT_EQ(fine.net.latency_sum, coarse.net.latency_sum);
  EXPECT_EQ(fine.net.delivered, coarse.net.delivered);
}

TEST(UdnStressRun, FailedSwitchesLoseTheirPacketsAndTheRestArrives) {
  const tools::StressResult r = small_run(5U, {0U, 27U});
  EXPECT_TRUE(r.completed());
  const std::uint64_t lost = r.net.lost[static_cast<std::size_t>(bsp::UdnLoss::kFailedSwitch)];
  // Tiles 0 and 27 lose all they send (40 packets) at least, and the others lose some.
  EXPECT_GT(lost, 40U);
  EXPECT_EQ(r.net.delivered + lost, 1280U);
  EXPECT_EQ(r.delivery.delivered, r.net.delivered);
  EXPECT_EQ(r.delivery.lost, lost);
}

TEST(UdnStressRun, FailedTilesRunNothingAndAreSentNothing) {
  // Tile 27 as a failed switch still sends (its 20 packets die at its switch)
  // and is sent to; as a failed tile it does neither, so fewer packets die.
  tools::StressOptions o;
  o.packets = 1260U;
  o.rate_per_us = 0.2;
  o.seed = 5U;
  o.failed_switches = {27U};
  const tools::StressResult as_switch = tools::run_stress(o, bsp::heap::SealMode::kCount);
  o.failed_switches.clear();
  o.failed_tiles = {27U};
  const tools::StressResult as_tile = tools::run_stress(o, bsp::heap::SealMode::kCount);
  ASSERT_TRUE(as_switch.completed());
  ASSERT_TRUE(as_tile.completed());
  EXPECT_EQ(as_tile.delivery.sent, 1260U);  // the 63 others send all of it
  const auto dead = [](const tools::StressResult& r) {
    return r.net.lost[static_cast<std::size_t>(bsp::UdnLoss::kFailedSwitch)];
  };
  EXPECT_GT(dead(as_tile), 0U);  // some X-then-Y paths still cross tile 27
  EXPECT_LT(dead(as_tile) + 20U, dead(as_switch));
  EXPECT_EQ(as_tile.delivery.lost, dead(as_tile));
  EXPECT_EQ(as_tile.delivery.delivered + as_tile.delivery.lost, 1260U);
}

TEST(UdnStressRun, BitErrorsReachARawRunAndItsReceiversCountThem) {
  tools::StressOptions o;
  o.packets = 3000U;
  o.rate_per_us = 0.1;
  o.words = 8U;
  o.ber = 3e-3;
  o.seed = 5U;
  const tools::StressResult r = tools::run_stress(o, bsp::heap::SealMode::kCount);
  ASSERT_TRUE(r.completed());
  EXPECT_GT(r.net.bit_flips, 0U);
  EXPECT_GT(r.delivery.corrupted_delivered, 0U);
  EXPECT_EQ(r.delivery.lost, r.net.lost_total());  // never read = lost in the network
  EXPECT_EQ(r.delivery.sent, 3000U);
  EXPECT_EQ(r.delivery.delivered + r.delivery.lost, r.delivery.sent);
  // A corrupted packet has at least one flipped word (two flips can meet in one packet).
  EXPECT_LE(r.delivery.corrupted_delivered + r.delivery.misdelivered + r.delivery.lost, r.net.bit_flips);
  EXPECT_EQ(r.delivery.duplicated, 0U);
  EXPECT_EQ(r.delivery.misordered, 0U);
  EXPECT_EQ(r.ft.corrected, 0U);  // no layer to correct anything
}

TEST(UdnStressRun, DefaultBoundCoversTheTrafficAtItsRate) {
  tools::StressOptions o;
  EXPECT_DOUBLE_EQ(tools::bound_ms(o), 1000.0 + 2.0 * 100.0 / 0.01 / 1000.0);  // 6400 packets over 64 tiles
  // A soak: 1640 messages on the busiest of 61 tiles at 0.001/us need 1640 ms.
  o.ft = true;
  o.packets = 100'000U;
  o.rate_per_us = 0.001;
  o.failed_tiles = {19U, 20U, 44U};
  EXPECT_DOUBLE_EQ(tools::bound_ms(o), 1000.0 + 2.0 * 1640.0);
  o.max_ms = 12.5;
  EXPECT_DOUBLE_EQ(tools::bound_ms(o), 12.5);
}

std::vector<std::string> lines_of(const std::string& text) {
  std::vector<std::string> lines;
  std::istringstream in(text);
  for (std::string l; std::getline(in, l);) {
    lines.push_back(l);
  }
  return lines;
}

int main_of(std::vector<const char*> args, std::string& out, std::string& err) {
  args.insert(args.begin(), "udn_stress");
  std::ostringstream o;
  std::ostringstream e;
  const int rc = tools::stress_main(static_cast<int>(args.size()), args.data(), o, e);
  out = o.str();
  err = e.str();
  return rc;
}

TEST(UdnStressMain, ARunCutShortByTheBoundSaysSoInOneLineAndExits3) {
  for (const char* ft : {"off", "on"}) {
    std::string out;
    std::string err;
    const int rc = main_of({"--ft", ft, "--packets", "2000", "--rate", "0.001", "--max-ms", "2"}, out, err);
    EXPECT_EQ(rc, tools::kExitBound) << ft;
    EXPECT_EQ(tools::kExitBound, 3);
    const std::vector<std::string> lines = lines_of(err);
    ASSERT_EQ(lines.size(), 1U) << err;
    EXPECT_NE(lines[0].find("stopped by the bound of 2 emulated ms (--max-ms)"), std::string::npos) << lines[0];
    EXPECT_NE(lines[0].find(" of 2000 "), std::string::npos) << lines[0];
    EXPECT_NE(out.find("\"completed\":false"), std::string::npos) << out;
    expect_keys(out);
  }
}

TEST(UdnStressMain, CompletedBadArgumentsAndHelpStatuses) {
  std::string out;
  std::string err;
  EXPECT_EQ(main_of({"--packets", "640", "--rate", "0.2"}, out, err), tools::kExitCompleted);
  EXPECT_TRUE(err.empty()) << err;
  expect_keys(out);
  EXPECT_EQ(main_of({"--ft", "on", "--words", "128"}, out, err), tools::kExitBadArguments);
  EXPECT_NE(err.find("--words"), std::string::npos) << err;
  EXPECT_EQ(main_of({"--help"}, out, err), tools::kExitCompleted);
  EXPECT_NE(out.find("Exit status"), std::string::npos);
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
  const std::string bin = std::string(build_info::kBinDir) + "/udn_stress";
  ASSERT_TRUE(std::filesystem::exists(bin)) << bin << " is not built (make test builds it)";
  const auto ok = run_command(bin + " --packets 640 --rate 0.2 --seed 3");
  EXPECT_EQ(ok.first, 0);
  expect_keys(ok.second);
  EXPECT_EQ(run_command(bin + " --pattern nope").first, 2);
  EXPECT_EQ(run_command(bin + " --failed-switches 99").first, 2);
}

}  // namespace
