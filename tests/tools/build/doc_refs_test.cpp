/**
 * @file doc_refs_test.cpp
 * @brief tools/lint/doc_refs.py (run by `make lint`): a path, make target or program option a document
 *        names that does not exist is reported by file and line and fails the check; what exists passes.
 */
#include "build_info.hpp"
#include "tests/support/run_command.hpp"

#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <utility>

#include <sys/wait.h>

namespace {

namespace fs = std::filesystem;

/** A small tree: a Makefile with two targets, one program with two options, a module and a doc. */
class DocRefs : public ::testing::Test {
 protected:
  void SetUp() override {
    std::string tmpl = (fs::temp_directory_path() / "doc_refs_XXXXXX").string();
    ASSERT_NE(::mkdtemp(tmpl.data()), nullptr);
    dir_ = tmpl;
    fs::create_directories(dir_ / "docs");
    fs::create_directories(dir_ / "tools" / "prog");
    fs::create_directories(dir_ / "tools" / "common");
    fs::create_directories(dir_ / "fdir");
    std::ofstream(dir_ / "Makefile") << "run: deps ## fly\n\t@true\ntest lint: deps\n\t@true\nVAR := x\n";
    std::ofstream(dir_ / "tools" / "prog" / "main.cpp") << "// \"--seed\" and \"--out\"\n";
    std::ofstream(dir_ / "fdir" / "tile_health.cpp") << "\n";
    std::ofstream(dir_ / "fdir" / "tile_health.hpp") << "\n";
  }
  void TearDown() override {
    std::error_code ec;
    fs::remove_all(dir_, ec);
  }

  /** Writes @p text as docs/A.md and runs the check; returns (exit status, what it printed). */
  std::pair<int, std::string> check(const std::string& text) const {
    std::ofstream(dir_ / "docs" / "A.md") << text;
    std::ofstream(dir_ / "README.md") << "# r\n";
    const std::string cmd = "python3 " + std::string(build_info::kRepoRoot) + "/tools/lint/doc_refs.py " +
                            dir_.string() + " 2>&1";
    return test_support::run_command(cmd);
  }

  fs::path dir_;
};

TEST_F(DocRefs, WhatExistsPasses) {
  const auto [rc, out] = check(
      "See `fdir/tile_health.cpp`, fdir/tile_health, `fdir/tile_health.*` and [a](../fdir/tile_health.hpp).\n"
      "Run `make run` or `make test`; `build/prog --seed 3 --out d` (options `--seed N`, `--out DIR` of prog).\n"
      "Outputs in `build/x` and `out/y` are not checked; nor `--array` of sbatch.\n"
      "```sh\nmake lint\nbuild/prog --seed 1\n```\n");
  EXPECT_EQ(rc, 0) << out;
  EXPECT_NE(out.find("0 dangling names"), std::string::npos) << out;
}

TEST_F(DocRefs, ADanglingPathTargetOrOptionFailsByLine) {
  const auto [rc, out] = check(
      "line one\n"
      "See `fdir/no_such.cpp`.\n"
      "Run `make nosuchtarget`.\n"
      "`build/prog --nosuchopt`\n"
      "[b](no_such.md)\n"
      "```sh\nbuild/prog --seed 1 --other\n```\n");
  EXPECT_EQ(rc, 1) << out;
  EXPECT_NE(out.find("docs/A.md:2: no such path: fdir/no_such.cpp"), std::string::npos) << out;
  EXPECT_NE(out.find("docs/A.md:3: no make target: nosuchtarget"), std::string::npos) << out;
  EXPECT_NE(out.find("docs/A.md:4: prog has no option --nosuchopt"), std::string::npos) << out;
  EXPECT_NE(out.find("docs/A.md:5: link to no such file: no_such.md"), std::string::npos) << out;
  EXPECT_NE(out.find("docs/A.md:7: prog has no option --other"), std::string::npos) << out;
  EXPECT_NE(out.find("5 dangling names"), std::string::npos) << out;
}

TEST(DocRefsTree, TheProjectsDocsNameOnlyWhatExists) {
  const std::string cmd = "python3 " + std::string(build_info::kRepoRoot) + "/tools/lint/doc_refs.py " +
                          std::string(build_info::kRepoRoot) + " >/dev/null 2>&1";
  EXPECT_EQ(std::system(cmd.c_str()), 0) << "run tools/lint/doc_refs.py for the list";
}

}  // namespace
