/**
 * @file udn_stress_ft_test.cpp
 * @brief udn_stress --ft: the fault-tolerance options, the link syntax, and a run with bit errors,
 *        failed tiles, switches and links that loses, duplicates, misorders and corrupts nothing.
 */
#include "tools/common/udn_stress.hpp"

#include <gtest/gtest.h>

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
  ASSERT_TRUE(r.completed);
  EXPECT_EQ(r.ft.sent, 20000U);
  EXPECT_EQ(r.ft.delivered, 20000U);
  EXPECT_EQ(r.ft.lost, 0U);
  EXPECT_EQ(r.ft.duplicated, 0U);
  EXPECT_EQ(r.ft.misordered, 0U);
  EXPECT_EQ(r.ft.corrupted_delivered, 0U);
  EXPECT_EQ(r.ft.unreachable, 0U);
  EXPECT_GT(r.ft.corrected, 0U);
  EXPECT_GT(r.ft.forwarded, 0U);
  EXPECT_EQ(r.heap_allocs_during_run, 0U);
  std::ostringstream json;
  tools::write_stress_json(json, o, r);
  for (const char* k : {"\"corrected\":", "\"forwarded\":", "\"retransmitted\":", "\"uncorrectable_detected\":",
                        "\"lost\":", "\"duplicated\":", "\"misordered\":", "\"corrupted_delivered\":",
                        "\"unreachable\":", "\"delivered\":20000"}) {
    EXPECT_NE(json.str().find(k), std::string::npos) << k;
  }
}

}  // namespace
