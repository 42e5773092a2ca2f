/**
 * @file udn_stress_ft_test.cpp
 * @brief udn_stress --ft: the fault-tolerance options, the link syntax, a run with bit errors,
 *        failed tiles, switches and links that loses, duplicates, misorders and corrupts nothing,
 *        and the same traffic raw and fault-tolerant, compared key for key.
 */
#include "tools/common/udn_stress/udn_stress.hpp"

#include <gtest/gtest.h>

#include <set>
#include <sstream>
#include <string>
#include <vector>

namespace {

int parse(std::vector<const char*> args, tools::StressOptions& opts, std::string& message) {
  args.insert(args.begin(), "udn_stress");
  return tools::parse_stress_args(static_cast<int>(args.size()), args.data(), opts, message);
}

TEST(UdnStressFt, OptionsParse) {
  tools::StressOptions o;
  std::string msg;
  ASSERT_EQ(parse({"--ft", "on", "--ber", "1e-4", "--failed-tiles", "4,5", "--failed-links", "12E,20-28"}, o, msg), -1)
      << msg;
  EXPECT_TRUE(o.ft);
  EXPECT_DOUBLE_EQ(o.ber, 1e-4);
  EXPECT_EQ(o.failed_tiles, (std::vector<std::uint32_t>{4U, 5U}));
  EXPECT_EQ(o.failed_links, (std::vector<std::string>{"12E", "20-28"}));
  ASSERT_EQ(parse({"--ft", "off"}, o, msg), -1) << msg;
  EXPECT_FALSE(o.ft);
  for (const auto& bad : std::vector<std::vector<const char*>>{{"--ft", "maybe"},
                                                               {"--ber", "0.5"},
                                                               {"--failed-tiles", "64"},
                                                               {"--failed-links", "7E"},
                                                               {"--failed-links", "0N"},
                                                               {"--failed-links", "12-14"},
                                                               {"--failed-links", "7-8"},
                                                               {"--failed-links", "12X"},
                                                               {"--failed-links", "x"}}) {
    tools::StressOptions b;
    EXPECT_EQ(parse(bad, b, msg), 2) << bad[0] << " " << bad[1];
    EXPECT_FALSE(msg.empty());
  }
}

TEST(UdnStressFt, LinkSyntaxNamesTheLinkLeavingTheTile) {
  tools::LinkSpec l{};
  ASSERT_EQ(tools::parse_link("12E", 8U, 8U, l), "");
  EXPECT_EQ(l.tile, 12U);
  EXPECT_EQ(l.dir, bsp::UdnDir::kEast);
  ASSERT_EQ(tools::parse_link("20-12", 8U, 8U, l), "");
  EXPECT_EQ(l.tile, 20U);
  EXPECT_EQ(l.dir, bsp::UdnDir::kNorth);
  ASSERT_EQ(tools::parse_link("9-8", 8U, 8U, l), "");
  EXPECT_EQ(l.dir, bsp::UdnDir::kWest);
}

TEST(UdnStressFt, RunWithErrorsAndFailuresDeliversEverythingOnceInOrder) {
  tools::StressOptions o;
  std::string msg;
  ASSERT_EQ(parse({"--ft", "on", "--packets", "20000", "--ber", "1e-3", "--failed-tiles", "8,9", "--failed-switches",
                   "45", "--failed-links", "20E,30-38", "--seed", "5"},
                  o, msg),
            -1)
      << msg;
  const tools::StressResult r = tools::run_stress(o, bsp::heap::SealMode::kCount);
  ASSERT_TRUE(r.completed());
  EXPECT_EQ(r.delivery.sent, 20000U);
  EXPECT_EQ(r.delivery.delivered, 20000U);
  EXPECT_EQ(r.delivery.lost, 0U);
  EXPECT_EQ(r.delivery.duplicated, 0U);
  EXPECT_EQ(r.delivery.misordered, 0U);
  EXPECT_EQ(r.delivery.corrupted_delivered, 0U);
  EXPECT_EQ(r.delivery.misdelivered, 0U);
  EXPECT_EQ(r.ft.unreachable, 0U);
  EXPECT_GT(r.ft.corrected, 0U);
  EXPECT_GT(r.ft.forwarded, 0U);
  EXPECT_EQ(r.heap_allocs_during_run, 0U);
  std::ostringstream json;
  tools::write_stress_json(json, o, r);
  for (const char* k : {"\"corrected\":", "\"forwarded\":", "\"retransmitted\":", "\"uncorrectable_detected\":",
                        "\"lost\":", "\"duplicated\":", "\"misordered\":", "\"corrupted_delivered\":",
                        "\"misdelivered\":", "\"unreachable\":", "\"delivered\":20000"}) {
    EXPECT_NE(json.str().find(k), std::string::npos) << k;
  }
}

/** The keys of a one-level JSON object, in order. */
std::vector<std::string> keys_of(const std::string& json) {
  std::vector<std::string> keys;
  for (std::size_t at = json.find("\":"); at != std::string::npos; at = json.find("\":", at + 1U)) {
    const std::size_t open = json.rfind('"', at - 1U);
    keys.push_back(json.substr(open + 1U, at - open - 1U));
  }
  return keys;
}

// The same traffic and bit error rate raw and through the fault-tolerant
// layer: the raw run's receivers see the errors (corrupted or lost packets),
// the fault-tolerant run's see none.
TEST(UdnStressFt, SameTrafficAndBitErrorsRawLosesOrCorruptsFaultTolerantDoesNot) {
  std::vector<const char*> args{"--packets", "3000", "--words", "8", "--rate", "0.05", "--ber", "3e-3",
                                "--failed-tiles", "27", "--seed", "5", "--ft", "off"};
  tools::StressOptions raw_opts;
  tools::StressOptions ft_opts;
  std::string msg;
  ASSERT_EQ(parse(args, raw_opts, msg), -1) << msg;
  args.back() = "on";
  ASSERT_EQ(parse(args, ft_opts, msg), -1) << msg;
  const tools::StressResult raw = tools::run_stress(raw_opts, bsp::heap::SealMode::kCount);
  const tools::StressResult ft = tools::run_stress(ft_opts, bsp::heap::SealMode::kCount);
  ASSERT_TRUE(raw.completed());
  ASSERT_TRUE(ft.completed());
  EXPECT_EQ(raw.delivery.sent, 3000U);
  EXPECT_EQ(ft.delivery.sent, 3000U);
  EXPECT_GT(raw.net.bit_flips, 0U);
  EXPECT_GT(ft.net.bit_flips, 0U);
  EXPECT_GT(raw.delivery.corrupted_delivered + raw.delivery.lost, 0U);
  EXPECT_GT(raw.delivery.corrupted_delivered, 0U);
  EXPECT_EQ(ft.delivery.lost, 0U);
  EXPECT_EQ(ft.delivery.duplicated, 0U);
  EXPECT_EQ(ft.delivery.misordered, 0U);
  EXPECT_EQ(ft.delivery.corrupted_delivered, 0U);
  EXPECT_EQ(ft.delivery.misdelivered, 0U);
  EXPECT_EQ(ft.delivery.delivered, 3000U);
  EXPECT_GT(ft.ft.corrected, 0U);
  std::ostringstream raw_json;
  std::ostringstream ft_json;
  tools::write_stress_json(raw_json, raw_opts, raw);
  tools::write_stress_json(ft_json, ft_opts, ft);
  const std::vector<std::string> keys = keys_of(raw_json.str());
  EXPECT_EQ(keys, keys_of(ft_json.str()));
  EXPECT_EQ(std::set<std::string>(keys.begin(), keys.end()).size(), keys.size());  // no key twice
  EXPECT_NE(raw_json.str().find("\"ft\":false,\"ber\":0.003"), std::string::npos) << raw_json.str();
  EXPECT_NE(ft_json.str().find("\"ft\":true,\"ber\":0.003"), std::string::npos) << ft_json.str();
}

TEST(UdnStressFt, PatternsReachTheFaultTolerantRunAndAvoidFailedTiles) {
  // Transpose with the centre's mirror failed: its senders draw uniformly instead;
  // diagonal tiles send to themselves through the layer.
  for (const char* pattern : {"transpose", "hotspot"}) {
    tools::StressOptions o;
    std::string msg;
    ASSERT_EQ(parse({"--ft", "on", "--pattern", pattern, "--packets", "1500", "--rate", "0.05", "--failed-tiles",
                     "35,26", "--ber", "1e-3", "--seed", "3"},
                    o, msg),
              -1)
        << msg;
    const tools::StressResult r = tools::run_stress(o, bsp::heap::SealMode::kCount);
    ASSERT_TRUE(r.completed()) << pattern;
    EXPECT_EQ(r.delivery.delivered, 1500U) << pattern;
    EXPECT_EQ(r.delivery.lost + r.delivery.corrupted_delivered + r.delivery.misdelivered, 0U) << pattern;
    EXPECT_EQ(r.ft.unreachable, 0U) << pattern;
  }
}

}  // namespace
