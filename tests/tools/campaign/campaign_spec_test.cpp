/**
 * @file campaign_spec_test.cpp
 * @brief Campaign specs validated key by key, each run's plan drawn from (seed, index) alone and accepted by the
 *        fault-plan parser, the outcome rules, and shard names (docs/CAMPAIGNS.md).
 */
#include "build_info.hpp"
#include "tools/common/campaign/campaign.hpp"
#include "tools/common/mission/fault_plan.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <set>
#include <string>
#include <vector>

namespace {

namespace cp = tools::campaign;

constexpr double kRunS = 46.0;

cp::SpecResult parse(const std::string& text) { return cp::parse_spec(text, "spec.toml", kRunS); }

const std::string kValid = R"(
name = "t"
campaign_seed = 9
runs = 50
faults_per_run = 2
window_s = [5.0, 20.0]
kinds = ["core_hang", "core_reset", "sdc", "seu", "packet_bit_flip", "switch_fail", "link_fail", "watchdog_fail"]
roles = ["trn_supervisor", "vision_coordinator", "io", "filter", "vision", "filter_replica"]
tiles = [27, 35]

[[command]]
t_s = 3.0
name = "reliability_high"
)";

TEST(CampaignSpec, AValidSpecIsReadWithItsDefaults) {
  const cp::SpecResult r = parse(kValid);
  ASSERT_TRUE(r.ok()) << r.error;
  EXPECT_EQ(r.spec.name, "t");
  EXPECT_EQ(r.spec.runs, 50U);
  EXPECT_EQ(r.spec.faults_per_run, 2U);
  EXPECT_EQ(r.spec.kinds.size(), 8U);
  EXPECT_EQ(r.spec.roles.size(), 6U);
  EXPECT_EQ(r.spec.tiles.size(), 2U);
  EXPECT_DOUBLE_EQ(r.spec.window_lo_s, 5.0);
  EXPECT_DOUBLE_EQ(r.spec.window_hi_s, 20.0);
  EXPECT_DOUBLE_EQ(r.spec.pass_bound_m, 2.0);
  EXPECT_DOUBLE_EQ(r.spec.degraded_bound_m, 20.0);
  EXPECT_EQ(r.spec.seed, 1U);
  ASSERT_EQ(r.spec.commands.size(), 1U);
  EXPECT_EQ(r.spec.commands[0].name, "reliability_high");
}

// A campaign on Maestro draws its plans for Maestro's deployment: a vision instance among its 35
// vision tiles, a tile on its 49; a spec without a chip flies its scenario's.
TEST(CampaignSpec, AChipDrawsThePlansForItsDeployment) {
  const cp::SpecResult r = parse("chip = \"maestro\"\n" + kValid);
  ASSERT_TRUE(r.ok()) << r.error;
  EXPECT_EQ(r.spec.chip, "maestro");
  EXPECT_EQ(&cp::spec_deployment(r.spec), &trn::tasks::kMaestroDeployment);
  EXPECT_EQ(&cp::spec_deployment(parse(kValid).spec), &trn::tasks::kTile64Deployment);
  std::uint32_t vision = 0;
  for (std::uint32_t i = 0; i < 200U; ++i) {
    const cp::DrawnPlan d = cp::draw_plan(r.spec, i, 49U, kRunS);
    ASSERT_TRUE(d.error.empty()) << d.error;
    const std::string key = "role = \"vision\"\ninstance = ";
    const std::size_t at = d.toml.find(key);
    if (at != std::string::npos) {
      ++vision;
      EXPECT_LT(std::stoul(d.toml.substr(at + key.size())), 35U) << d.toml;
    }
    EXPECT_NE(d.toml.find("--chip maestro"), std::string::npos) << "the plan says how to fly it again";
  }
  EXPECT_GT(vision, 10U);
  const cp::SpecResult bad = parse("chip = \"tile36\"\n" + kValid);
  EXPECT_NE(bad.error.find("chip: \"tile36\": no such chip (allowed: tile64, maestro)"), std::string::npos)
      << bad.error;
  const cp::SpecResult maestro =
      cp::load_spec(std::string(build_info::kRepoRoot) + "/campaigns/maestro_single_100.toml", kRunS);
  ASSERT_TRUE(maestro.ok()) << maestro.error;
  EXPECT_EQ(maestro.spec.chip, "maestro");
  const cp::SpecResult plain =
      cp::load_spec(std::string(build_info::kRepoRoot) + "/campaigns/single_late_100.toml", kRunS);
  ASSERT_TRUE(plain.ok()) << plain.error;
  EXPECT_EQ(plain.spec.chip, "tile64") << "the built-in scenario's chip";
}

TEST(CampaignSpec, EveryBadKeyIsNamedWithWhatIsAllowed) {
  const cp::SpecResult r = parse(R"(
name = "t"
runs = 0
kinds = ["core_hang", "melt"]
roles = ["pilot"]
window_s = [30.0, 10.0]
pass_bound_m = 5.0
degraded_bound_m = 1.0
colour = "red"
)");
  ASSERT_FALSE(r.ok());
  for (const char* e : {"spec.toml: unknown key colour (allowed: name, scenario,",
                        "spec.toml: runs: 0 is out of range: allowed 1 ..",
                        "spec.toml: kinds: element 1: unknown fault kind \"melt\" (allowed: core_hang,",
                        "spec.toml: roles: element 0: unknown role \"pilot\" (allowed: trn_supervisor,",
                        "spec.toml: window_s: the end must come after the start",
                        "spec.toml: degraded_bound_m (1 m) is below pass_bound_m (5 m)"}) {
    EXPECT_NE(r.error.find(e), std::string::npos) << "missing: " << e << "\nin:\n" << r.error;
  }
}

TEST(CampaignSpec, MissingKeysAndAWindowBeyondTheRunAreErrors) {
  const cp::SpecResult r = parse("kinds = []\nwindow_s = [1.0, 50.0]\n");
  ASSERT_FALSE(r.ok());
  for (const char* e : {"missing key name", "missing key runs", "no target: give roles, tiles or both",
                        "window_s: 50 is out of range: allowed 0 .. 46 s (the run's duration)"}) {
    EXPECT_NE(r.error.find(e), std::string::npos) << "missing: " << e << "\nin:\n" << r.error;
  }
  const cp::SpecResult syntax = parse("name = \n");
  ASSERT_FALSE(syntax.ok());
  EXPECT_NE(syntax.error.find("spec.toml:1:"), std::string::npos) << syntax.error;
}

// A run's plan depends on (campaign_seed, index) only: the same twice, another for another index or
// seed; every drawn plan is one the fault-plan parser takes, with its faults inside the window.
// The same text the scenario fuzzer found (tests/tools/scenario): toml++ asserted on it.
TEST(CampaignSpec, ATableHeaderTheTomlParserCannotReadIsASyntaxErrorNotAnAbort) {
  const cp::SpecResult r = parse("[[[1]]]\n");
  EXPECT_FALSE(r.ok());
  EXPECT_EQ(r.error.rfind("spec.toml:", 0), 0U) << r.error;
  EXPECT_NE(r.error.find("TOML syntax error"), std::string::npos) << r.error;
}

TEST(CampaignSpec, PlansAreDrawnFromSeedAndIndexAndAreValidPlans) {
  const cp::SpecResult r = parse(kValid);
  ASSERT_TRUE(r.ok()) << r.error;
  std::set<std::string> kinds;
  std::set<std::string> texts;
  for (std::uint32_t i = 0; i < r.spec.runs; ++i) {
    const cp::DrawnPlan a = cp::draw_plan(r.spec, i, 64U, kRunS);
    ASSERT_TRUE(a.error.empty()) << a.error;
    EXPECT_EQ(cp::draw_plan(r.spec, i, 64U, kRunS).toml, a.toml) << "run " << i;
    texts.insert(a.toml);
    kinds.insert(a.kind);
    const tools::FaultPlanResult p = tools::parse_fault_plan(a.toml, "run", 64U, kRunS);
    ASSERT_TRUE(p.ok()) << p.error << "\n" << a.toml;
    ASSERT_EQ(p.plan->items.size(), 2U);
    ASSERT_EQ(p.plan->commands.size(), 1U) << "the spec's command in every plan";
    for (const tools::FaultPlanItem& it : p.plan->items) {
      EXPECT_GE(it.t_s, 5.0);
      EXPECT_LE(it.t_s, 20.0);
    }
  }
  EXPECT_EQ(texts.size(), r.spec.runs) << "each run its own plan";
  EXPECT_TRUE(kinds.count("mixed") > 0U) << "two faults of different kinds make a mixed run";
  cp::Spec other = r.spec;
  other.campaign_seed = 10U;
  EXPECT_NE(cp::draw_plan(other, 0U, 64U, kRunS).toml, cp::draw_plan(r.spec, 0U, 64U, kRunS).toml);
}

// Each run records the target it drew, for coverage per role: a single fault's role (or "tile_<n>" for a
// tile target), the common one of several faults, else "mixed"; "none" without faults. The draws stay
// those of (campaign_seed, index): the plan text is the same with the role recorded.
TEST(CampaignSpec, TheTargetOfEachRunIsRecordedWithItsPlan) {
  const cp::SpecResult one = parse("name = \"t\"\nruns = 40\nkinds = [\"core_hang\"]\nroles = [\"filter\", \"io\"]\n"
                                   "tiles = [27]\n");
  ASSERT_TRUE(one.ok()) << one.error;
  std::set<std::string> roles;
  for (std::uint32_t i = 0; i < one.spec.runs; ++i) {
    const cp::DrawnPlan d = cp::draw_plan(one.spec, i, 64U, kRunS);
    ASSERT_TRUE(d.error.empty()) << d.error;
    roles.insert(d.role);
    const std::string named = d.role == "tile_27" ? "tile = 27" : "role = \"" + d.role + "\"";
    EXPECT_NE(d.toml.find(named), std::string::npos) << d.role << "\n" << d.toml;
  }
  EXPECT_EQ(roles, (std::set<std::string>{"filter", "io", "tile_27"}));

  const cp::SpecResult two = parse(kValid);
  ASSERT_TRUE(two.ok()) << two.error;
  std::set<std::string> multi;
  for (std::uint32_t i = 0; i < two.spec.runs; ++i) {
    const cp::DrawnPlan d = cp::draw_plan(two.spec, i, 64U, kRunS);
    ASSERT_TRUE(d.error.empty()) << d.error;
    const tools::FaultPlanResult p = tools::parse_fault_plan(d.toml, "run", 64U, kRunS);
    ASSERT_TRUE(p.ok()) << p.error;
    const auto target = [](const tools::FaultPlanItem& it) {
      return it.role.empty() ? "tile_" + std::to_string(it.tile) : it.role;
    };
    const std::string a = target(p.plan->items[0]);
    const std::string b = target(p.plan->items[1]);
    EXPECT_EQ(d.role, a == b ? a : std::string("mixed")) << d.toml;
    multi.insert(d.role);
  }
  EXPECT_TRUE(multi.count("mixed") > 0U);
  const cp::SpecResult sweep = parse("name = \"s\"\nfaults_per_run = 0\nruns = 1\n");
  ASSERT_TRUE(sweep.ok()) << sweep.error;
  EXPECT_EQ(cp::draw_plan(sweep.spec, 0U, 64U, kRunS).role, "none");
}

// A target no draw can hit (an sdc on a spare tile, which publishes nothing) is refused after the
// draws, naming the run and the parser's reason.
TEST(CampaignSpec, APlanNoDrawCanMakeValidIsAnError) {
  const cp::SpecResult r = parse("name = \"t\"\nruns = 1\nkinds = [\"sdc\"]\ntiles = [2]\n");
  ASSERT_TRUE(r.ok()) << r.error;
  const cp::DrawnPlan d = cp::draw_plan(r.spec, 0U, 64U, kRunS);
  EXPECT_TRUE(d.toml.empty());
  EXPECT_NE(d.error.find("run 0: no valid plan in 64 draws"), std::string::npos) << d.error;
}

// Points and carves narrow what an sdc or an seu hits: every drawn plan names one of them.
TEST(CampaignSpec, PointsAndCarvesNarrowTheDraws) {
  const cp::SpecResult r = parse("name = \"t\"\nruns = 40\nkinds = [\"sdc\", \"seu\"]\nroles = [\"filter\"]\n"
                                 "points = [\"filter_state\", \"nav_output\"]\ncarves = [\"ekf\"]\n");
  ASSERT_TRUE(r.ok()) << r.error;
  std::set<double> positions;
  std::size_t upsets = 0U;
  for (std::uint32_t i = 0; i < r.spec.runs; ++i) {
    const cp::DrawnPlan d = cp::draw_plan(r.spec, i, 64U, kRunS);
    ASSERT_TRUE(d.error.empty()) << d.error;
    const tools::FaultPlanResult p = tools::parse_fault_plan(d.toml, "run", 64U, kRunS);
    ASSERT_TRUE(p.ok()) << p.error;
    const tools::FaultPlanItem& it = p.plan->items[0];
    if (it.kind == bsp::FaultKind::kSeu) {
      EXPECT_EQ(it.carve, "ekf") << d.toml;
      EXPECT_GE(it.position, 0.0) << "the campaign says where the byte is: " << d.toml;
      positions.insert(it.position);
      ++upsets;
    } else {
      EXPECT_TRUE(it.channel == 1U || it.channel == 2U) << "nav_output or filter_state\n" << d.toml;
    }
  }
  EXPECT_GT(upsets, 5U);
  EXPECT_EQ(positions.size(), upsets) << "each run's upset at its own place (the injector's stream gives one)";
  const cp::SpecResult bad = parse("name = \"t\"\nruns = 1\nkinds = [\"sdc\"]\nroles = [\"filter\"]\npoints = [\"x\"]\n");
  EXPECT_NE(bad.error.find("points: element 0: unknown point \"x\""), std::string::npos) << bad.error;
}

// same_time: every fault of a run at one drawn time (faults in the same job); the times differ from run
// to run, the targets are drawn as usual; without it the faults of a run fall at their own times, the
// plans those campaigns always drew. Refused in a fault-free campaign and when not a boolean.
TEST(CampaignSpec, SameTimePutsEveryFaultOfARunAtOneTime) {
  const std::string spec = "name = \"t\"\nruns = 20\nfaults_per_run = 3\nkinds = [\"sdc\"]\n"
                           "roles = [\"filter_replica\"]\nwindow_s = [5.0, 40.0]\n";
  const cp::SpecResult same = parse(spec + "same_time = true\n");
  const cp::SpecResult apart = parse(spec);
  ASSERT_TRUE(same.ok()) << same.error;
  ASSERT_TRUE(apart.ok()) << apart.error;
  EXPECT_TRUE(same.spec.same_time);
  EXPECT_FALSE(apart.spec.same_time);
  std::set<double> run_times;
  std::size_t apart_runs_at_one_time = 0U;
  for (std::uint32_t i = 0; i < same.spec.runs; ++i) {
    for (const cp::SpecResult* r : {&same, &apart}) {
      const cp::DrawnPlan d = cp::draw_plan(r->spec, i, 64U, kRunS);
      ASSERT_TRUE(d.error.empty()) << d.error;
      const tools::FaultPlanResult p = tools::parse_fault_plan(d.toml, "run", 64U, kRunS);
      ASSERT_TRUE(p.ok()) << p.error;
      ASSERT_EQ(p.plan->items.size(), 3U);
      std::set<double> times;
      for (const tools::FaultPlanItem& it : p.plan->items) {
        times.insert(it.t_s);
        EXPECT_GE(it.t_s, 5.0);
        EXPECT_LE(it.t_s, 40.0);
      }
      if (r == &same) {
        EXPECT_EQ(times.size(), 1U) << d.toml;
        run_times.insert(*times.begin());
      } else if (times.size() == 1U) {
        ++apart_runs_at_one_time;
      }
    }
  }
  EXPECT_GT(run_times.size(), 15U) << "each run its own time";
  EXPECT_EQ(apart_runs_at_one_time, 0U);
  EXPECT_NE(parse(spec + "same_time = 1\n").error.find("same_time: wrong type: expected true or false"),
            std::string::npos);
  EXPECT_NE(parse("name = \"t\"\nruns = 2\nfaults_per_run = 0\nsame_time = true\n")
                .error.find("same_time: faults_per_run is 0"),
            std::string::npos);
}

// ------------------------------------------------------------------ CMP-07 outcome classes

constexpr double kPass = 2.0;
constexpr double kLoose = 20.0;

/** A run that flew one fault to the chip, nothing detected, the stream changed, 0.5 m off: masked. */
cp::RunFacts delivered() {
  cp::RunFacts f;
  f.exited_ok = true;
  f.final_error_m = 0.5;
  f.injected = 1U;
  return f;
}

/** @p f with @p det faults detected and @p rec recovered. */
cp::RunFacts detected(cp::RunFacts f, std::uint32_t det, std::uint32_t rec) {
  f.detected = det;
  f.recovered = rec;
  return f;
}

cp::Outcome cls(const cp::RunFacts& f) { return cp::classify(f, kPass, kLoose); }

// CMP-07: one run per class, each built from the facts the rules read (docs/CAMPAIGNS.md, "Outcome classes").
TEST(CampaignSpec, OutcomesFollowTheWrittenRules) {
  cp::RunFacts crash = delivered();
  crash.exited_ok = false;
  EXPECT_EQ(cls(crash), cp::Outcome::kCrash) << "no summary: a crash or a hang";
  cp::RunFacts none = delivered();
  none.injected = 0U;
  none.not_delivered = 1U;
  EXPECT_EQ(cls(none), cp::Outcome::kNotDelivered) << "armed, but no fault reached the chip";
  cp::RunFacts same = delivered();
  same.output_as_golden = true;
  EXPECT_EQ(cls(same), cp::Outcome::kNoEffect) << "the delivered stream is the fault-free one";
  EXPECT_EQ(cls(delivered()), cp::Outcome::kMasked) << "the stream changed, within the pass bound";
  cp::RunFacts wrong = delivered();
  wrong.final_error_m = 5.0;
  EXPECT_EQ(cls(wrong), cp::Outcome::kSdc) << "wrong beyond the bound, nothing detected";
  cp::RunFacts lost = delivered();
  lost.mission_lost = true;
  EXPECT_EQ(cls(lost), cp::Outcome::kSdc) << "lost, nothing detected";
  EXPECT_EQ(cls(detected(delivered(), 1, 1)), cp::Outcome::kRecovered);
  EXPECT_EQ(cls(detected(delivered(), 2, 1)), cp::Outcome::kDegraded) << "correct, but not every detection recovered";
  EXPECT_EQ(cls(detected(wrong, 1, 1)), cp::Outcome::kDegraded) << "within the looser bound";
  cp::RunFacts far = delivered();
  far.final_error_m = 25.0;
  EXPECT_EQ(cls(detected(far, 1, 1)), cp::Outcome::kLost);
  EXPECT_EQ(cls(detected(lost, 1, 1)), cp::Outcome::kLost);
}

// CMP-07: the bounds are inclusive; a final error that is not finite (navigation lost) is beyond both.
TEST(CampaignSpec, TheBoundsAreInclusive) {
  cp::RunFacts f = delivered();
  f.final_error_m = kPass;
  EXPECT_EQ(cls(f), cp::Outcome::kMasked);
  EXPECT_EQ(cls(detected(f, 1, 1)), cp::Outcome::kRecovered);
  f.final_error_m = std::nextafter(kPass, 100.0);
  EXPECT_EQ(cls(f), cp::Outcome::kSdc);
  EXPECT_EQ(cls(detected(f, 1, 1)), cp::Outcome::kDegraded);
  f.final_error_m = kLoose;
  EXPECT_EQ(cls(detected(f, 1, 1)), cp::Outcome::kDegraded);
  f.final_error_m = std::nextafter(kLoose, 100.0);
  EXPECT_EQ(cls(detected(f, 1, 1)), cp::Outcome::kLost);
  f.final_error_m = std::numeric_limits<double>::infinity();
  EXPECT_EQ(cls(f), cp::Outcome::kSdc);
  EXPECT_EQ(cls(detected(f, 1, 1)), cp::Outcome::kLost);
}

// CMP-07: not_delivered is a run whose image flew but whose faults all stayed armed; it comes before the
// error and the detections (nothing tested can have caused them), and after a crash (no summary to say so).
TEST(CampaignSpec, NotDeliveredIsARunNoFaultReached) {
  cp::RunFacts f = delivered();
  f.injected = 0U;
  f.not_delivered = 2U;
  EXPECT_EQ(cls(f), cp::Outcome::kNotDelivered);
  f.final_error_m = 50.0;
  EXPECT_EQ(cls(f), cp::Outcome::kNotDelivered) << "the filter's own error, no fault's";
  EXPECT_EQ(cls(detected(f, 1, 0)), cp::Outcome::kNotDelivered) << "an accusation without a fault: a false alarm";
  f.output_as_golden = true;
  EXPECT_EQ(cls(f), cp::Outcome::kNotDelivered);
  f.exited_ok = false;
  EXPECT_EQ(cls(f), cp::Outcome::kCrash);
  cp::RunFacts some = delivered();
  some.not_delivered = 1U;
  EXPECT_EQ(cls(some), cp::Outcome::kMasked) << "one fault of two delivered: judged as any run";
  cp::RunFacts fault_free = delivered();
  fault_free.injected = 0U;
  EXPECT_EQ(cls(fault_free), cp::Outcome::kMasked) << "nothing armed (a fault-free campaign) is not not_delivered";
  fault_free.output_as_golden = true;
  EXPECT_EQ(cls(fault_free), cp::Outcome::kNoEffect);
}

// CMP-07: with nothing detected, the stream's CRC against the golden run's tells no_effect (bit for bit the
// fault-free stream) from masked (changed, still correct) and sdc (changed, wrong); with a detection the
// CRC does not matter.
TEST(CampaignSpec, NoEffectAndMaskedAreToldApartByTheStreamsCrc) {
  cp::RunFacts f = delivered();
  f.output_as_golden = true;
  EXPECT_EQ(cls(f), cp::Outcome::kNoEffect);
  f.output_as_golden = false;
  EXPECT_EQ(cls(f), cp::Outcome::kMasked);
  f.final_error_m = 3.0;
  EXPECT_EQ(cls(f), cp::Outcome::kSdc);
  cp::RunFacts d = detected(delivered(), 1, 1);
  d.output_as_golden = true;
  EXPECT_EQ(cls(d), cp::Outcome::kRecovered) << "a detection is never no_effect";
}

// CMP-07: detected_recovered needs every detection recovered, exactly, and none by giving up a mode.
TEST(CampaignSpec, ARecoveryThatGaveUpAModeIsDegraded) {
  cp::RunFacts f = detected(delivered(), 2, 2);
  EXPECT_EQ(cls(f), cp::Outcome::kRecovered);
  f.degraded_accepted = 1U;
  EXPECT_EQ(cls(f), cp::Outcome::kDegraded) << "TMR to simplex: the mission goes on with less";
  EXPECT_EQ(cls(detected(delivered(), 1, 2)), cp::Outcome::kDegraded) << "more recoveries than detections";
  EXPECT_EQ(cls(detected(delivered(), 2, 0)), cp::Outcome::kDegraded);
  cp::RunFacts far = detected(delivered(), 1, 1);
  far.final_error_m = 25.0;
  far.degraded_accepted = 1U;
  EXPECT_EQ(cls(far), cp::Outcome::kLost) << "not kept is lost, whatever the recovery";
}

// CMP-07: the flags (a wrong diagnosis, a false alarm, a healthy tile disturbed) are carried beside the
// class and never change it, in any class.
TEST(CampaignSpec, FlagsDoNotChangeTheClass) {
  std::vector<cp::RunFacts> cases;
  cp::RunFacts crash = delivered();
  crash.exited_ok = false;
  cp::RunFacts none = delivered();
  none.injected = 0U;
  none.not_delivered = 1U;
  cp::RunFacts same = delivered();
  same.output_as_golden = true;
  cp::RunFacts wrong = delivered();
  wrong.final_error_m = 5.0;
  cp::RunFacts far = delivered();
  far.final_error_m = 25.0;
  cases = {crash, none, same, delivered(), wrong, detected(delivered(), 1, 1), detected(wrong, 1, 1),
           detected(far, 1, 1)};
  std::set<cp::Outcome> seen;
  for (const cp::RunFacts& c : cases) {
    const cp::Outcome plain = cls(c);
    seen.insert(plain);
    for (int flag = 0; flag < 3; ++flag) {
      cp::RunFacts flagged = c;
      (flag == 0 ? flagged.misdiagnosed : flag == 1 ? flagged.false_alarms : flagged.healthy_disturbed) = 3U;
      EXPECT_EQ(cls(flagged), plain) << cp::outcome_name(plain) << ", flag " << flag;
    }
  }
  EXPECT_EQ(seen.size(), cp::kOutcomeCount) << "every class was among the cases";
}

TEST(CampaignSpec, ShardsAreIOverN) {
  std::uint32_t i = 9U;
  std::uint32_t n = 9U;
  ASSERT_TRUE(cp::parse_shard("1/4", i, n));
  EXPECT_EQ(i, 1U);
  EXPECT_EQ(n, 4U);
  for (const char* bad : {"4/4", "1/0", "a/2", "1/", "/2", "12", "-1/2", ""}) {
    EXPECT_FALSE(cp::parse_shard(bad, i, n)) << bad;
  }
}

// A seed sweep without faults (the integrity campaign): run i flies seed + i, its plan carries the spec's
// telecommands and no fault, and a key that only shapes fault draws is refused rather than ignored.
TEST(CampaignSpec, AFaultFreeSeedSweepFliesSeedPlusIndexAndRefusesKeysOfDraws) {
  const cp::SpecResult r = parse(
      "name = \"sweep\"\nseed = 7\nseed_per_run = true\nfaults_per_run = 0\nruns = 3\n"
      "[[command]]\nt_s = 3.0\nname = \"reliability_high\"\n");
  ASSERT_TRUE(r.ok()) << r.error;
  EXPECT_TRUE(r.spec.seed_per_run);
  EXPECT_EQ(r.spec.faults_per_run, 0U);
  EXPECT_EQ(cp::scenario_seed(r.spec, 0U), 7U);
  EXPECT_EQ(cp::scenario_seed(r.spec, 2U), 9U);
  const cp::DrawnPlan d = cp::draw_plan(r.spec, 2U, 64U, kRunS);
  ASSERT_TRUE(d.error.empty()) << d.error;
  EXPECT_EQ(d.kind, "none");
  EXPECT_NE(d.toml.find("--seed 9"), std::string::npos) << "the replay line names the run's own seed\n" << d.toml;
  const tools::FaultPlanResult p = tools::parse_fault_plan(d.toml, "run", 64U, kRunS);
  ASSERT_TRUE(p.ok()) << p.error << "\n" << d.toml;
  EXPECT_TRUE(p.plan->items.empty());
  EXPECT_EQ(p.plan->commands.size(), 1U);

  cp::Spec fixed = r.spec;
  fixed.seed_per_run = false;
  EXPECT_EQ(cp::scenario_seed(fixed, 2U), 7U) << "without seed_per_run every run flies the spec's seed";

  const cp::SpecResult bad = parse(
      "name = \"sweep\"\nfaults_per_run = 0\nruns = 3\nkinds = [\"sdc\"]\nroles = [\"filter\"]\n"
      "window_s = [1.0, 2.0]\nseed_per_run = 1\n");
  EXPECT_FALSE(bad.ok());
  for (const char* key : {"kinds", "roles", "window_s"}) {
    EXPECT_NE(bad.error.find(std::string("spec.toml: ") + key + ": faults_per_run is 0"), std::string::npos)
        << key << "\n" << bad.error;
  }
  EXPECT_NE(bad.error.find("seed_per_run: wrong type: expected true or false"), std::string::npos) << bad.error;
  const cp::SpecResult overflow =
      parse("name = \"sweep\"\nfaults_per_run = 0\nruns = 3\nseed_per_run = true\nseed = 9223372036854775806\n");
  EXPECT_NE(overflow.error.find("seed: with seed_per_run"), std::string::npos) << overflow.error;
  EXPECT_FALSE(parse("name = \"t\"\nruns = 3\n").ok()) << "faults drawn (the default 1) still need kinds";
}

TEST(CampaignSpec, TheShippedCampaignsAreValid) {
  for (const char* f : {"campaigns/single_faults.toml", "campaigns/slurm_small.toml", "campaigns/ft_single_1000.toml",
                        "campaigns/integrity_100.toml",
                        "campaigns/ft_five_300.toml", "campaigns/ft_seu_240.toml", "campaigns/ft_seu_control_40.toml",
                        "campaigns/maestro_single_100.toml", "tests/fixtures/campaigns/small.toml",
                        "tests/fixtures/campaigns/crash.toml"}) {
    const cp::SpecResult r = cp::load_spec(std::string(build_info::kRepoRoot) + "/" + f, kRunS);
    EXPECT_TRUE(r.ok()) << f << ": " << r.error;
  }
}

}  // namespace
