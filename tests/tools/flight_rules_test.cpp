/**
 * @file flight_rules_test.cpp
 * @brief The flight-rules checker rejects heap use, exceptions and upward includes, and
 *        accepts clean code (fixtures under tests/fixtures/flight_rules/).
 */
#include "tools/common/flight_rules.hpp"
#include "build_info.hpp"

#include <gtest/gtest.h>

#include <fstream>
#include <sstream>
#include <string>

namespace {

namespace fr = tools::flight_rules;

std::vector<fr::Finding> check_fixture(const std::string& name, const char* layer) {
  const std::string path = std::string(build_info::kRepoRoot) + "/tests/fixtures/flight_rules/" + name;
  std::ifstream in(path);
  EXPECT_TRUE(in.good()) << "missing fixture " << path;
  std::ostringstream ss;
  ss << in.rdbuf();
  return fr::check_source(name, ss.str(), layer, false);
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
  for (const auto& x : f) {
    ADD_FAILURE() << x.file << ":" << x.line << " [" << x.rule << "] " << x.message;
  }
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
      {"#include \"tools/common/flight_rules.hpp\"", "layering"},
      {"#include \"bsp_tile64/world/terrain.hpp\"", "truth"},
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
  EXPECT_EQ(fr::layer_of("tools/x.cpp"), "");
  EXPECT_LT(fr::layer_rank("bsp_tile64"), fr::layer_rank("trn"));
}

}  // namespace
