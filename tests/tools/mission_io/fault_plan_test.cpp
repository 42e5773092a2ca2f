/**
 * @file fault_plan_test.cpp
 * @brief Fault-plan files: every kind parsed, clear errors (file, entry, key, range) for bad plans, the demo
 *        plan, and plans armed on a real board whose fault log shows the injections.
 */
#include "tools/common/mission/fault_plan.hpp"

#include "bsp_tile64/emu/board.hpp"
#include "bsp_tile64/api/memory.hpp"
#include "bsp_tile64/api/udn_hw.hpp"
#include "bsp_tile64/emu/udn_net.hpp"
#include "tools/common/mission/run_folder.hpp"
#include "trn/tasks/messages.hpp"
#include "trn/tasks/sdc_points.hpp"

#include "build_info.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace {

constexpr std::uint32_t kTiles = 64U;
constexpr double kDuration = 60.0;
constexpr tools::DemoTiles kDemo = tools::demo_tiles(trn::tasks::kTile64Deployment);

std::string fixture(const std::string& name) {
  return std::string(build_info::kRepoRoot) + "/tests/fixtures/fault_plans/" + name;
}

tools::FaultPlanResult load(const std::string& name) { return tools::load_fault_plan(fixture(name), trn::tasks::kTile64Deployment, kDuration); }

/** The error of a fixture that must fail, with the assertion that it did. */
std::string error_of(const std::string& name) {
  const tools::FaultPlanResult r = load(name);
  EXPECT_FALSE(r.ok()) << name << " was accepted";
  return r.error;
}

bool same_items(const tools::FaultPlan& a, const tools::FaultPlan& b) {
  if (a.items.size() != b.items.size() || a.name != b.name || a.rates != b.rates ||
      a.commands.size() != b.commands.size()) {
    return false;
  }
  for (std::size_t i = 0; i < a.commands.size(); ++i) {
    if (a.commands[i].t_s != b.commands[i].t_s || a.commands[i].name != b.commands[i].name ||
        a.commands[i].code != b.commands[i].code) {
      return false;
    }
  }
  for (std::size_t i = 0; i < a.items.size(); ++i) {
    const tools::FaultPlanItem& x = a.items[i];
    const tools::FaultPlanItem& y = b.items[i];
    if (x.t_s != y.t_s || x.kind != y.kind || x.tile != y.tile || x.channel != y.channel || x.offset != y.offset ||
        x.bit != y.bit || x.param != y.param || x.role != y.role || x.instance != y.instance || x.carve != y.carve ||
        x.position != y.position) {
      return false;
    }
  }
  return true;
}

TEST(FaultPlan, KindNamesRoundTrip) {
  for (std::size_t k = 0; k < tools::kFaultKinds; ++k) {
    const auto kind = static_cast<bsp::FaultKind>(k);
    const std::optional<bsp::FaultKind> back = tools::fault_kind_from_name(tools::fault_kind_name(kind));
    ASSERT_TRUE(back.has_value()) << k;
    EXPECT_EQ(*back, kind);
  }
  EXPECT_EQ(tools::fault_kind_name(bsp::FaultKind::kCoreHang), "core_hang");
  EXPECT_EQ(tools::fault_kind_name(bsp::FaultKind::kPacketBitFlip), "packet_bit_flip");
  EXPECT_EQ(tools::fault_kind_name(bsp::FaultKind::kLinkFail), "link_fail");
  EXPECT_FALSE(tools::fault_kind_from_name("Core_Hang").has_value());
}

TEST(FaultPlan, EmptyTextIsAnEmptyPlan) {
  const tools::FaultPlanResult r = tools::parse_fault_plan("", "<empty>", kTiles, kDuration);
  ASSERT_TRUE(r.ok()) << r.error;
  EXPECT_TRUE(r.plan->items.empty());
  for (const double rate : r.plan->rates) {
    EXPECT_EQ(rate, 0.0);
  }
}

// The same text the scenario fuzzer found (tests/tools/scenario): toml++ asserted on it.
TEST(FaultPlan, ATableHeaderTheTomlParserCannotReadIsASyntaxErrorNotAnAbort) {
  const tools::FaultPlanResult r = tools::parse_fault_plan("[[fault]]\nt_s = 1.0\n[:a]\n", "plan.toml", kTiles, kDuration);
  EXPECT_FALSE(r.ok());
  EXPECT_EQ(r.error.rfind("plan.toml:", 0), 0U) << r.error;
  EXPECT_NE(r.error.find("TOML syntax error"), std::string::npos) << r.error;
}

TEST(FaultPlan, EveryKindAndKeyIsParsed) {
  const tools::FaultPlanResult r = load("full.toml");
  ASSERT_TRUE(r.ok()) << r.error;
  const tools::FaultPlan& p = *r.plan;
  EXPECT_EQ(p.name, "fixture-full");
  ASSERT_EQ(p.items.size(), 9U);
  EXPECT_EQ(p.items[0].kind, bsp::FaultKind::kCoreHang);
  EXPECT_DOUBLE_EQ(p.items[0].t_s, 1.5);
  EXPECT_EQ(p.items[0].tile, 3U);
  EXPECT_DOUBLE_EQ(p.items[1].t_s, 2.0);  // an integer is a valid time
  EXPECT_EQ(p.items[2].kind, bsp::FaultKind::kSdc);
  EXPECT_EQ(p.items[2].channel, 2U);
  EXPECT_EQ(p.items[2].bit, 40U);
  EXPECT_EQ(p.items[3].kind, bsp::FaultKind::kSeu);
  EXPECT_EQ(p.items[3].offset, 4096U);
  EXPECT_EQ(p.items[3].bit, 7U);
  EXPECT_EQ(p.items[4].kind, bsp::FaultKind::kWatchdogFail);
  EXPECT_EQ(p.items[5].kind, bsp::FaultKind::kPacketBitFlip);
  EXPECT_EQ(p.items[5].offset, 3U);  // word
  EXPECT_EQ(p.items[5].bit, 31U);
  EXPECT_EQ(p.items[6].kind, bsp::FaultKind::kSwitchFail);
  EXPECT_EQ(p.items[6].tile, 36U);
  EXPECT_EQ(p.items[7].kind, bsp::FaultKind::kLinkFail);
  EXPECT_DOUBLE_EQ(p.items[7].t_s, 0.0);  // no time: at the start
  EXPECT_EQ(p.items[7].param, static_cast<std::uint64_t>(bsp::UdnDir::kNorth));
  // Keys left out keep the injector's "draw it" values.
  EXPECT_DOUBLE_EQ(p.items[8].t_s, kDuration);  // the last instant of the run is allowed
  EXPECT_EQ(p.items[8].offset, bsp::kRandomOffset);
  EXPECT_EQ(p.items[8].bit, bsp::kRandomBit);
  EXPECT_EQ(p.items[0].channel, bsp::kAnyChannel);
  EXPECT_DOUBLE_EQ(p.rates[static_cast<std::size_t>(bsp::FaultKind::kSeu)], 1e-3);
  EXPECT_DOUBLE_EQ(p.rates[static_cast<std::size_t>(bsp::FaultKind::kCoreReset)], 2.5e-4);
  EXPECT_EQ(p.rates[static_cast<std::size_t>(bsp::FaultKind::kPacketBitFlip)], 0.0);
}

TEST(FaultPlan, FormattedPlanParsesBackToTheSamePlan) {
  const tools::FaultPlanResult r = load("full.toml");
  ASSERT_TRUE(r.ok()) << r.error;
  tools::FaultPlan p = *r.plan;
  p.name = "quote \" backslash \\ tab \t";
  const std::string text = tools::format_fault_plan(p);
  const tools::FaultPlanResult back = tools::parse_fault_plan(text, "<formatted>", kTiles, kDuration);
  ASSERT_TRUE(back.ok()) << back.error << "\n" << text;
  EXPECT_TRUE(same_items(p, *back.plan)) << text;
}

// Where in the upset space an seu's byte is: a fraction in [0, 1), written back as read; not with
// an offset, not for another kind, not 1 or beyond.
TEST(FaultPlan, AnSeuCanSayWhereInItsSpace) {
  const std::string text = "[[fault]]\nt_s = 1.0\nkind = \"seu\"\ntile = 3\nposition = 0.8125\nbit = 4\n";
  const tools::FaultPlanResult r = tools::parse_fault_plan(text, "<position>", kTiles, kDuration);
  ASSERT_TRUE(r.ok()) << r.error;
  EXPECT_DOUBLE_EQ(r.plan->items[0].position, 0.8125);
  const tools::FaultPlanResult back =
      tools::parse_fault_plan(tools::format_fault_plan(*r.plan), "<formatted>", kTiles, kDuration);
  ASSERT_TRUE(back.ok()) << back.error;
  EXPECT_TRUE(same_items(*r.plan, *back.plan));
  EXPECT_TRUE(tools::parse_fault_plan("[[fault]]\nt_s = 1.0\nkind = \"seu\"\ntile = 3\nposition = 0\n", "<zero>",
                                      kTiles, kDuration)
                  .ok());
  for (const char* bad : {"position = 1.0\n", "position = -0.1\n", "position = 0.5\noffset = 12\n",
                          "position = \"half\"\n"}) {
    const tools::FaultPlanResult e = tools::parse_fault_plan(
        std::string("[[fault]]\nt_s = 1.0\nkind = \"seu\"\ntile = 3\n") + bad, "<bad>", kTiles, kDuration);
    EXPECT_FALSE(e.ok()) << bad;
  }
  EXPECT_FALSE(tools::parse_fault_plan("[[fault]]\nt_s = 1.0\nkind = \"sdc\"\ntile = 3\nposition = 0.5\n", "<sdc>",
                                       kTiles, kDuration)
                   .ok());
}

// An upset aimed at a carve of the tile's RAM (the filter's EKF here), offset counted from its start.
TEST(FaultPlan, AnSeuCanNameACarve) {
  const std::string text = "[[fault]]\nt_s = 1.0\nkind = \"seu\"\nrole = \"filter_replica\"\ninstance = 0\n"
                           "carve = \"ekf\"\noffset = 512\nbit = 4\n";
  const tools::FaultPlanResult r = tools::parse_fault_plan(text, "<carve>", kTiles, kDuration);
  ASSERT_TRUE(r.ok()) << r.error;
  ASSERT_EQ(r.plan->items.size(), 1U);
  EXPECT_EQ(r.plan->items[0].carve, "ekf");
  EXPECT_EQ(r.plan->items[0].offset, 512U);
  const tools::FaultPlanResult back =
      tools::parse_fault_plan(tools::format_fault_plan(*r.plan), "<formatted>", kTiles, kDuration);
  ASSERT_TRUE(back.ok()) << back.error;
  EXPECT_TRUE(same_items(*r.plan, *back.plan));
  const tools::FaultPlanResult wrong = tools::parse_fault_plan(
      "[[fault]]\nt_s = 1.0\nkind = \"sdc\"\ntile = 3\ncarve = \"ekf\"\n", "<sdc>", kTiles, kDuration);
  EXPECT_FALSE(wrong.ok()) << "carve is an seu key only";
  const tools::FaultPlanResult long_name = tools::parse_fault_plan(
      "[[fault]]\nt_s = 1.0\nkind = \"seu\"\ntile = 3\ncarve = \"a name far too long for a carve\"\n", "<long>",
      kTiles, kDuration);
  ASSERT_FALSE(long_name.ok());
  EXPECT_NE(long_name.error.find("1 to 23 characters"), std::string::npos) << long_name.error;
}

TEST(FaultPlan, DemoFileIsTheBuiltInDemoPlan) {
  const tools::FaultPlanResult r = load("demo.toml");
  ASSERT_TRUE(r.ok()) << r.error;
  EXPECT_TRUE(same_items(*r.plan, tools::demo_fault_plan(trn::tasks::kTile64Deployment)))
      << "tests/fixtures/fault_plans/demo.toml and demo_fault_plan() differ:\n"
      << tools::format_fault_plan(tools::demo_fault_plan(trn::tasks::kTile64Deployment));
}

TEST(FaultPlan, DemoPlanAimsAtFaultTolerantSendersWithHandledKinds) {
  const tools::FaultPlan p = tools::demo_fault_plan(trn::tasks::kTile64Deployment);
  std::size_t flips = 0U;
  std::size_t switches = 0U;
  std::size_t replica_faults = 0U;
  for (const tools::FaultPlanItem& it : p.items) {
    if (!it.role.empty()) {
      // The TMR part: faults on replicas and on the voter, after the switch at 10 s.
      ++replica_faults;
      EXPECT_TRUE(it.role == "filter_replica" || (it.role == "filter" && it.kind == bsp::FaultKind::kCoreHang)) << it.role;
      EXPECT_TRUE(it.kind == bsp::FaultKind::kSdc || it.kind == bsp::FaultKind::kCoreHang) << tools::fault_kind_name(it.kind);
      EXPECT_GT(it.t_s, 10.0);
      continue;
    }
    ASSERT_TRUE(it.kind == bsp::FaultKind::kPacketBitFlip || it.kind == bsp::FaultKind::kSwitchFail)
        << tools::fault_kind_name(it.kind);
    if (it.kind == bsp::FaultKind::kPacketBitFlip) {
      ++flips;
      EXPECT_TRUE(it.tile == kDemo.vision_coordinator || it.tile == kDemo.filter ||
                  it.tile == kDemo.vision_a || it.tile == kDemo.vision_b)
          << it.tile;
      EXPECT_GE(it.t_s, 5.0);
      EXPECT_LE(it.t_s, 35.0);
      EXPECT_GE(it.offset, 2U) << "the demo flips payload words, not the hardware header and tag";
    } else {
      ++switches;
      EXPECT_EQ(it.tile, kDemo.failed_switch);
      EXPECT_DOUBLE_EQ(it.t_s, 20.0);
    }
  }
  EXPECT_EQ(replica_faults, 19U) << "3, then two replicas in each of 8 jobs";
  ASSERT_EQ(p.commands.size(), 1U);
  EXPECT_EQ(p.commands[0].name, "reliability_high");
  EXPECT_EQ(p.commands[0].code, trn::tasks::kCmdReliabilityHigh) << "a policy for the supervisor tree, not a filter command";
  EXPECT_EQ(flips, 8U);
  EXPECT_EQ(switches, 1U);
  EXPECT_DOUBLE_EQ(tools::demo_fault_plan_end_s(), 35.0);
  // Every tile the demo uses is one the parser accepts on the chip.
  const tools::FaultPlanResult r =
      tools::parse_fault_plan(tools::format_fault_plan(p), "<demo>", kTiles, tools::demo_fault_plan_end_s());
  EXPECT_TRUE(r.ok()) << r.error;
}

// ------------------------------------------------------------------ bad plans

TEST(FaultPlanErrors, UnknownKindListsTheKinds) {
  const std::string e = error_of("unknown_kind.toml");
  EXPECT_NE(e.find("unknown_kind.toml: [[fault]] #1 (line 1) kind: unknown fault kind \"cosmic_ray\""),
            std::string::npos)
      << e;
  EXPECT_NE(e.find("core_hang, core_reset, sdc, seu, watchdog_fail, packet_bit_flip, switch_fail, link_fail"),
            std::string::npos)
      << e;
}

TEST(FaultPlanErrors, UnknownTopLevelKey) {
  const std::string e = error_of("unknown_top_key.toml");
  EXPECT_NE(e.find("unknown_top_key.toml: severity: unknown key (allowed at the top: name, [[fault]], [[command]], [rates])"),
            std::string::npos)
      << e;
}

TEST(FaultPlanErrors, TileOutOfRangeNamesTheRange) {
  const std::string e = error_of("tile_out_of_range.toml");
  EXPECT_NE(e.find("tile_out_of_range.toml: [[fault]] #1 (line 1) tile: 64 is out of range: allowed 0 .. 63"),
            std::string::npos)
      << e;
}

TEST(FaultPlanErrors, TimesBeforeZeroOrAfterTheRunAreRejected) {
  std::string e = error_of("negative_time.toml");
  EXPECT_NE(e.find("negative_time.toml: [[fault]] #1 (line 1) t_s: -1 is out of range: allowed 0 .. 60 s"),
            std::string::npos)
      << e;
  e = error_of("beyond_duration.toml");
  EXPECT_NE(e.find("t_s: 75 is out of range: allowed 0 .. 60 s (the run's duration)"), std::string::npos) << e;
}

TEST(FaultPlanErrors, BitRangeDependsOnTheKind) {
  const std::string e = error_of("bad_bit.toml");
  EXPECT_NE(e.find("[[fault]] #1 (line 1) bit: 32 is out of range: allowed 0 .. 31"), std::string::npos) << e;
  EXPECT_NE(e.find("[[fault]] #2 (line 7) bit: 8 is out of range: allowed 0 .. 7"), std::string::npos) << e;
}

TEST(FaultPlanErrors, KeysOfOtherKindsAreRejected) {
  std::string e = error_of("key_not_for_kind.toml");
  EXPECT_NE(e.find("bit: not used by switch_fail (allowed keys for switch_fail: t_s, kind, tile or role (and "
                   "instance))"),
            std::string::npos)
      << e;
  e = error_of("unknown_fault_key.toml");
  EXPECT_NE(e.find("address: unknown key (allowed keys for seu: t_s, kind, tile or role (and instance), offset, bit, carve, position)"),
            std::string::npos)
      << e;
}

TEST(FaultPlanErrors, BadRatesAreRejected) {
  std::string e = error_of("bad_rate.toml");
  EXPECT_NE(e.find("bad_rate.toml: [rates] seu: -0.001 is out of range: allowed 0 .. 1 faults per tile per second"),
            std::string::npos)
      << e;
  EXPECT_NE(e.find("[rates] core_hang: 5 is out of range"), std::string::npos) << e;  // every error is reported
  e = error_of("unknown_rate_kind.toml");
  EXPECT_NE(e.find("[rates] bitrot: unknown fault kind (allowed: core_hang"), std::string::npos) << e;
}

TEST(FaultPlanErrors, LinkFailNeedsAValidDirection) {
  std::string e = error_of("link_without_direction.toml");
  EXPECT_NE(e.find("[[fault]] #1 (line 1): missing key direction (allowed: east, west, north, south)"),
            std::string::npos)
      << e;
  e = error_of("bad_direction.toml");
  EXPECT_NE(e.find("direction: unknown direction \"up\" (allowed: east, west, north, south)"), std::string::npos)
      << e;
}

TEST(FaultPlanErrors, WrongTypesNameTheExpectedType) {
  const std::string e = error_of("wrong_type.toml");
  EXPECT_NE(e.find("t_s: wrong type: expected a number"), std::string::npos) << e;
  EXPECT_NE(e.find("tile: wrong type: expected an integer"), std::string::npos) << e;
}

TEST(FaultPlanErrors, MissingKindOrTile) {
  std::string e = error_of("missing_kind.toml");
  EXPECT_NE(e.find("[[fault]] #1 (line 1): missing key kind (allowed: core_hang"), std::string::npos) << e;
  e = error_of("missing_tile.toml");
  EXPECT_NE(e.find("[[fault]] #1 (line 1): missing key tile (allowed 0 .. 63) or role (trn_supervisor, "
                   "vision_coordinator, io, filter, vision, filter_replica, filter_supervisor, vision_supervisor)"),
            std::string::npos)
      << e;
}

// Core health moves roles between tiles: a plan can name the role, resolved when the fault is due.
TEST(FaultPlan, ARoleIsNamedInsteadOfATile) {
  const tools::FaultPlanResult r = tools::parse_fault_plan(
      "[[fault]]\nt_s = 3.0\nkind = \"core_hang\"\nrole = \"filter\"\n"
      "[[fault]]\nt_s = 4.0\nkind = \"sdc\"\nrole = \"vision\"\ninstance = 39\nchannel = 7\n",
      "<text>", kTiles, kDuration);
  ASSERT_TRUE(r.ok()) << r.error;
  ASSERT_EQ(r.plan->items.size(), 2U);
  EXPECT_EQ(r.plan->items[0].role, "filter");
  EXPECT_EQ(r.plan->items[1].role, "vision");
  EXPECT_EQ(r.plan->items[1].instance, 39U);
  // It formats back as a role.
  const tools::FaultPlanResult again =
      tools::parse_fault_plan(tools::format_fault_plan(*r.plan), "<formatted>", kTiles, kDuration);
  ASSERT_TRUE(again.ok()) << again.error;
  EXPECT_EQ(again.plan->items[0].role, "filter");
  EXPECT_EQ(again.plan->items[1].instance, 39U);
}

// An sdc names the point of the flight code it corrupts; it formats back as that point.
TEST(FaultPlan, AnSdcNamesAPoint) {
  const tools::FaultPlanResult r = tools::parse_fault_plan(
      "[[fault]]\nt_s = 3.0\nkind = \"sdc\"\nrole = \"filter\"\npoint = \"filter_state\"\nbit = 52\n"
      "[[fault]]\nt_s = 4.0\nkind = \"sdc\"\ntile = 30\npoint = \"vision_matches\"\n"
      "[[fault]]\nt_s = 5.0\nkind = \"sdc\"\ntile = 1\nchannel = 4\n",
      "<text>", kTiles, kDuration);
  ASSERT_TRUE(r.ok()) << r.error;
  ASSERT_EQ(r.plan->items.size(), 3U);
  EXPECT_EQ(r.plan->items[0].channel, trn::tasks::kFilterStateChannel);
  EXPECT_EQ(r.plan->items[1].channel, trn::tasks::kVisionMatchesChannel);
  EXPECT_EQ(r.plan->items[2].channel, trn::tasks::kCoordinatorBatchChannel);
  const std::string text = tools::format_fault_plan(*r.plan);
  EXPECT_NE(text.find("point = \"coordinator_batch\""), std::string::npos) << text;
  const tools::FaultPlanResult again = tools::parse_fault_plan(text, "<formatted>", kTiles, kDuration);
  ASSERT_TRUE(again.ok()) << again.error;
  EXPECT_EQ(again.plan->items[2].channel, trn::tasks::kCoordinatorBatchChannel);
}

// A lasting error: `shift` at a point whose value starts with a number, formatted back, armed with its shift;
// the mistakes are named.
TEST(FaultPlan, AShiftIsALastingSdcAtAPointThatTakesIt) {
  const tools::FaultPlanResult r = tools::parse_fault_plan(
      "[[fault]]\nt_s = 8.0\nkind = \"sdc\"\nrole = \"vision\"\ninstance = 5\npoint = \"match_position\"\n"
      "shift = 2.0\n",
      "<text>", kTiles, kDuration);
  ASSERT_TRUE(r.ok()) << r.error;
  ASSERT_EQ(r.plan->items.size(), 1U);
  EXPECT_EQ(r.plan->items[0].channel, trn::vision::kMatchPositionChannel);
  EXPECT_EQ(r.plan->items[0].shift, 2.0);
  const std::string text = tools::format_fault_plan(*r.plan);
  EXPECT_NE(text.find("shift = 2.0"), std::string::npos) << text;
  const tools::FaultPlanResult again = tools::parse_fault_plan(text, "<formatted>", kTiles, kDuration);
  ASSERT_TRUE(again.ok()) << again.error;
  EXPECT_EQ(again.plan->items[0].shift, 2.0);
  const auto error_for = [](const std::string& entry) {
    const tools::FaultPlanResult e =
        tools::parse_fault_plan("[[fault]]\nt_s = 1.0\nkind = \"sdc\"\n" + entry, "<text>", kTiles, kDuration);
    return e.ok() ? std::string("accepted") : e.error;
  };
  std::string e = error_for("tile = 18\npoint = \"filter_product\"\nshift = 1.0\n");
  EXPECT_NE(e.find("shift: filter_product does not start with a number a shift could move (allowed at: "
                   "match_position)"),
            std::string::npos)
      << e;
  e = error_for("tile = 24\npoint = \"match_position\"\nshift = 1.0\nbit = 3\n");
  EXPECT_NE(e.find("bit: a shift is a lasting error, not a bit flip"), std::string::npos) << e;
  e = error_for("tile = 24\nshift = 1.0\n");
  EXPECT_NE(e.find("shift: a lasting error names its point"), std::string::npos) << e;
  e = error_for("tile = 24\npoint = \"match_position\"\nshift = 0\n");
  EXPECT_NE(e.find("shift: 0 changes nothing"), std::string::npos) << e;
  e = error_for("tile = 24\npoint = \"match_position\"\nshift = 5000.0\n");
  EXPECT_NE(e.find("shift: 5000 is out of range"), std::string::npos) << e;
}

// An sdc that could never be delivered is refused with the key named, never armed to do nothing.
TEST(FaultPlanErrors, AnSdcNobodyWouldDeliverIsRefused) {
  const auto error_for = [](const std::string& entry) {
    const tools::FaultPlanResult r =
        tools::parse_fault_plan("[[fault]]\nt_s = 1.0\nkind = \"sdc\"\n" + entry, "<text>", kTiles, kDuration);
    return r.ok() ? std::string("accepted") : r.error;
  };
  std::string e = error_for("tile = 24\npoint = \"filter_state\"\n");
  EXPECT_NE(e.find("point: tile 24 (vision) never publishes at filter_state (published by: filter, filter_replica)"),
            std::string::npos)
      << e;
  e = error_for("role = \"io\"\npoint = \"nav_output\"\n");
  EXPECT_NE(e.find("point: role io never publishes at nav_output"), std::string::npos) << e;
  e = error_for("tile = 18\nchannel = 99\n");
  EXPECT_NE(e.find("channel: no flight code publishes on channel 99 (name a point instead: nav_output, filter_state, "
                   "vision_matches, coordinator_batch, filter_product, filter_update_product, match_position, "
                   "self_test, correlation_surface, correlation_dot, coarse_band)"),
            std::string::npos)
      << e;
  e = error_for("tile = 2\n");
  EXPECT_NE(e.find("tile: tile 2 (spare) publishes nothing an sdc could corrupt"), std::string::npos) << e;
  e = error_for("tile = 18\npoint = \"velocity\"\n");
  EXPECT_NE(e.find("point: unknown point \"velocity\" (allowed: nav_output"), std::string::npos) << e;
  e = error_for("tile = 18\npoint = \"nav_output\"\nchannel = 1\n");
  EXPECT_NE(e.find("point: an sdc names a point or a channel, not both"), std::string::npos) << e;
  e = error_for("tile = 1\npoint = \"self_test\"\n");
  EXPECT_EQ(e, "accepted");
}

TEST(FaultPlanErrors, RoleMistakesAreNamed) {
  std::string e = error_of("unknown_role.toml");
  EXPECT_NE(e.find("unknown_role.toml: [[fault]] #1 (line 1) role: unknown role \"navigator\" (allowed: "
                   "trn_supervisor, vision_coordinator, io, filter, vision, filter_replica, filter_supervisor, "
                   "vision_supervisor)"),
            std::string::npos)
      << e;
  e = error_of("role_and_tile.toml");
  EXPECT_NE(e.find("role: a fault names a tile or a role, not both"), std::string::npos) << e;
  EXPECT_NE(e.find("instance: only with role = \"vision\""), std::string::npos) << e;
  const tools::FaultPlanResult r = tools::parse_fault_plan(
      "[[fault]]\nt_s = 1.0\nkind = \"core_hang\"\nrole = \"vision\"\ninstance = 40\n", "<text>", kTiles, kDuration);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error.find("instance: 40 is out of range: allowed 0 .. 39"), std::string::npos) << r.error;
}

// Telecommands: timed, named, formatted back; an unknown one is an error naming the allowed ones.
TEST(FaultPlan, CommandsAreParsedAndFormatted) {
  const tools::FaultPlanResult r = tools::parse_fault_plan(
      "[[command]]\nt_s = 5.0\nname = \"filter_tmr\"\n[[command]]\nt_s = 9.5\nname = \"filter_simplex\"\n"
      "[[fault]]\nt_s = 6.0\nkind = \"core_hang\"\nrole = \"filter_replica\"\ninstance = 2\n",
      "<text>", kTiles, kDuration);
  ASSERT_TRUE(r.ok()) << r.error;
  ASSERT_EQ(r.plan->commands.size(), 2U);
  EXPECT_EQ(r.plan->commands[0].code, trn::tasks::kCmdFilterTmr);
  EXPECT_EQ(r.plan->commands[1].code, trn::tasks::kCmdFilterSimplex);
  EXPECT_DOUBLE_EQ(r.plan->commands[1].t_s, 9.5);
  EXPECT_EQ(r.plan->items[0].instance, 2U);
  const tools::FaultPlanResult again =
      tools::parse_fault_plan(tools::format_fault_plan(*r.plan), "<formatted>", kTiles, kDuration);
  ASSERT_TRUE(again.ok()) << again.error;
  EXPECT_EQ(again.plan->commands.size(), 2U);
  EXPECT_EQ(again.plan->items[0].role, "filter_replica");
}

TEST(FaultPlanErrors, CommandMistakesAreNamed) {
  const std::string e = error_of("unknown_command.toml");
  EXPECT_NE(e.find("[[command]] #1 (line 2) name: unknown command \"filter_quintuple\" (allowed: filter_tmr, "
                   "filter_simplex, reliability_normal, reliability_high, power_full, power_save)"),
            std::string::npos)
      << e;
  const tools::FaultPlanResult r = tools::parse_fault_plan(
      "[[command]]\nt_s = 1.0\n[[fault]]\nkind = \"core_hang\"\nrole = \"filter_replica\"\ninstance = 3\n",
      "<text>", kTiles, kDuration);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error.find("missing key name"), std::string::npos) << r.error;
  EXPECT_NE(r.error.find("instance: 3 is out of range: allowed 0 .. 2 (the filter's replicas)"), std::string::npos)
      << r.error;
}

TEST(FaultPlanErrors, SeuOffsetBeyondTheTileRam) {
  const std::string e = error_of("offset_out_of_range.toml");
  EXPECT_NE(e.find("offset: 99999999999 is out of range: allowed 0 .. " + std::to_string(bsp::kTileRamBytes - 1U)),
            std::string::npos)
      << e;
}

TEST(FaultPlanErrors, FaultMustBeAnArrayOfTables) {
  const std::string e = error_of("fault_not_a_table.toml");
  EXPECT_NE(e.find("fault: must be an array of tables ([[fault]] entries)"), std::string::npos) << e;
}

TEST(FaultPlanErrors, SyntaxErrorsGiveFileLineAndColumn) {
  const std::string e = error_of("syntax_error.toml");
  EXPECT_NE(e.find("syntax_error.toml:3:"), std::string::npos) << e;
  EXPECT_NE(e.find("TOML syntax error"), std::string::npos) << e;
}

TEST(FaultPlanErrors, MissingFileIsNamed) {
  const std::string e = error_of("does_not_exist.toml");
  EXPECT_NE(e.find("does_not_exist.toml: cannot open fault plan file: No such file or directory"), std::string::npos)
      << e;
}

TEST(FaultPlanErrors, MoreEntriesThanTheInjectorHolds) {
  std::string text;
  for (std::size_t i = 0; i <= bsp::kFaultPlanCapacity; ++i) {
    text += "[[fault]]\nkind = \"core_hang\"\ntile = 1\n";
  }
  const tools::FaultPlanResult r = tools::parse_fault_plan(text, "big.toml", kTiles, kDuration);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error.find("big.toml: [[fault]]: 257 entries are more than the injector holds (allowed 0 .. 256)"),
            std::string::npos)
      << r.error;
  // Exactly the capacity is fine.
  text.resize(text.size() - std::string("[[fault]]\nkind = \"core_hang\"\ntile = 1\n").size());
  EXPECT_TRUE(tools::parse_fault_plan(text, "full.toml", kTiles, kDuration).ok());
}

TEST(FaultPlanErrors, TheChipSizeDecidesTheTileRange) {
  const tools::FaultPlanResult r =
      tools::parse_fault_plan("[[fault]]\nkind = \"seu\"\ntile = 20\n", "small.toml", 16U, kDuration);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error.find("tile: 20 is out of range: allowed 0 .. 15"), std::string::npos) << r.error;
}

TEST(FaultPlan, EveryKindIsDocumentedAndTheDocExampleParses) {
  std::ifstream in(std::string(build_info::kRepoRoot) + "/docs/FAULT_PLANS.md");
  ASSERT_TRUE(in) << "docs/FAULT_PLANS.md missing";
  std::stringstream ss;
  ss << in.rdbuf();
  const std::string doc = ss.str();
  for (std::size_t k = 0; k < tools::kFaultKinds; ++k) {
    const std::string name = tools::fault_kind_name(static_cast<bsp::FaultKind>(k));
    EXPECT_NE(doc.find("`" + name + "`"), std::string::npos) << name << " is not documented";
  }
  const std::size_t open = doc.find("```toml\n");
  ASSERT_NE(open, std::string::npos) << "no ```toml example";
  const std::size_t close = doc.find("```", open + 8U);
  ASSERT_NE(close, std::string::npos);
  const tools::FaultPlanResult r =
      tools::parse_fault_plan(doc.substr(open + 8U, close - open - 8U), "FAULT_PLANS.md example", kTiles, kDuration);
  EXPECT_TRUE(r.ok()) << r.error;
}

// ------------------------------------------------------------------ armed on a real board

constexpr bsp::Cycles kQuantum = 1000U;

/** A board with no tile running code; @p quantum short for exact timing, long (1 ms) for long runs. */
void init_board(bsp::Cycles quantum = kQuantum) {
  bsp::BoardConfig c = bsp::default_config(bsp::kTile64);
  c.quantum_cycles = quantum;
  c.tick_cycles = std::max(10U * kQuantum, quantum);
  c.powered_at_start = 0U;  // host-driven: faults and the network still act at the barriers
  c.monitor_tile = bsp::kNoTile;
  c.seed = 7U;
  ASSERT_EQ(bsp::board_init(c), bsp::BoardError::kOk);
  ASSERT_EQ(bsp::udn_net_init(bsp::NetConfig{}), bsp::NetError::kOk);
}

double clock_hz() { return static_cast<double>(bsp::kTile64.clock_hz); }

bsp::Cycles cycles(double t_s) { return static_cast<bsp::Cycles>(std::llround(t_s * clock_hz())); }

const bsp::FaultRecord* record_of(bsp::FaultKind kind, bsp::TileId tile) {
  for (const bsp::FaultRecord& r : bsp::fault_log()) {
    if (r.spec.kind == kind && r.spec.tile == tile && !r.random) {
      return &r;
    }
  }
  return nullptr;
}

TEST(FaultPlanArm, InjectionsHappenAtTheirTimesWithTheirTargets) {
  init_board();
  const char* text = R"(
name = "arm-test"
[[fault]]
t_s = 0.002
kind = "seu"
tile = 3
offset = 100
bit = 5
[[fault]]
t_s = 0.003
kind = "packet_bit_flip"
tile = 1
word = 3
bit = 7
[[fault]]
t_s = 0.005
kind = "switch_fail"
tile = 44
[[fault]]
t_s = 0.004
kind = "link_fail"
tile = 20
direction = "east"
)";
  const tools::FaultPlanResult r = tools::parse_fault_plan(text, "<arm>", bsp::kTile64.tiles(), 1.0);
  ASSERT_TRUE(r.ok()) << r.error;
  const std::byte before = bsp::region_span(bsp::Region{3U})[100];
  std::string error;
  ASSERT_TRUE(tools::arm_fault_plan(*r.plan, clock_hz(), error)) << error;
  EXPECT_TRUE(bsp::fault_log().empty()) << "nothing is injected before the run";

  (void)bsp::run_for(cycles(0.010));
  ASSERT_EQ(bsp::fault_log().size(), 4U);

  const bsp::FaultRecord* seu = record_of(bsp::FaultKind::kSeu, 3U);
  ASSERT_NE(seu, nullptr);
  EXPECT_EQ(seu->status, bsp::FaultStatus::kApplied);
  EXPECT_EQ(seu->applied_cycle, cycles(0.002));
  EXPECT_EQ(seu->offset, 100U);
  EXPECT_EQ(seu->bit, 5U);
  EXPECT_EQ(bsp::region_span(bsp::Region{3U})[100], before ^ std::byte{1U << 5U}) << "the bit really flipped";

  const bsp::FaultRecord* sw = record_of(bsp::FaultKind::kSwitchFail, 44U);
  ASSERT_NE(sw, nullptr);
  EXPECT_EQ(sw->status, bsp::FaultStatus::kApplied);
  EXPECT_EQ(sw->applied_cycle, cycles(0.005));

  const bsp::FaultRecord* link = record_of(bsp::FaultKind::kLinkFail, 20U);
  ASSERT_NE(link, nullptr);
  EXPECT_EQ(link->status, bsp::FaultStatus::kApplied);
  EXPECT_EQ(link->spec.param, static_cast<std::uint64_t>(bsp::UdnDir::kEast));

  // The bit flip waits for the next packet tile 1 sends, then corrupts word 3 bit 7 of it.
  const bsp::FaultRecord* flip = record_of(bsp::FaultKind::kPacketBitFlip, 1U);
  ASSERT_NE(flip, nullptr);
  EXPECT_EQ(flip->status, bsp::FaultStatus::kArmed);
  const std::vector<std::uint32_t> words = {bsp::udn_make_header(2U, 0U, 4U), 0x55U, 10U, 20U, 30U};
  ASSERT_EQ(bsp::udn_net_send_from(1U, bsp::board_time(), words), bsp::NetError::kOk);
  (void)bsp::run_for(5U * kQuantum);
  EXPECT_EQ(flip->status, bsp::FaultStatus::kApplied);
  EXPECT_EQ(flip->offset, 3U);
  EXPECT_EQ(flip->bit, 7U);
  bsp::RxPacket rx{};
  std::array<std::uint32_t, 8> payload{};
  ASSERT_EQ(bsp::udn_net_receive_on(2U, bsp::kUdnCatchAll, rx, payload), bsp::NetError::kOk);
  ASSERT_EQ(rx.payload_words, 3U);
  EXPECT_EQ(payload[0], 10U);
  EXPECT_EQ(payload[1], 20U ^ (1U << 7U)) << "word 3 of the packet is the second payload word";
  EXPECT_EQ(payload[2], 30U);

  // The events log gets one INJECT line per fault that took effect.
  tools::EventLog log(16U);
  EXPECT_EQ(tools::log_injections(bsp::fault_log(), clock_hz(), log), 4U);
  EXPECT_EQ(log.count(tools::EventCategory::kInject), 4U);
  const std::vector<tools::Event> ev = log.sorted();
  ASSERT_EQ(ev.size(), 4U);
  EXPECT_NE(std::string(ev[0].text.data()).find("seu RAM offset 0x64 bit 5 (planned)"), std::string::npos)
      << ev[0].text.data();
  EXPECT_NEAR(ev[0].t_s, 0.002, 1e-12);
  EXPECT_NE(std::string(ev[1].text.data()).find("link_fail east link"), std::string::npos) << ev[1].text.data();
}

// The demo's faults on tiles, on a bare board (its telecommand needs the uplink and its replica
// faults the mission's role directory: the mission test DemoPlanCountsComeFromFlightEvents flies those).
TEST(FaultPlanArm, DemoPlanIsInjectedOnTheChip) {
  init_board(bsp::kTile64.cycles_per_ms());
  tools::FaultPlan demo = tools::demo_fault_plan(trn::tasks::kTile64Deployment);
  demo.commands.clear();
  std::erase_if(demo.items, [](const tools::FaultPlanItem& it) { return !it.role.empty(); });
  ASSERT_EQ(demo.items.size(), 9U);
  std::string error;
  ASSERT_TRUE(tools::arm_fault_plan(demo, clock_hz(), error)) << error;
  (void)bsp::run_for(cycles(tools::demo_fault_plan_end_s() + 0.01));
  const std::span<const bsp::FaultRecord> log = bsp::fault_log();
  ASSERT_EQ(log.size(), demo.items.size());
  for (const bsp::FaultRecord& r : log) {
    EXPECT_NE(r.status, bsp::FaultStatus::kUnsupported) << tools::describe_fault(r);
    EXPECT_NE(r.status, bsp::FaultStatus::kSkipped) << tools::describe_fault(r);
    EXPECT_FALSE(r.random);
  }
  const bsp::FaultRecord* sw = record_of(bsp::FaultKind::kSwitchFail, kDemo.failed_switch);
  ASSERT_NE(sw, nullptr);
  EXPECT_EQ(sw->status, bsp::FaultStatus::kApplied);
  EXPECT_EQ(sw->applied_cycle, cycles(20.0));
  // No tile sent anything: the flips stay armed, and the log says so.
  tools::EventLog events(32U);
  EXPECT_EQ(tools::log_injections(log, clock_hz(), events), 1U);
  EXPECT_EQ(events.count(tools::EventCategory::kInfo), 8U);
}

TEST(FaultPlanArm, RatesDrawRandomFaults) {
  init_board();
  tools::FaultPlan p;
  p.rates[static_cast<std::size_t>(bsp::FaultKind::kSwitchFail)] = 1.0;  // 64 tiles: about 64 per second
  std::string error;
  ASSERT_TRUE(tools::arm_fault_plan(p, clock_hz(), error)) << error;
  (void)bsp::run_for(cycles(0.5));
  const std::span<const bsp::FaultRecord> log = bsp::fault_log();
  EXPECT_GT(log.size(), 10U);
  EXPECT_LT(log.size(), 70U);
  for (const bsp::FaultRecord& r : log) {
    EXPECT_TRUE(r.random);
    EXPECT_EQ(r.spec.kind, bsp::FaultKind::kSwitchFail);
  }
}

TEST(FaultPlanArm, RefusedItemsAreNamed) {
  init_board();
  tools::FaultPlan p;
  p.name = "bad";
  tools::FaultPlanItem it{};
  it.t_s = 1.0;
  it.kind = bsp::FaultKind::kSeu;
  it.tile = 70U;
  p.items.push_back(it);
  std::string error;
  EXPECT_FALSE(tools::arm_fault_plan(p, clock_hz(), error));
  EXPECT_NE(error.find("fault plan bad: fault #1 (seu on tile 70 at 1 s): the board has no such tile (tiles 0 .. 63)"),
            std::string::npos)
      << error;
  p.items[0].tile = 20U;
  p.items[0].kind = bsp::FaultKind::kLinkFail;
  p.items[0].param = 9U;
  EXPECT_FALSE(tools::arm_fault_plan(p, clock_hz(), error));
  EXPECT_NE(error.find("invalid link direction 9"), std::string::npos) << error;
}

}  // namespace
