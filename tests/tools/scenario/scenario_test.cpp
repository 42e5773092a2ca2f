/**
 * @file scenario_test.cpp
 * @brief Scenario files: defaults, every section parsed, and clear errors (file, key, range) for bad files.
 */
#include "tools/common/mission/scenario.hpp"
#include "tools/common/toml_input.hpp"

#include "build_info.hpp"

#include <gtest/gtest.h>

#include <array>
#include <cstdio>
#include <string>
#include <sys/wait.h>
#include <unistd.h>

namespace {

std::string fixture(const std::string& name) {
  return std::string(build_info::kRepoRoot) + "/tests/fixtures/scenarios/" + name;
}

/** The error of a fixture that must fail, with the assertion that it did. */
std::string error_of(const std::string& name) {
  const tools::ScenarioResult r = tools::load_scenario(fixture(name));
  EXPECT_FALSE(r.ok()) << name << " was accepted";
  return r.error;
}

TEST(Scenario, EmptyTextGivesTheBuiltInDefaults) {
  const tools::ScenarioResult r = tools::parse_scenario("", "<empty>");
  ASSERT_TRUE(r.ok()) << r.error;
  const tools::Scenario& s = *r.scenario;
  EXPECT_EQ(s.name, "default");
  EXPECT_EQ(s.terrain.size_px, 4096U);
  EXPECT_DOUBLE_EQ(s.terrain.m_per_px, 4.0);
  EXPECT_DOUBLE_EQ(s.map.fine_m_per_px, 6.0);
  EXPECT_DOUBLE_EQ(s.map.coarse_m_per_px, 12.0);
  EXPECT_DOUBLE_EQ(s.trajectory.start_altitude_m, 4200.0);
  EXPECT_DOUBLE_EQ(s.imu.gyro_arw_dpsh, 0.07);
  EXPECT_EQ(s.camera.width_px, 1024U);
  EXPECT_DOUBLE_EQ(s.camera.fov_deg, 90.0);
  // The descent and map suns differ, as an orbital map's would.
  EXPECT_NE(s.camera.sun.azimuth_deg, s.map.sun.azimuth_deg);
}

TEST(Scenario, AFileSettingEverySectionIsParsed) {
  const tools::ScenarioResult r = tools::load_scenario(fixture("full.toml"));
  ASSERT_TRUE(r.ok()) << r.error;
  const tools::Scenario& s = *r.scenario;
  EXPECT_EQ(s.name, "fixture-full");
  EXPECT_EQ(s.seed, 42U);
  EXPECT_EQ(s.terrain.seed, 7U);
  EXPECT_EQ(s.terrain.size_px, 2048U);
  EXPECT_DOUBLE_EQ(s.terrain.crater_sfd_exponent, 2.5);
  EXPECT_DOUBLE_EQ(s.map.fine_m_per_px, 6.0);  // an integer is a valid float
  EXPECT_DOUBLE_EQ(s.map.sun.azimuth_deg, 200.0);
  EXPECT_DOUBLE_EQ(s.trajectory.end_altitude_m, 1500.0);
  EXPECT_TRUE(s.imu.enabled);
  EXPECT_DOUBLE_EQ(s.imu.gyro_arw_dpsh, 0.1);
  EXPECT_DOUBLE_EQ(s.imu.gyro_bias_in_run_dph, 0.35);  // untouched keys keep defaults
  EXPECT_EQ(s.camera.width_px, 512U);
  EXPECT_DOUBLE_EQ(s.camera.rate_hz, 2.0);
  EXPECT_TRUE(s.camera.blur);
  EXPECT_DOUBLE_EQ(s.initial_error.position_m, 3000.0);
  // The parsed configuration is one the models accept.
  bsp::world::Trajectory t;
  EXPECT_EQ(t.init(s.trajectory), bsp::world::WorldError::kOk);
}

TEST(Scenario, UnknownKeyIsNamedWithTheAllowedKeys) {
  const std::string e = error_of("unknown_key.toml");
  EXPECT_NE(e.find("unknown_key.toml"), std::string::npos) << e;
  EXPECT_NE(e.find("[terrain] crater_count: unknown key"), std::string::npos) << e;
  EXPECT_NE(e.find("crater_density_per_km2"), std::string::npos) << e;
}

TEST(Scenario, UnknownSectionIsRejected) {
  const std::string e = error_of("unknown_section.toml");
  EXPECT_NE(e.find("[lidar]: unknown section"), std::string::npos) << e;
}

TEST(Scenario, WrongTypesAreRejectedWithTheExpectedType) {
  std::string e = error_of("wrong_type.toml");
  EXPECT_NE(e.find("wrong_type.toml: [camera] width_px: wrong type: expected an integer"), std::string::npos) << e;
  e = error_of("float_for_integer.toml");
  EXPECT_NE(e.find("[terrain] size_px: wrong type: expected an integer"), std::string::npos) << e;
}

TEST(Scenario, TheChipIsTheTile64ByDefaultAndMaestroWhenNamed) {
  EXPECT_EQ(tools::default_scenario().chip, "tile64");
  const tools::ScenarioResult m = tools::parse_scenario("[scenario]\nchip = \"maestro\"\n", "<chip>");
  ASSERT_TRUE(m.ok()) << m.error;
  EXPECT_EQ(m.scenario->chip, "maestro");
  const tools::ScenarioResult bad = tools::parse_scenario("[scenario]\nchip = \"tile36\"\n", "c.toml");
  ASSERT_FALSE(bad.ok());
  EXPECT_NE(bad.error.find("c.toml: [scenario] chip: \"tile36\": no such chip (allowed: tile64, maestro)"),
            std::string::npos)
      << bad.error;
  const tools::ScenarioResult number = tools::parse_scenario("[scenario]\nchip = 64\n", "n.toml");
  ASSERT_FALSE(number.ok());
  EXPECT_NE(number.error.find("[scenario] chip: wrong type: expected a string"), std::string::npos) << number.error;
  EXPECT_TRUE(tools::chip_known("maestro"));
  EXPECT_FALSE(tools::chip_known("Maestro"));
}

TEST(Scenario, OutOfRangeValuesNameTheAllowedRange) {
  const std::string e = error_of("out_of_range.toml");
  EXPECT_NE(e.find("out_of_range.toml: [camera] rate_hz: 5 is out of range: allowed 1 .. 2"), std::string::npos)
      << e;
}

TEST(Scenario, SyntaxErrorsGiveFileLineAndColumn) {
  const std::string e = error_of("syntax_error.toml");
  EXPECT_NE(e.find("syntax_error.toml:3:"), std::string::npos) << e;
  EXPECT_NE(e.find("TOML syntax error"), std::string::npos) << e;
}

// Found by tests/fuzz/scenario_fuzz.cpp: a table header starting with a character no key starts
// with broke an assertion inside toml++ 3.3.0 and aborted the program; it is a syntax error.
TEST(Scenario, ATableHeaderTheTomlParserCannotReadIsASyntaxErrorNotAnAbort) {
  for (const std::string& text : {std::string("[:dar0\0\0\0]\nrange_m 5.0\n", 23), std::string("[:a]\n"),
                                 std::string("[[[1]]]\n"), std::string("seed = 3\n[[:x]]\n")}) {
    const tools::ScenarioResult r = tools::parse_scenario(text, "fuzz.toml");
    EXPECT_FALSE(r.ok());
    EXPECT_EQ(r.error.rfind("fuzz.toml", 0), 0U) << r.error;
    EXPECT_NE(r.error.find("TOML syntax error"), std::string::npos) << r.error;
  }
}

// Found by tests/fuzz/fault_plan_fuzz.cpp and scenario_fuzz.cpp: toml++ 3.3.0 asks whether a
// character is whitespace wherever it looks for whitespace or a value's end, and for most
// characters that are not ASCII its table reached an "unreachable" branch (undefined behaviour).
TEST(Scenario, ACharacterTheTomlParserCannotClassifyIsRefusedWithItsLine) {
  for (const std::string& text :
       {std::string("seed = 3\n[[phase]]\xD0\x92\n"), std::string("seed = 3 \xC2\xA1\n"),
        std::string("[t0n]\nsize_px = 00ml.[tBB''='Bsize\xC8\xBD\n"), std::string("# \xC2\xB0 in a comment\n")}) {
    const tools::ScenarioResult r = tools::parse_scenario(text, "u.toml");
    EXPECT_FALSE(r.ok());
    EXPECT_EQ(r.error.rfind("u.toml:", 0), 0U) << r.error;
    EXPECT_NE(r.error.find("TOML parser cannot read"), std::string::npos) << r.error;
  }
  EXPECT_NE(tools::parse_scenario("x = 1\n[[phase]]\xD0\x92\n", "u.toml").error.find("u.toml:2:"), std::string::npos);
  // Other characters that are not ASCII are read as before, a byte order mark too.
  const tools::ScenarioResult ok = tools::parse_scenario(
      "\xEF\xBB\xBF# \xE2\x80\x94 comment \xE4\xB8\xAD\n[scenario]\nname = \"\xE2\x80\x94 \xE4\xB8\xAD\"\n", "u.toml");
  EXPECT_TRUE(ok.ok()) << ok.error;
}

/** toml++ 3.3.0's is_non_ascii_horizontal_whitespace(), reduced to whether it has an answer for @p c. */
bool toml_has_answer(std::uint32_t c) {
  if (c < 0xA0U || c > 0xFEFFU) {
    return true;
  }
  const std::uint32_t block = (c - 0xA0U) / 0x3FAU;
  if (((1ULL << block) & 0x7FFFFFFFFFFFF75EULL) != 0U || c == 0xA0U || c == 0x3000U || c == 0xFEFFU) {
    return true;
  }
  return block == 5U || block == 7U;  // the switch's cases; any other block is its "unreachable" default
}

std::string utf8(std::uint32_t c) {
  std::string s;
  if (c < 0x800U) {
    s += static_cast<char>(0xC0U | (c >> 6U));
  } else if (c < 0x10000U) {
    s += static_cast<char>(0xE0U | (c >> 12U));
    s += static_cast<char>(0x80U | ((c >> 6U) & 0x3FU));
  } else {
    s += static_cast<char>(0xF0U | (c >> 18U));
    s += static_cast<char>(0x80U | ((c >> 12U) & 0x3FU));
    s += static_cast<char>(0x80U | ((c >> 6U) & 0x3FU));
  }
  s += static_cast<char>(0x80U | (c & 0x3FU));
  return s;
}

TEST(Scenario, EveryCodePointTheTomlParserHasNoAnswerForIsRefusedAndNoOther) {
  for (std::uint32_t c = 0x80U; c < 0x110000U; ++c) {
    if (c >= 0xD800U && c <= 0xDFFFU) {
      continue;  // surrogates: not UTF-8
    }
    const std::string text = "# " + utf8(c) + "\n";
    ASSERT_EQ(tools::detail::toml_unsafe_line(text) != 0U, !toml_has_answer(c)) << std::hex << "U+" << c;
  }
}

TEST(Scenario, InconsistentKeysAreRejected) {
  const std::string e = error_of("inconsistent.toml");
  EXPECT_NE(e.find("[trajectory] end_altitude_m: must be below start_altitude_m"), std::string::npos) << e;
}

TEST(Scenario, MissingFileIsNamed) {
  const std::string e = error_of("does_not_exist.toml");
  EXPECT_NE(e.find("does_not_exist.toml: cannot open scenario file"), std::string::npos) << e;
}

TEST(Scenario, EveryKeyIsDocumentedInScenarioMd) {
  std::FILE* f = std::fopen((std::string(build_info::kRepoRoot) + "/docs/SCENARIO.md").c_str(), "r");
  ASSERT_NE(f, nullptr) << "docs/SCENARIO.md missing";
  std::string doc;
  std::array<char, 4096> buf{};
  std::size_t n = 0;
  while ((n = std::fread(buf.data(), 1, buf.size(), f)) > 0) {
    doc.append(buf.data(), n);
  }
  std::fclose(f);
  for (const tools::ScenarioKeyDoc& k : tools::scenario_keys()) {
    EXPECT_NE(doc.find("| `" + k.key + "` | " + k.type + " | " + k.range + " | " + k.default_value + " |"),
              std::string::npos)
        << "[" << k.section << "] " << k.key << " is not documented as generated";
  }
}

/** world_view beside this test binary (programs in $(BIN), tests in $(BIN)/tests). */
std::string world_view_path() {
  std::array<char, 4096> self{};
  const ssize_t n = readlink("/proc/self/exe", self.data(), self.size() - 1);
  std::string dir = n > 0 ? std::string(self.data(), static_cast<std::size_t>(n)) : std::string();
  dir = dir.substr(0, dir.rfind('/'));
  return dir.substr(0, dir.rfind('/')) + "/world_view";
}

int run_status(const std::string& cmd) {
  const int rc = std::system(cmd.c_str());
  return WIFEXITED(rc) ? WEXITSTATUS(rc) : -1;
}

TEST(Scenario, TheViewerExitsWithStatusTwoOnEveryBadFile) {
  const std::string exe = world_view_path();
  ASSERT_EQ(access(exe.c_str(), X_OK), 0) << exe << " not built (make builds programs before tests)";
  for (const char* bad : {"unknown_key.toml", "unknown_section.toml", "wrong_type.toml", "out_of_range.toml",
                          "syntax_error.toml", "inconsistent.toml", "does_not_exist.toml"}) {
    EXPECT_EQ(run_status(exe + " --frame '' --scenario " + fixture(bad) + " 2>/dev/null"), 2) << bad;
  }
  EXPECT_EQ(run_status(exe + " --time -1 2>/dev/null"), 2);
  EXPECT_EQ(run_status(exe + " --layer medium 2>/dev/null"), 2);
}

}  // namespace

namespace {

TEST(Scenario, TheBuiltInPhasesAreApproachTrnAndTerminal) {
  const tools::ScenarioResult r = tools::parse_scenario("", "<empty>");
  ASSERT_TRUE(r.ok()) << r.error;
  ASSERT_EQ(r.scenario->phases.size(), 3U);
  EXPECT_EQ(r.scenario->phases[0].name, "approach");
  EXPECT_EQ(r.scenario->phases[0].start_s, 0.0);
  EXPECT_EQ(r.scenario->phases[2].name, "terminal");
  EXPECT_EQ(r.scenario->phases[2].reliability, 1U);
}

TEST(Scenario, PhasesAreParsedWithTheirPolicies) {
  const tools::ScenarioResult r = tools::parse_scenario(
      "[[phase]]\nname = \"a\"\nstart_s = 0\npower = \"full\"\n"
      "[[phase]]\nname = \"b\"\nstart_s = 20.5\nreliability = \"high\"\npower = \"save\"\n",
      "<phases>");
  ASSERT_TRUE(r.ok()) << r.error;
  ASSERT_EQ(r.scenario->phases.size(), 2U);
  EXPECT_EQ(r.scenario->phases[0].reliability, 0U);
  EXPECT_EQ(r.scenario->phases[0].power, 0U);
  EXPECT_EQ(r.scenario->phases[1].start_s, 20.5);
  EXPECT_EQ(r.scenario->phases[1].reliability, 1U);
  EXPECT_EQ(r.scenario->phases[1].power, 1U);
}

TEST(Scenario, BadPhasesAreNamedWithTheirKey) {
  auto error = [](const std::string& text) {
    const tools::ScenarioResult r = tools::parse_scenario(text, "<p>");
    EXPECT_FALSE(r.ok()) << text;
    return r.error;
  };
  EXPECT_NE(error("[[phase]]\nname = \"a\"\nstart_s = 1\n").find("the first phase must start at 0"), std::string::npos);
  EXPECT_NE(error("[[phase]]\nname = \"a\"\n[[phase]]\nname = \"b\"\nstart_s = 0\n").find("must be after"),
            std::string::npos);
  EXPECT_NE(error("[[phase]]\nname = \"a\"\n[[phase]]\nname = \"a\"\nstart_s = 2\n").find("used twice"),
            std::string::npos);
  EXPECT_NE(error("[[phase]]\nname = \"a\"\nreliability = \"max\"\n").find("reliability: expected \"normal\" or \"high\""),
            std::string::npos);
  EXPECT_NE(error("[[phase]]\nname = \"a\"\npower = 3\n").find("power: expected \"full\" or \"save\""),
            std::string::npos);
  EXPECT_NE(error("[[phase]]\nname = \"a\"\nrate = 3\n").find("rate: unknown key"), std::string::npos);
  EXPECT_NE(error("[[phase]]\nstart_s = 0\n").find("missing key name"), std::string::npos);
  EXPECT_NE(error("[phase]\nname = \"a\"\n").find("[[phase]] tables"), std::string::npos);
}

}  // namespace
