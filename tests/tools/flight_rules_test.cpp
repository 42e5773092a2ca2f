/**
 * @file flight_rules_test.cpp
 * @brief The flight-rules checker rejects heap use, exceptions, upward includes, board headers
 *        outside the board's interface and include cycles, accepts clean code (fixtures under
 *        tests/fixtures/flight_rules/), and finds nothing in the real tree.
 */
#include "tools/common/rules/flight_rules.hpp"
#include "build_info.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace {

namespace fr = tools::flight_rules;

const std::string kFixtureDir = "tests/fixtures/flight_rules/";

std::string read_fixture(const std::string& name) {
  const std::string path = std::string(build_info::kRepoRoot) + "/" + kFixtureDir + name;
  std::ifstream in(path);
  EXPECT_TRUE(in.good()) << "missing fixture " << path;
  std::ostringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

std::vector<fr::Finding> check_fixture(const std::string& name, const char* layer) {
  return fr::check_source(name, read_fixture(name), layer, false);
}

void print(const std::vector<fr::Finding>& f) {
  for (const auto& x : f) {
    ADD_FAILURE() << x.file << ":" << x.line << " [" << x.rule << "] " << x.message;
  }
}

bool has_rule(const std::vector<fr::Finding>& f, const std::string& rule, int line) {
  for (const auto& x : f) {
    if (x.rule == rule && x.line == line) {
      return true;
    }
  }
  return false;
}

TEST(FlightRules, RejectsNew) {
  const auto f = check_fixture("uses_new.cpp", "kernel");
  ASSERT_EQ(f.size(), 1U);
  EXPECT_TRUE(has_rule(f, "heap", 5));
}

TEST(FlightRules, RejectsThrow) {
  const auto f = check_fixture("uses_throw.cpp", "kernel");
  ASSERT_EQ(f.size(), 1U);
  EXPECT_TRUE(has_rule(f, "exceptions", 5));
}

TEST(FlightRules, RejectsUpwardInclude) {
  const auto f = check_fixture("upward_include.cpp", "kernel");
  ASSERT_EQ(f.size(), 1U);
  EXPECT_TRUE(has_rule(f, "layering", 2));
}

TEST(FlightRules, SameIncludeIsFineFromTheTopLayer) {
  EXPECT_TRUE(check_fixture("upward_include.cpp", "trn").empty());
}

TEST(FlightRules, AcceptsCleanCode) {
  const auto f = check_fixture("clean.cpp", "kernel");
  print(f);
  EXPECT_TRUE(f.empty());
}

struct Case {
  const char* code;
  const char* rule;
};

TEST(FlightRules, EachRuleTriggersOnItsConstruct) {
  const Case cases[] = {
      {"void f() { void* p = malloc(4); }", "heap"},
      {"void f() { std::free(p); }", "heap"},
      {"std::vector<int> v;", "heap"},
      {"std::string s;", "heap"},
      {"std::function<void()> g;", "heap"},
      {"std::map<int, int> m;", "heap"},
      {"#include <vector>", "heap"},
      {"#include <iostream>", "heap"},
      {"void f() { delete p; }", "heap"},
      {"void f() { try { g(); } catch (...) {} }", "exceptions"},
      {"auto* d = dynamic_cast<D*>(b);", "rtti"},
      {"auto& t = typeid(x);", "rtti"},
      {"int r = rand();", "host-time"},
      {"auto t = std::chrono::steady_clock::now();", "host-time"},
      {"#include \"tools/common/rules/flight_rules.hpp\"", "layering"},
      {"#include \"bsp_tile64/world/terrain.hpp\"", "truth"},
      {"#include \"bsp_tile64/emu/devices/camera.hpp\"", "truth"},
      {"#include \"bsp_tile64/emu/udn_net.hpp\"", "truth"},
      {"#include <bsp_tile64/emu/board.hpp>", "truth"},
  };
  for (const Case& c : cases) {
    const auto f = fr::check_source("case.cpp", c.code, "udn", false);
    ASSERT_FALSE(f.empty()) << c.code;
    EXPECT_EQ(f[0].rule, c.rule) << c.code;
  }
}

TEST(FlightRules, HostSideFilesOnlyGetIncludeRules) {
  EXPECT_TRUE(fr::check_source("h.cpp", "void* g() { return malloc(4); }", "bsp_tile64", true).empty());
  EXPECT_FALSE(fr::check_source("h.cpp", "#include \"trn/x.hpp\"", "bsp_tile64", true).empty());
}

TEST(FlightRules, BoardMayIncludeItsOwnWorld) {
  EXPECT_TRUE(fr::check_source("b.cpp", "#include \"bsp_tile64/world/terrain.hpp\"", "bsp_tile64", false).empty());
}

TEST(FlightRules, StripKeepsLinesAndBlanksCommentsAndLiterals) {
  const std::string s = fr::strip_comments_and_literals("a // new\n/* throw\n */ \"delete\" 'x' 0xFF'FF b");
  EXPECT_EQ(s.find("new"), std::string::npos);
  EXPECT_EQ(s.find("throw"), std::string::npos);
  EXPECT_EQ(s.find("delete"), std::string::npos);
  EXPECT_NE(s.find('b'), std::string::npos);
  EXPECT_EQ(std::count(s.begin(), s.end(), '\n'), 2);
}

TEST(FlightRules, LayerOfAPath) {
  EXPECT_EQ(fr::layer_of("kernel/sched.cpp"), "kernel");
  EXPECT_EQ(fr::layer_of("./udn/ecc.hpp"), "udn");
  EXPECT_EQ(fr::layer_of("tools/x.cpp"), "tools");
  EXPECT_EQ(fr::layer_of("docs/x.md"), "");
  EXPECT_LT(fr::layer_rank("bsp_tile64"), fr::layer_rank("trn"));
  EXPECT_LT(fr::layer_rank("trn"), fr::layer_rank("tools"));
  EXPECT_EQ(fr::layer_rank("tools"), fr::layer_rank("tests"));
  EXPECT_TRUE(fr::is_flight_layer("trn"));
  EXPECT_FALSE(fr::is_flight_layer("tests"));
}

// ---------------------------------------------------------------- layering

TEST(FlightRules, RejectsTheBoardIncludingTheKernel) {
  const auto f = check_fixture("board_includes_kernel.cpp", "bsp_tile64");
  ASSERT_EQ(f.size(), 1U);
  EXPECT_TRUE(has_rule(f, "layering", 2));
}

TEST(FlightRules, EveryUpwardIncludeIsRejectedAndEveryDownwardOneAccepted) {
  // Exhaustive over the ordered layers: an include of a strictly higher rank
  // fires, one of the same or a lower rank does not. Board headers are named
  // by an interface header so the truth rule stays out of it.
  const std::vector<std::string> layers = {"bsp_tile64", "kernel", "udn", "fdir", "trn", "tools", "tests"};
  for (const std::string& from : layers) {
    for (const std::string& to : layers) {
      const std::string header = to == "bsp_tile64" ? "bsp_tile64/api/port.hpp" : to + "/x.hpp";
      const auto f = fr::check_source("f.cpp", "#include \"" + header + "\"\n", from, false);
      if (fr::layer_rank(to) > fr::layer_rank(from)) {
        ASSERT_EQ(f.size(), 1U) << from << " -> " << to;
        EXPECT_EQ(f[0].rule, "layering") << from << " -> " << to;
      } else {
        EXPECT_TRUE(f.empty()) << from << " -> " << to;
      }
    }
  }
}

// ---------------------------------------------------------------- the board's interface

TEST(FlightRules, RejectsTrnIncludingTheCamerasSimulation) {
  const auto f = check_fixture("trn_includes_camera.cpp", "trn");
  ASSERT_EQ(f.size(), 1U);
  EXPECT_TRUE(has_rule(f, "truth", 3));  // camera.hpp; camera_model.hpp on line 2 is interface
  EXPECT_NE(f[0].message.find("bsp_tile64/emu/devices/camera.hpp"), std::string::npos);
}

TEST(FlightRules, RejectsFlightCodeIncludingTheNetworkModel) {
  for (const char* layer : {"kernel", "udn", "fdir", "trn"}) {
    const auto f = check_fixture("flight_includes_udn_net.cpp", layer);
    ASSERT_EQ(f.size(), 1U) << layer;
    EXPECT_TRUE(has_rule(f, "truth", 3)) << layer;  // udn_net.hpp; udn_driver.hpp on line 2 is interface
  }
}

TEST(FlightRules, TheBoardMayIncludeItsOwnModel) {
  EXPECT_TRUE(check_fixture("trn_includes_camera.cpp", "bsp_tile64").empty());
  EXPECT_TRUE(check_fixture("flight_includes_udn_net.cpp", "bsp_tile64").empty());
}

TEST(FlightRules, TheBoardInterfaceIsItsFolder) {
  // The folder holds the interface headers and nothing else; each passes, and
  // nothing below it or beside it does.
  std::size_t headers = 0;
  for (const auto& e : std::filesystem::directory_iterator(std::string(build_info::kRepoRoot) + "/" +
                                                           std::string(fr::kBoardInterfaceDir))) {
    ASSERT_TRUE(e.is_regular_file()) << e.path();
    EXPECT_EQ(e.path().extension(), ".hpp") << e.path();
    EXPECT_TRUE(fr::is_board_interface(std::string(fr::kBoardInterfaceDir) + e.path().filename().string()));
    ++headers;
  }
  EXPECT_EQ(headers, 11U);
  EXPECT_FALSE(fr::is_board_interface("bsp_tile64/api/../emu/board.hpp"));
  EXPECT_FALSE(fr::is_board_interface("bsp_tile64/api/detail/x.hpp"));
  EXPECT_FALSE(fr::is_board_interface("bsp_tile64/api/"));
  EXPECT_FALSE(fr::is_board_interface("bsp_tile64/emu/board.hpp"));
  EXPECT_FALSE(fr::is_board_interface("bsp_tile64/" "port.hpp"));  // the board folder itself is not the interface
}

TEST(FlightRules, AboveTheBoardOnlyTheInterfaceOfTheBoardIsIncluded) {
  // Every header of the real board, from every layer above it: the interface
  // headers pass, every other one (model, world, devices' simulation) fires.
  std::size_t outside = 0;
  for (const std::string& path : fr::project_files(build_info::kRepoRoot)) {
    if (path.rfind("bsp_tile64/", 0) != 0 || path.find(".hpp") == std::string::npos) {
      continue;
    }
    const bool allowed = fr::is_board_interface(path);
    outside += allowed ? 0U : 1U;
    for (const char* layer : {"kernel", "udn", "fdir", "trn"}) {
      const auto f = fr::check_source("f.cpp", "#include \"" + path + "\"\n", layer, false);
      if (allowed) {
        EXPECT_TRUE(f.empty()) << layer << " -> " << path;
      } else {
        ASSERT_EQ(f.size(), 1U) << layer << " -> " << path;
        EXPECT_EQ(f[0].rule, "truth") << layer << " -> " << path;
      }
    }
  }
  EXPECT_GT(outside, 10U);  // the model is most of the board: the walk really saw it
}

// ---------------------------------------------------------------- include cycles

std::vector<fr::Source> cycle_fixtures() {
  std::vector<fr::Source> s;
  for (const char* name : {"include_cycle_user.cpp", "include_cycle_c.hpp", "include_cycle_b.hpp", "include_cycle_a.hpp"}) {
    s.push_back({kFixtureDir + name, read_fixture(name)});
  }
  return s;
}

TEST(FlightRules, RejectsAnIncludeCycleOnceAtTheIncludeThatClosesIt) {
  const auto f = fr::find_include_cycles(cycle_fixtures());
  ASSERT_EQ(f.size(), 1U);
  EXPECT_EQ(f[0].rule, "cycle");
  EXPECT_EQ(f[0].file, kFixtureDir + "include_cycle_c.hpp");
  EXPECT_EQ(f[0].line, 4);
  const std::string a = kFixtureDir + "include_cycle_a.hpp";
  const std::string b = kFixtureDir + "include_cycle_b.hpp";
  const std::string c = kFixtureDir + "include_cycle_c.hpp";
  EXPECT_NE(f[0].message.find(a + " -> " + b + " -> " + c + " -> " + a), std::string::npos) << f[0].message;
  // The same through the whole check: the fixtures are test files, so nothing else fires.
  const auto all = fr::check_sources(cycle_fixtures());
  ASSERT_EQ(all.size(), 1U);
  EXPECT_EQ(all[0].rule, "cycle");
}

TEST(FlightRules, IncludeGraphsWithoutCyclesPass) {
  // A diamond (two paths to one header) is not a cycle; a relative include resolves
  // against the including file's folder.
  const std::vector<fr::Source> diamond = {
      {"kernel/top.hpp", "#include \"kernel/left.hpp\"\n#include \"kernel/right.hpp\"\n"},
      {"kernel/left.hpp", "#include \"kernel/base.hpp\"\n"},
      {"kernel/right.hpp", "#include \"base.hpp\"\n#include <cstdint>\n"},
      {"kernel/base.hpp", "#include \"bsp_tile64/api/port.hpp\"\n"},
  };
  EXPECT_TRUE(fr::find_include_cycles(diamond).empty());
}

TEST(FlightRules, EachShapeOfCycleIsFound) {
  const std::vector<fr::Source> self = {{"udn/a.hpp", "#include \"udn/a.hpp\"\n"}};
  const std::vector<fr::Source> pair = {{"kernel/config.hpp", "#include \"kernel/config_check.hpp\"\n"},
                                        {"kernel/config_check.hpp", "#include \"kernel/config.hpp\"\n"}};
  const std::vector<fr::Source> relative = {{"tests/x/a.hpp", "#include \"b.hpp\"\n"},
                                            {"tests/x/b.hpp", "#include \"tests/x/a.hpp\"\n"}};
  // A quoted name is looked up next to the including file before the root, as the compiler does.
  const std::vector<fr::Source> shadowing = {{"tests/x/a.hpp", "#include \"b.hpp\"\n"},
                                             {"tests/x/b.hpp", "#include \"tests/x/a.hpp\"\n"},
                                             {"b.hpp", ""}};
  for (const auto* graph : {&self, &pair, &relative, &shadowing}) {
    const auto f = fr::find_include_cycles(*graph);
    ASSERT_EQ(f.size(), 1U) << (*graph)[0].path;
    EXPECT_EQ(f[0].rule, "cycle");
  }
}

// ---------------------------------------------------------------- the real tree

TEST(FlightRules, TheRealTreeIsClean) {
  const std::string root = build_info::kRepoRoot;
  const std::vector<std::string> files = fr::project_files(root);
  auto has = [&](const std::string& p) { return std::find(files.begin(), files.end(), p) != files.end(); };
  ASSERT_TRUE(has("kernel/sched.cpp"));
  ASSERT_TRUE(has("bsp_tile64/api/udn_driver.hpp"));
  ASSERT_TRUE(has("tests/tools/flight_rules_test.cpp"));
  for (const std::string& p : files) {
    EXPECT_NE(p.rfind("tests/fixtures/", 0), 0U) << p;
  }
  std::vector<fr::Finding> errors;
  const std::vector<fr::Source> sources = fr::read_sources(root, files, errors);
  print(errors);
  EXPECT_EQ(sources.size(), files.size());
  const auto f = fr::check_sources(sources);
  print(f);
  EXPECT_TRUE(f.empty());
}

}  // namespace
