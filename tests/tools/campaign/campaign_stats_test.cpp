/**
 * @file campaign_stats_test.cpp
 * @brief Campaign statistics (docs/CAMPAIGNS.md, "Statistics"): outcome names, the Clopper-Pearson and Wilson
 *        intervals against published values, runs for a margin against published tables, per-kind summaries and
 *        the report files.
 */
#include "tools/common/campaign/campaign_stats.hpp"

#include "tests/support/folder_permissions.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <array>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include <fcntl.h>
#include <unistd.h>

namespace {

namespace fs = std::filesystem;
using tools::campaign::Interval;
using tools::campaign::Outcome;
using tools::campaign::RunResult;

/** A fresh temporary folder, removed (made writable first) at the end of the test. */
class TempDir {
 public:
  TempDir() {
    std::string tmpl = (fs::temp_directory_path() / "campaign_stats_XXXXXX").string();
    const char* made = ::mkdtemp(tmpl.data());
    EXPECT_NE(made, nullptr);
    path_ = tmpl;
  }
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;
  TempDir(TempDir&&) = delete;
  TempDir& operator=(TempDir&&) = delete;
  ~TempDir() {
    std::error_code ec;
    fs::permissions(path_, fs::perms::owner_all, fs::perm_options::add, ec);
    fs::remove_all(path_, ec);
  }
  const fs::path& path() const { return path_; }
  fs::path operator/(const std::string& name) const { return path_ / name; }

 private:
  fs::path path_;
};

/** Sets PATH for one scope. */
class PathOverride {
 public:
  explicit PathOverride(const std::string& path) : old_(std::getenv("PATH") != nullptr ? std::getenv("PATH") : "") {
    ::setenv("PATH", path.c_str(), 1);
  }
  PathOverride(const PathOverride&) = delete;
  PathOverride& operator=(const PathOverride&) = delete;
  PathOverride(PathOverride&&) = delete;
  PathOverride& operator=(PathOverride&&) = delete;
  ~PathOverride() { ::setenv("PATH", old_.c_str(), 1); }

 private:
  std::string old_;
};

std::string read_file(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

void write_file(const fs::path& path, const std::string& text) {
  std::ofstream out(path, std::ios::binary);
  out << text;
}

std::vector<std::string> lines_of(const std::string& text) {
  std::vector<std::string> out;
  std::stringstream ss(text);
  for (std::string l; std::getline(ss, l);) {
    out.push_back(l);
  }
  return out;
}

/** Names in @p dir that start with a dot: temporary files left behind. */
std::vector<std::string> hidden_entries(const fs::path& dir) {
  std::vector<std::string> out;
  for (const fs::directory_entry& e : fs::directory_iterator(dir)) {
    const std::string name = e.path().filename().string();
    if (!name.empty() && name[0] == '.') {
      out.push_back(name);
    }
  }
  return out;
}

bool is_png(const fs::path& path) {
  const std::string s = read_file(path);
  return s.size() > 1000U && s.compare(0, 8, "\x89PNG\r\n\x1a\n") == 0;
}

RunResult run(std::uint32_t index, const std::string& kind, Outcome outcome, double host_s = 1.0) {
  RunResult r;
  r.index = index;
  r.kind = kind;
  r.outcome = outcome;
  r.host_s = host_s;
  return r;
}

/**
 * Ten runs: sdc 4 (2 masked, 1 recovered, 1 sdc), core_hang 5 (3 recovered, 1 lost, 1 hang_crash),
 * one with no kind (degraded). Over all: masked 2, recovered 4, degraded 1, lost 1, sdc 1, hang_crash 1.
 */
std::vector<RunResult> ten_runs() {
  return {run(0, "sdc", Outcome::kMasked),       run(1, "core_hang", Outcome::kRecovered),
          run(2, "sdc", Outcome::kMasked),       run(3, "core_hang", Outcome::kRecovered),
          run(4, "sdc", Outcome::kRecovered),    run(5, "core_hang", Outcome::kRecovered),
          run(6, "sdc", Outcome::kSdc),          run(7, "core_hang", Outcome::kLost),
          run(8, "", Outcome::kDegraded, 2.5),   run(9, "core_hang", Outcome::kCrash)};
}

// ------------------------------------------------------------------ CST-01 outcome names

// CST-01: every outcome has its report name, and the name reads back as the same outcome.
TEST(OutcomeNames, EveryOutcomeRoundTripsThroughItsName) {
  const std::array<const char*, tools::campaign::kOutcomeCount> expected = {
      "not_delivered",     "no_effect",     "masked", "detected_recovered",
      "detected_degraded", "detected_lost", "sdc",    "hang_crash"};
  for (std::size_t i = 0; i < tools::campaign::kOutcomeCount; ++i) {
    const Outcome o = tools::campaign::kOutcomes[i];
    EXPECT_EQ(static_cast<std::size_t>(o), i) << "kOutcomes is in enum order";
    EXPECT_STREQ(tools::campaign::outcome_name(o), expected[i]);
    Outcome back = i == 0U ? Outcome::kCrash : Outcome::kMasked;
    ASSERT_TRUE(tools::campaign::outcome_from_name(expected[i], back)) << expected[i];
    EXPECT_EQ(back, o);
  }
}

// CST-01: a name that is not exactly one of the eight is refused and leaves the output alone.
TEST(OutcomeNames, OtherNamesAreRefused) {
  for (const char* bad : {"", "Masked", "masked ", "recovered", "hang", "detected", "sdc\n", "not delivered",
                          "noeffect"}) {
    Outcome out = Outcome::kLost;
    EXPECT_FALSE(tools::campaign::outcome_from_name(bad, out)) << "'" << bad << "'";
    EXPECT_EQ(out, Outcome::kLost);
  }
  EXPECT_STREQ(tools::campaign::outcome_name(static_cast<Outcome>(42)), "?");
}

// ------------------------------------------------------------------ CST-02 Clopper-Pearson

struct Published {
  std::uint64_t k;
  std::uint64_t n;
  double conf;
  double lo;
  double hi;
};

// CST-02: the exact interval agrees with R's binom.test() (which returns qbeta(a/2, k, n-k+1) and
// qbeta(1-a/2, k+1, n-k)). binom.test(0, 10), (5, 10), (10, 10) and (1, 1000) print [0, 0.3084971],
// [0.1870860, 0.8129140], [0.6915029, 1] and [2.531749e-05, 5.558924e-03]; the digits below were
// derived to 12 places from the same definition with mpmath at 40 digits (bisection on the regularized
// incomplete beta, no quantile routine), and agree with those printouts.
TEST(ClopperPearson, AgreesWithRsBinomTest) {
  const std::vector<Published> table = {
      {0, 10, 0.95, 0.0, 0.308497107819},
      {5, 10, 0.95, 0.187086028447, 0.812913971553},
      {10, 10, 0.95, 0.691502892181, 1.0},
      {1, 1000, 0.95, 2.53174874913e-5, 0.00555892427983},
      {3, 20, 0.95, 0.0320709371855, 0.378926826545},
      {50, 100, 0.95, 0.398321129503, 0.601678870497},
      {999, 1000, 0.95, 0.99444107572, 0.999974682513},
      {7, 10000, 0.95, 0.000281481145743, 0.00144173230915},
      {2, 30, 0.99, 0.00350266245515, 0.274001347228},
  };
  for (const Published& p : table) {
    const Interval i = tools::campaign::clopper_pearson(p.k, p.n, p.conf);
    // Relative 1e-9 (absolute for the ends at 0 and 1): far tighter than any report prints.
    EXPECT_NEAR(i.lo, p.lo, 1e-9 * std::max(p.lo, 1e-3)) << p.k << "/" << p.n << " at " << p.conf;
    EXPECT_NEAR(i.hi, p.hi, 1e-9 * std::max(p.hi, 1e-3)) << p.k << "/" << p.n << " at " << p.conf;
  }
}

// CST-02: at k = 0 the upper end has the closed form 1 - (a/2)^(1/n), at k = n the lower end (a/2)^(1/n),
// and the other end is exactly 0 or 1; checked for every n up to 300.
TEST(ClopperPearson, EdgesHaveTheirClosedForms) {
  for (const double conf : {0.9, 0.95, 0.99}) {
    const double half_alpha = (1.0 - conf) / 2.0;
    for (std::uint64_t n = 1; n <= 300U; ++n) {
      const double root = std::pow(half_alpha, 1.0 / static_cast<double>(n));
      const Interval none = tools::campaign::clopper_pearson(0, n, conf);
      EXPECT_EQ(none.lo, 0.0);
      EXPECT_NEAR(none.hi, 1.0 - root, 1e-12) << "0/" << n << " at " << conf;
      const Interval all = tools::campaign::clopper_pearson(n, n, conf);
      EXPECT_EQ(all.hi, 1.0);
      EXPECT_NEAR(all.lo, root, 1e-12) << n << "/" << n << " at " << conf;
    }
  }
  const Interval empty = tools::campaign::clopper_pearson(0, 0);
  EXPECT_EQ(empty.lo, 0.0);
  EXPECT_EQ(empty.hi, 1.0);
}

// CST-02: for every k of every n up to 60 the interval holds k/n, moves up with k and is symmetric
// (the interval of n-k is the mirror of that of k).
TEST(ClopperPearson, HoldsTheEstimateMovesWithKAndIsSymmetric) {
  for (std::uint64_t n = 1; n <= 60U; ++n) {
    Interval previous{-1.0, -1.0};
    for (std::uint64_t k = 0; k <= n; ++k) {
      const Interval i = tools::campaign::clopper_pearson(k, n);
      const double p = static_cast<double>(k) / static_cast<double>(n);
      EXPECT_LE(i.lo, p) << k << "/" << n;
      EXPECT_GE(i.hi, p) << k << "/" << n;
      EXPECT_GT(i.lo, previous.lo) << k << "/" << n;
      EXPECT_GT(i.hi, previous.hi) << k << "/" << n;
      const Interval mirror = tools::campaign::clopper_pearson(n - k, n);
      EXPECT_NEAR(i.lo, 1.0 - mirror.hi, 1e-12) << k << "/" << n;
      EXPECT_NEAR(i.hi, 1.0 - mirror.lo, 1e-12) << k << "/" << n;
      previous = i;
    }
  }
}

// CST-02: counts that cannot be and confidences outside (0, 1) are errors of the caller.
TEST(ClopperPearson, RefusesArgumentsOutsideItsDomain) {
  EXPECT_THROW((void)tools::campaign::clopper_pearson(11, 10), std::invalid_argument);
  for (const double conf : {0.0, 1.0, -0.5, 1.5, std::numeric_limits<double>::quiet_NaN()}) {
    EXPECT_THROW((void)tools::campaign::clopper_pearson(1, 10, conf), std::invalid_argument) << conf;
    EXPECT_THROW((void)tools::campaign::wilson(1, 10, conf), std::invalid_argument) << conf;
  }
  EXPECT_THROW((void)tools::campaign::wilson(3, 2), std::invalid_argument);
}

// ------------------------------------------------------------------ CST-03 Wilson

// The normal quantiles the intervals use: qnorm(0.975) and qnorm(0.995) in R.
TEST(Wilson, NormalQuantilesAreTheTwoSidedOnes) {
  EXPECT_NEAR(tools::campaign::normal_quantile(0.95), 1.959963984540054, 1e-13);
  EXPECT_NEAR(tools::campaign::normal_quantile(0.99), 2.575829303548901, 1e-13);
  EXPECT_NEAR(tools::campaign::normal_quantile(0.90), 1.644853626951472, 1e-13);
}

// CST-03: the Wilson score interval of Newcombe, "Two-sided confidence intervals for the single
// proportion: comparison of seven methods", Statistics in Medicine 17 (1998) 857-872: its worked
// examples 81/263, 15/148, 0/20 and 1/29 with method 3 (score, no continuity correction), to 4 decimals.
TEST(Wilson, AgreesWithNewcombesExamples) {
  const std::vector<Published> table = {
      {81, 263, 0.95, 0.2553, 0.3662},
      {15, 148, 0.95, 0.0624, 0.1605},
      {0, 20, 0.95, 0.0, 0.1611},
      {1, 29, 0.95, 0.0061, 0.1718},
  };
  for (const Published& p : table) {
    const Interval i = tools::campaign::wilson(p.k, p.n, p.conf);
    EXPECT_NEAR(i.lo, p.lo, 0.5e-4) << p.k << "/" << p.n;
    EXPECT_NEAR(i.hi, p.hi, 0.5e-4) << p.k << "/" << p.n;
  }
}

// CST-03: every k of every n up to 80 against the closed form
// (p + z^2/2n -+ z sqrt(p(1-p)/n + z^2/4n^2)) / (1 + z^2/n), z = qnorm(0.975), written out here apart.
TEST(Wilson, AgreesWithItsClosedForm) {
  const double z = 1.959963984540054;
  for (std::uint64_t n = 1; n <= 80U; ++n) {
    const double nd = static_cast<double>(n);
    for (std::uint64_t k = 0; k <= n; ++k) {
      const double p = static_cast<double>(k) / nd;
      const double denom = 1.0 + z * z / nd;
      const double centre = (p + z * z / (2.0 * nd)) / denom;
      const double half = z * std::sqrt(p * (1.0 - p) / nd + z * z / (4.0 * nd * nd)) / denom;
      const Interval i = tools::campaign::wilson(k, n);
      EXPECT_NEAR(i.lo, std::max(0.0, centre - half), 1e-12) << k << "/" << n;
      EXPECT_NEAR(i.hi, std::min(1.0, centre + half), 1e-12) << k << "/" << n;
    }
    EXPECT_EQ(tools::campaign::wilson(0, n).lo, 0.0) << "exactly 0 at k = 0";
    EXPECT_EQ(tools::campaign::wilson(n, n).hi, 1.0) << "exactly 1 at k = n";
  }
  const Interval empty = tools::campaign::wilson(0, 0);
  EXPECT_EQ(empty.lo, 0.0);
  EXPECT_EQ(empty.hi, 1.0);
}

// ------------------------------------------------------------------ CST-04 runs for a margin

// CST-04: an infinite population (Leveugle et al., DATE 2009): n = t^2 p (1-p) / e^2, rounded up.
// 95 %: e = 1 % -> 9604, e = 5 % -> 385 (384.1); 99 %, e = 1 % -> 16588 (16587.2); p = 0.1, 5 % -> 139 (138.3).
TEST(RunsForMargin, InfinitePopulationMatchesTheFormula) {
  EXPECT_EQ(tools::campaign::runs_for_margin(0.01), 9604U);
  EXPECT_EQ(tools::campaign::runs_for_margin(0.05), 385U);
  EXPECT_EQ(tools::campaign::runs_for_margin(0.01, 0.99), 16588U);
  EXPECT_EQ(tools::campaign::runs_for_margin(0.05, 0.95, 0.1), 139U);
  EXPECT_EQ(tools::campaign::runs_for_margin(0.05, 0.95, 0.9), 139U) << "p and 1 - p need the same";
}

// CST-04: a finite population. Leveugle's n = N / (1 + e^2 (N-1) / (t^2 p (1-p))) is the formula of
// Krejcie and Morgan, "Determining sample size for research activities", Educational and Psychological
// Measurement 30 (1970) 607-610, whose Table 1 (e = 5 %, p = 0.5, chi^2 = 3.841 = 1.96^2) gives
// N = 100 -> 80, 1000 -> 278, 10000 -> 370, 1000000 -> 384. With e = 1 %, N = 10000 -> 4900 (4899.2).
TEST(RunsForMargin, FinitePopulationMatchesThePublishedTable) {
  EXPECT_EQ(tools::campaign::runs_for_margin(0.05, 0.95, 0.5, 100), 80U);
  EXPECT_EQ(tools::campaign::runs_for_margin(0.05, 0.95, 0.5, 1000), 278U);
  EXPECT_EQ(tools::campaign::runs_for_margin(0.05, 0.95, 0.5, 10000), 370U);
  EXPECT_EQ(tools::campaign::runs_for_margin(0.05, 0.95, 0.5, 1000000), 384U);
  EXPECT_EQ(tools::campaign::runs_for_margin(0.01, 0.95, 0.5, 10000), 4900U);
  EXPECT_EQ(tools::campaign::runs_for_margin(0.01, 0.95, 0.5, 1), 1U) << "a population of one needs its one run";
  for (const std::uint64_t population : {2U, 10U, 50U, 385U}) {
    EXPECT_LE(tools::campaign::runs_for_margin(0.05, 0.95, 0.5, population), population)
        << "never more runs than the population";
  }
}

// CST-04: the margin a run count gives is the inverse (worst case, infinite population).
TEST(RunsForMargin, MarginForRunsIsItsInverse) {
  EXPECT_NEAR(tools::campaign::margin_for_runs(9604), 0.01, 1e-5);
  EXPECT_NEAR(tools::campaign::margin_for_runs(385), 0.05, 1e-3);
  EXPECT_EQ(tools::campaign::margin_for_runs(0), 0.5);
  for (const std::uint64_t n : {1U, 7U, 100U, 385U, 1000U, 9604U, 123457U}) {
    EXPECT_EQ(tools::campaign::runs_for_margin(tools::campaign::margin_for_runs(n)), n) << n;
  }
}

// CST-04: margins, confidences and proportions outside (0, 1) are errors of the caller.
TEST(RunsForMargin, RefusesArgumentsOutsideItsDomain) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  for (const double bad : {0.0, 1.0, -0.1, nan}) {
    EXPECT_THROW((void)tools::campaign::runs_for_margin(bad), std::invalid_argument) << bad;
    EXPECT_THROW((void)tools::campaign::runs_for_margin(0.05, bad), std::invalid_argument) << bad;
    EXPECT_THROW((void)tools::campaign::runs_for_margin(0.05, 0.95, bad), std::invalid_argument) << bad;
  }
  EXPECT_THROW((void)tools::campaign::runs_for_margin(1e-12), std::invalid_argument) << "more than 2^64 runs";
}

// ------------------------------------------------------------------ CST-05 summary

// CST-05: the classes are counted over all runs and per kind; kinds come sorted by name, a run with no
// kind counts as "unknown", and every interval is the one of its own count and run total.
TEST(Summarize, CountsEachClassOverAllAndPerKind) {
  const std::vector<RunResult> runs = ten_runs();
  const tools::campaign::Report r = tools::campaign::summarize("demo", runs, 0.9);
  EXPECT_EQ(r.campaign, "demo");
  EXPECT_EQ(r.confidence, 0.9);
  EXPECT_EQ(r.runs, 10U);
  EXPECT_DOUBLE_EQ(r.host_s_total, 11.5);
  EXPECT_DOUBLE_EQ(r.margin_at_runs, tools::campaign::margin_for_runs(10, 0.9));
  const std::array<std::uint64_t, tools::campaign::kOutcomeCount> all = {0, 0, 2, 4, 1, 1, 1, 1};
  for (std::size_t i = 0; i < all.size(); ++i) {
    EXPECT_EQ(r.classes[i].count, all[i]) << tools::campaign::outcome_name(tools::campaign::kOutcomes[i]);
    const Interval cp = tools::campaign::clopper_pearson(all[i], 10, 0.9);
    const Interval w = tools::campaign::wilson(all[i], 10, 0.9);
    EXPECT_EQ(r.classes[i].cp.lo, cp.lo);
    EXPECT_EQ(r.classes[i].cp.hi, cp.hi);
    EXPECT_EQ(r.classes[i].wilson.lo, w.lo);
    EXPECT_EQ(r.classes[i].wilson.hi, w.hi);
  }
  ASSERT_EQ(r.kinds.size(), 3U);
  EXPECT_EQ(r.kinds[0].name, "core_hang");
  EXPECT_EQ(r.kinds[1].name, "sdc");
  EXPECT_EQ(r.kinds[2].name, "unknown");
  const std::array<std::array<std::uint64_t, tools::campaign::kOutcomeCount>, 3> per_kind = {{
      {0, 0, 0, 3, 0, 1, 0, 1},
      {0, 0, 2, 1, 0, 0, 1, 0},
      {0, 0, 0, 0, 1, 0, 0, 0},
  }};
  const std::array<std::uint64_t, 3> kind_runs = {5, 4, 1};
  for (std::size_t k = 0; k < 3U; ++k) {
    EXPECT_EQ(r.kinds[k].runs, kind_runs[k]) << r.kinds[k].name;
    for (std::size_t i = 0; i < tools::campaign::kOutcomeCount; ++i) {
      EXPECT_EQ(r.kinds[k].classes[i].count, per_kind[k][i]) << r.kinds[k].name << " class " << i;
      const Interval cp = tools::campaign::clopper_pearson(per_kind[k][i], kind_runs[k], 0.9);
      EXPECT_EQ(r.kinds[k].classes[i].cp.lo, cp.lo);
      EXPECT_EQ(r.kinds[k].classes[i].cp.hi, cp.hi);
    }
  }
}

// CST-05: no runs is a report of nothing known: every class 0 with the interval [0, 1].
TEST(Summarize, NoRunsGivesTheWholeInterval) {
  const tools::campaign::Report r = tools::campaign::summarize("empty", {});
  EXPECT_EQ(r.runs, 0U);
  EXPECT_TRUE(r.kinds.empty());
  EXPECT_EQ(r.margin_at_runs, 0.5);
  for (const tools::campaign::ClassCount& c : r.classes) {
    EXPECT_EQ(c.count, 0U);
    EXPECT_EQ(c.cp.lo, 0.0);
    EXPECT_EQ(c.cp.hi, 1.0);
    EXPECT_EQ(c.wilson.lo, 0.0);
    EXPECT_EQ(c.wilson.hi, 1.0);
  }
  EXPECT_THROW((void)tools::campaign::summarize("bad", {}, 1.0), std::invalid_argument);
  const std::vector<RunResult> bad = {run(3, "sdc", static_cast<Outcome>(9))};
  EXPECT_THROW((void)tools::campaign::summarize("bad", bad), std::invalid_argument) << "an outcome outside the enum";
}

// ------------------------------------------------------------------ CST-07 coverage and flags

/** A run of kind @p kind on @p role with @p injected faults delivered. */
RunResult aimed(std::uint32_t index, const std::string& kind, const std::string& role, Outcome outcome,
                std::uint32_t injected = 1U) {
  RunResult r = run(index, kind, outcome);
  r.role = role;
  r.injected = injected;
  return r;
}

/**
 * Ten runs of kinds sdc and seu on the roles filter, io and tile_5. Eligible for coverage (a fault
 * delivered, neither no_effect nor hang_crash): 0, 1, 2, 3, 7, 8, 9, of which 0, 1, 7, 9 detected. Flags:
 * false alarm in 5 and 8, misdiagnosed in 1 and 8, a healthy tile disturbed in 3.
 */
std::vector<RunResult> aimed_runs() {
  std::vector<RunResult> v = {aimed(0, "sdc", "filter", Outcome::kRecovered),
                              aimed(1, "sdc", "filter", Outcome::kDegraded),
                              aimed(2, "sdc", "io", Outcome::kMasked),
                              aimed(3, "sdc", "io", Outcome::kSdc),
                              aimed(4, "sdc", "filter", Outcome::kNoEffect),
                              aimed(5, "seu", "filter", Outcome::kNotDelivered, 0U),
                              aimed(6, "seu", "io", Outcome::kCrash, 0U),
                              aimed(7, "seu", "tile_5", Outcome::kLost, 2U),
                              aimed(8, "seu", "filter", Outcome::kMasked),
                              aimed(9, "seu", "io", Outcome::kRecovered)};
  v[1].misdiagnosed = 1U;
  v[3].healthy_disturbed = 2U;
  v[5].not_delivered = 1U;
  v[5].false_alarms = 1U;
  v[8].false_alarms = 2U;
  v[8].misdiagnosed = 1U;
  return v;
}

/** Expects @p c to be @p detected of @p eligible with the intervals of that count at @p conf. */
void expect_coverage(const tools::campaign::Coverage& c, std::uint64_t detected, std::uint64_t eligible,
                     const std::string& what, double conf = 0.95) {
  EXPECT_EQ(c.detected, detected) << what;
  EXPECT_EQ(c.eligible, eligible) << what;
  const Interval cp = tools::campaign::clopper_pearson(detected, eligible, conf);
  const Interval w = tools::campaign::wilson(detected, eligible, conf);
  EXPECT_EQ(c.cp.lo, cp.lo) << what;
  EXPECT_EQ(c.cp.hi, cp.hi) << what;
  EXPECT_EQ(c.wilson.lo, w.lo) << what;
  EXPECT_EQ(c.wilson.hi, w.hi) << what;
}

// CST-07: coverage counts the detected runs among those with a fault delivered whose class is neither
// no_effect nor hang_crash, over all runs, per kind and per role, each with its own interval; 4 of 7 over
// all is Clopper-Pearson [18.4, 90.1] % (binom.test(4, 7)).
TEST(Coverage, IsTheDetectedShareOfTheRunsWhoseFaultReachedTheChipAndChangedSomething) {
  const std::vector<RunResult> runs = aimed_runs();
  const tools::campaign::Report r = tools::campaign::summarize("aimed", runs);
  expect_coverage(r.coverage, 4U, 7U, "all");
  EXPECT_NEAR(r.coverage.cp.lo, 0.1840516, 1e-6);
  EXPECT_NEAR(r.coverage.cp.hi, 0.9010117, 1e-6);
  ASSERT_EQ(r.kinds.size(), 2U);
  EXPECT_EQ(r.kinds[0].name, "sdc");
  expect_coverage(r.kinds[0].coverage, 2U, 4U, "kind sdc");
  EXPECT_EQ(r.kinds[1].name, "seu");
  expect_coverage(r.kinds[1].coverage, 2U, 3U, "kind seu");
  ASSERT_EQ(r.roles.size(), 3U);
  EXPECT_EQ(r.roles[0].name, "filter");
  EXPECT_EQ(r.roles[0].runs, 5U);
  expect_coverage(r.roles[0].coverage, 2U, 3U, "role filter");
  EXPECT_EQ(r.roles[1].name, "io");
  expect_coverage(r.roles[1].coverage, 1U, 3U, "role io");
  EXPECT_EQ(r.roles[2].name, "tile_5");
  expect_coverage(r.roles[2].coverage, 1U, 1U, "role tile_5");
  EXPECT_EQ(r.roles[2].classes[static_cast<std::size_t>(Outcome::kLost)].count, 1U) << "classes per role too";
  // The same figures from the run list alone, and at another confidence.
  expect_coverage(tools::campaign::coverage_of(runs, 0.9), 4U, 7U, "coverage_of at 90 %", 0.9);
  EXPECT_THROW((void)tools::campaign::coverage_of(runs, 0.0), std::invalid_argument);
}

// CST-07: the boundaries of eligibility: a run with no fault delivered is out whatever its class, a
// no_effect or a hang_crash run is out even with a fault delivered, and none eligible is the interval [0, 1].
TEST(Coverage, LeavesOutRunsWithoutADeliveredFaultNoEffectAndHangs) {
  const std::vector<RunResult> none = {aimed(0, "sdc", "io", Outcome::kNoEffect),
                                       aimed(1, "sdc", "io", Outcome::kCrash),
                                       aimed(2, "sdc", "io", Outcome::kNotDelivered, 0U),
                                       aimed(3, "none", "none", Outcome::kMasked, 0U),
                                       aimed(4, "none", "none", Outcome::kRecovered, 0U)};
  expect_coverage(tools::campaign::coverage_of(none), 0U, 0U, "nothing eligible");
  const std::vector<RunResult> one = {aimed(0, "sdc", "io", Outcome::kSdc), aimed(1, "sdc", "io", Outcome::kMasked)};
  expect_coverage(tools::campaign::coverage_of(one), 0U, 2U, "two missed");
  const std::vector<RunResult> all = {aimed(0, "sdc", "io", Outcome::kDegraded, 3U)};
  expect_coverage(tools::campaign::coverage_of(all), 1U, 1U, "one detected");
}

// CST-07: a flag counts the runs that raised it (a count above zero), over all runs, per kind and per role.
TEST(Coverage, FlagsCountTheRunsThatRaisedThem) {
  const tools::campaign::Report r = tools::campaign::summarize("aimed", aimed_runs());
  const auto expect_flags = [](const tools::campaign::FlagCounts& f, std::uint64_t fa, std::uint64_t mis,
                               std::uint64_t healthy, const std::string& what) {
    EXPECT_EQ(f.false_alarm, fa) << what;
    EXPECT_EQ(f.misdiagnosed, mis) << what;
    EXPECT_EQ(f.healthy_disturbed, healthy) << what;
  };
  expect_flags(r.flags, 2U, 2U, 1U, "all");
  expect_flags(r.kinds[0].flags, 0U, 1U, 1U, "kind sdc");
  expect_flags(r.kinds[1].flags, 2U, 1U, 0U, "kind seu");
  expect_flags(r.roles[0].flags, 2U, 2U, 0U, "role filter");
  expect_flags(r.roles[1].flags, 0U, 0U, 1U, "role io");
  expect_flags(r.roles[2].flags, 0U, 0U, 0U, "role tile_5");
}

// CST-06, CST-07: the report files carry the coverage and the flags: report.json per kind and per role,
// coverage.csv a row for all, each kind and each role, runs.csv a row per run with its class and flags,
// report.md a table of them.
TEST(WriteReport, TheCoverageAndTheFlagsAreInTheReport) {
  TempDir tmp;
  const PathOverride path("/nonexistent");  // the chart is not what this test is about
  const tools::campaign::Report r = tools::campaign::summarize("aimed", aimed_runs());
  std::string err;
  std::string note;
  ASSERT_TRUE(tools::campaign::write_report(r, tmp.path(), err, note)) << err;
  const nlohmann::json j = nlohmann::json::parse(read_file(tmp / "report.json"));
  EXPECT_EQ(j.at("coverage").at("detected"), 4);
  EXPECT_EQ(j.at("coverage").at("eligible"), 7);
  EXPECT_DOUBLE_EQ(j.at("coverage").at("fraction").get<double>(), 4.0 / 7.0);
  EXPECT_DOUBLE_EQ(j.at("coverage").at("cp").at("lo").get<double>(), r.coverage.cp.lo);
  EXPECT_EQ(j.at("flags").at("false_alarm_runs"), 2);
  EXPECT_EQ(j.at("flags").at("misdiagnosed_runs"), 2);
  EXPECT_EQ(j.at("flags").at("healthy_disturbed_runs"), 1);
  EXPECT_EQ(j.at("classes").at("not_delivered").at("count"), 1);
  EXPECT_EQ(j.at("classes").at("no_effect").at("count"), 1);
  EXPECT_EQ(j.at("kinds")[1].at("kind"), "seu");
  EXPECT_EQ(j.at("kinds")[1].at("coverage").at("eligible"), 3);
  EXPECT_EQ(j.at("kinds")[1].at("flags").at("false_alarm_runs"), 2);
  ASSERT_EQ(j.at("roles").size(), 3U);
  EXPECT_EQ(j.at("roles")[1].at("role"), "io");
  EXPECT_EQ(j.at("roles")[1].at("coverage").at("detected"), 1);
  EXPECT_EQ(j.at("roles")[1].at("classes").at("hang_crash").at("count"), 1);

  const std::vector<std::string> cov = lines_of(read_file(tmp / "coverage.csv"));
  ASSERT_EQ(cov.size(), 1U + 1U + 2U + 3U) << "header, all, two kinds, three roles";
  EXPECT_EQ(cov[0], tools::campaign::kCoverageCsvHeader);
  EXPECT_EQ(cov[1].rfind("all,all,10,7,4,0.571429,0.184052,0.901012,", 0), 0U) << cov[1];
  EXPECT_EQ(cov[1].substr(cov[1].size() - 6U), ",2,2,1") << cov[1];
  EXPECT_EQ(cov[2].rfind("kind,sdc,5,4,2,0.500000,0.067586,0.932414,", 0), 0U) << cov[2];
  EXPECT_EQ(cov[6].rfind("role,tile_5,1,1,1,1.000000,0.025000,1.000000,", 0), 0U) << cov[6];

  const std::vector<std::string> rows = lines_of(read_file(tmp / "runs.csv"));
  ASSERT_EQ(rows.size(), 11U);
  EXPECT_EQ(rows[0], tools::campaign::kRunsCsvHeader);
  EXPECT_EQ(rows[6], "5,seu,filter,0,not_delivered,0,0,1,0,0,0,0,1,0,0") << rows[6];
  EXPECT_EQ(rows[9], "8,seu,filter,0,masked,0,1,0,0,0,0,1,2,0,0") << rows[9];

  const std::string md = read_file(tmp / "report.md");
  EXPECT_NE(md.find("| all | 10 | 7 | 4 | 57.1 % (CP 18.4-90.1 %) | 2 | 2 | 1 |"), std::string::npos) << md;
  EXPECT_NE(md.find("| role io | 4 | 3 | 1 | 33.3 % (CP 0.8-90.6 %) | 0 | 0 | 1 |"), std::string::npos) << md;
}

// CST-07: with no run eligible the coverage has no fraction (null in report.json, empty in coverage.csv, "-"
// in report.md) and the interval [0, 1].
TEST(WriteReport, NoEligibleRunIsACoverageOfNothingKnown) {
  TempDir tmp;
  const PathOverride path("/nonexistent");
  const std::vector<RunResult> runs = ten_runs();  // no run has a delivered fault
  std::string err;
  std::string note;
  ASSERT_TRUE(tools::campaign::write_report(tools::campaign::summarize("demo", runs), tmp.path(), err, note)) << err;
  const nlohmann::json j = nlohmann::json::parse(read_file(tmp / "report.json"));
  EXPECT_TRUE(j.at("coverage").at("fraction").is_null()) << j.at("coverage").dump();
  EXPECT_EQ(j.at("coverage").at("cp").at("lo"), 0.0);
  EXPECT_EQ(j.at("coverage").at("cp").at("hi"), 1.0);
  EXPECT_EQ(lines_of(read_file(tmp / "coverage.csv"))[1].rfind("all,all,10,0,0,,0.000000,1.000000,", 0), 0U);
  EXPECT_NE(read_file(tmp / "report.md").find("| all | 10 | 0 | 0 | - | 0 | 0 | 0 |"), std::string::npos);
}

// ------------------------------------------------------------------ integrity

/** A run with integrity figures: per axis, outputs beyond 3 and 5 sigma and the worst ratio. */
RunResult flown(std::uint32_t index, std::uint64_t seed, double final_m, double max_m, double fix_s, double converged_s,
                std::uint64_t outputs, std::array<std::uint64_t, 3> b3, std::array<std::uint64_t, 3> b5,
                std::array<double, 3> worst) {
  RunResult r = run(index, "none", Outcome::kMasked);
  r.seed = seed;
  r.has_integrity = true;
  r.final_error_m = final_m;
  r.max_error_m = max_m;
  r.fix_at_s = fix_s;
  r.converged_at_s = converged_s;
  r.integrity_outputs = outputs;
  r.beyond_3sigma = b3;
  r.beyond_5sigma = b5;
  r.worst_ratio = worst;
  return r;
}

/** Four runs with figures (one never converged) and a crashed one without, in shuffled order. */
std::vector<RunResult> sweep_runs() {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  RunResult crashed = run(4, "none", Outcome::kCrash);
  crashed.seed = 14;
  return {flown(3, 13, 0.3, 2.0, 2.2, 2.9, 2000, {0, 35, 0}, {0, 1, 0}, {0.5, 2.5, 0.6}), crashed,
          flown(0, 10, 0.5, 1.0, 2.3, 3.0, 1000, {0, 5, 20}, {0, 0, 2}, {0.8, 1.1, 1.9}),
          flown(2, 12, 0.9, nan, -1.0, -1.0, 0, {0, 0, 0}, {0, 0, 0}, {nan, nan, nan}),
          flown(1, 11, 0.2, 4.0, 2.25, 3.1, 1000, {10, 0, 0}, {0, 0, 0}, {1.5, 0.9, 0.7})};
}

// The integrity of a sweep: the spreads by linear interpolation over the runs that have the figure, the
// axes pooled over the outputs, a run at exactly the 1 % bound not over it, and the worst run of each.
TEST(SummarizeIntegrity, PoolsTheAxesAndNamesTheWorstRuns) {
  const tools::campaign::Report rep = tools::campaign::summarize("sweep", sweep_runs());
  const tools::campaign::IntegrityReport& r = rep.integrity;
  EXPECT_EQ(r.runs, 4U) << "the crashed run has no figures";
  EXPECT_EQ(r.not_converged, 1U);
  ASSERT_EQ(rep.per_run.size(), 4U);
  EXPECT_EQ(rep.per_run[0].index, 0U) << "by index";
  EXPECT_EQ(rep.per_run[3].index, 3U);
  EXPECT_EQ(r.final_error_m.n, 4U);
  EXPECT_NEAR(r.final_error_m.median, 0.4, 1e-12);  // 0.2 0.3 | 0.5 0.9
  EXPECT_NEAR(r.final_error_m.p90, 0.78, 1e-12);    // 0.5 + 0.7 (0.9 - 0.5)
  EXPECT_EQ(r.final_error_m.max, 0.9);
  EXPECT_EQ(r.final_error_m.max_index, 2U);
  EXPECT_EQ(r.final_error_m.max_seed, 12U);
  EXPECT_EQ(r.max_error_m.n, 3U) << "the run that never converged has no maximum after convergence";
  EXPECT_NEAR(r.max_error_m.median, 2.0, 1e-12);
  EXPECT_NEAR(r.max_error_m.p90, 3.6, 1e-12);
  EXPECT_EQ(r.max_error_m.max_seed, 11U);
  EXPECT_EQ(r.runs_over_max_error, 1U);
  const std::array<std::uint64_t, 3> b3 = {10, 40, 20};
  const std::array<std::uint64_t, 3> b5 = {0, 1, 2};
  const std::array<std::uint64_t, 3> over = {0, 1, 1};  // x: 10 of 1000 is the bound itself, not beyond it
  const std::array<std::uint64_t, 3> with5 = {0, 1, 1};
  const std::array<double, 3> worst = {1.5, 2.5, 1.9};
  const std::array<std::uint64_t, 3> worst_seed = {11, 13, 10};
  for (std::size_t a = 0; a < 3U; ++a) {
    const tools::campaign::AxisIntegrity& ax = r.axes[a];
    EXPECT_EQ(ax.outputs, 4000U) << a;
    EXPECT_EQ(ax.beyond_3sigma, b3[a]) << a;
    EXPECT_EQ(ax.beyond_5sigma, b5[a]) << a;
    EXPECT_EQ(ax.runs_over_fraction, over[a]) << a;
    EXPECT_EQ(ax.runs_beyond_5sigma, with5[a]) << a;
    EXPECT_EQ(ax.worst_ratio, worst[a]) << a;
    EXPECT_EQ(ax.worst_seed, worst_seed[a]) << a;
  }
}

// The report carries the integrity: the JSON figures, a Markdown table per axis, integrity.csv one row per
// run with figures (an empty field where a value is not finite), the plot script; a later report of runs
// without figures removes them, so the folder never mixes two campaigns' figures.
TEST(WriteReport, TheIntegrityFilesHoldTheRunsWithFigures) {
  TempDir tmp;
  const tools::campaign::Report rep = tools::campaign::summarize("sweep", sweep_runs());
  std::string err;
  std::string note;
  ASSERT_TRUE(tools::campaign::write_report(rep, tmp / "r", err, note)) << err;
  const fs::path dir = tmp / "r";
  const nlohmann::json j = nlohmann::json::parse(read_file(dir / "report.json"));
  const nlohmann::json& in = j.at("integrity");
  EXPECT_EQ(in.at("runs"), 4);
  EXPECT_EQ(in.at("not_converged"), 1);
  EXPECT_EQ(in.at("runs_over_max_error_bound"), 1);
  EXPECT_EQ(in.at("max_error_after_convergence_m").at("max_seed"), 11);
  EXPECT_EQ(in.at("y").at("beyond_3sigma"), 40);
  EXPECT_DOUBLE_EQ(in.at("y").at("beyond_3sigma_fraction").get<double>(), 40.0 / 4000.0);
  EXPECT_EQ(in.at("z").at("worst_seed"), 10);

  const std::string md = read_file(dir / "report.md");
  EXPECT_NE(md.find("## Navigation integrity"), std::string::npos) << md;
  EXPECT_NE(md.find("| y | 4000 | 40 (1.00 %) | 1 | 1 | 1 | 2.5 (run 3, seed 13) |"), std::string::npos) << md;
  EXPECT_NE(md.find("1 of 3 converged runs beyond 3 m"), std::string::npos) << md;

  const std::vector<std::string> csv = lines_of(read_file(dir / "integrity.csv"));
  ASSERT_EQ(csv.size(), 5U);
  EXPECT_EQ(csv[0], tools::campaign::kIntegrityCsvHeader);
  EXPECT_EQ(csv[1], "0,10,masked,0.5,1,2.3,3,1000,0,5,20,0,0,2,0.8,1.1,1.9");
  EXPECT_EQ(csv[3], "2,12,masked,0.9,,,,0,0,0,0,0,0,0,,,") << "never converged: no maximum, no times, no ratios";
  const std::string gp = read_file(dir / "integrity.gp");
  EXPECT_NE(gp.find("'integrity.png'"), std::string::npos);
  EXPECT_NE(gp.find("2 12 0.9 NaN NaN NaN NaN"), std::string::npos) << gp;
  // `make deps` installs gnuplot: the plot is made, and a note would say why it was not.
  EXPECT_TRUE(note.empty()) << note;
  EXPECT_TRUE(is_png(dir / "integrity.png"));

  ASSERT_TRUE(tools::campaign::write_report(tools::campaign::summarize("faults", ten_runs()), dir, err, note)) << err;
  for (const char* f : {"integrity.csv", "integrity.gp", "integrity.png"}) {
    EXPECT_FALSE(fs::exists(dir / f)) << f << " of the earlier report is gone";
  }
  EXPECT_NE(read_file(dir / "report.md").find("No run gave integrity figures."), std::string::npos);
}

// ------------------------------------------------------------------ CST-06 report files

// CST-06: the report files are written, the JSON holds the counts, the CSV one row per class of "all"
// and of each kind, the Markdown a column per kind; no temporary file is left behind.
TEST(WriteReport, WritesTheReportFilesWithTheCounts) {
  TempDir tmp;
  const std::vector<RunResult> runs = ten_runs();
  const tools::campaign::Report r = tools::campaign::summarize("demo", runs);
  std::string err;
  std::string note;
  ASSERT_TRUE(tools::campaign::write_report(r, tmp / "out/report", err, note)) << err;
  const fs::path dir = tmp / "out/report";
  for (const char* f : {"report.json", "report.csv", "report.md", "coverage.csv", "runs.csv", "outcomes.gp"}) {
    EXPECT_TRUE(fs::is_regular_file(dir / f)) << f;
  }
  EXPECT_TRUE(hidden_entries(dir).empty()) << hidden_entries(dir).front();

  const nlohmann::json j = nlohmann::json::parse(read_file(dir / "report.json"));
  EXPECT_EQ(j.at("campaign"), "demo");
  EXPECT_EQ(j.at("runs"), 10);
  EXPECT_DOUBLE_EQ(j.at("confidence").get<double>(), 0.95);
  EXPECT_DOUBLE_EQ(j.at("host_s_total").get<double>(), 11.5);
  EXPECT_DOUBLE_EQ(j.at("margin_at_runs").get<double>(), r.margin_at_runs);
  EXPECT_EQ(j.at("classes").at("masked").at("count"), 2);
  EXPECT_EQ(j.at("classes").at("detected_recovered").at("count"), 4);
  EXPECT_DOUBLE_EQ(j.at("classes").at("detected_recovered").at("fraction").get<double>(), 0.4);
  const auto sdc = static_cast<std::size_t>(Outcome::kSdc);
  EXPECT_DOUBLE_EQ(j.at("classes").at("sdc").at("cp").at("hi").get<double>(), r.classes[sdc].cp.hi);
  EXPECT_DOUBLE_EQ(j.at("classes").at("sdc").at("wilson").at("lo").get<double>(), r.classes[sdc].wilson.lo);
  ASSERT_EQ(j.at("kinds").size(), 3U);
  EXPECT_EQ(j.at("kinds")[0].at("kind"), "core_hang");
  EXPECT_EQ(j.at("kinds")[0].at("runs"), 5);
  EXPECT_EQ(j.at("kinds")[0].at("classes").at("detected_recovered").at("count"), 3);
  EXPECT_EQ(j.at("kinds")[1].at("classes").at("masked").at("count"), 2);

  const std::vector<std::string> csv = lines_of(read_file(dir / "report.csv"));
  ASSERT_EQ(csv.size(), 1U + 8U * 4U) << "header, the all block and three kinds of eight classes";
  EXPECT_EQ(csv[0], tools::campaign::kReportCsvHeader);
  EXPECT_EQ(csv[0], "kind,outcome,count,runs,fraction,cp_lo,cp_hi,wilson_lo,wilson_hi");
  EXPECT_EQ(csv[1].rfind("all,not_delivered,0,10,0.000000,", 0), 0U) << csv[1];
  EXPECT_EQ(csv[2].rfind("all,no_effect,0,10,0.000000,", 0), 0U) << csv[2];
  EXPECT_EQ(csv[3].rfind("all,masked,2,10,0.200000,", 0), 0U) << csv[3];
  EXPECT_EQ(csv[11].rfind("core_hang,masked,0,5,0.000000,0.000000,", 0), 0U) << csv[11];
  EXPECT_EQ(csv[20].rfind("sdc,detected_recovered,1,4,0.250000,", 0), 0U) << csv[20];
  EXPECT_EQ(csv[29].rfind("unknown,detected_degraded,1,1,1.000000,", 0), 0U) << csv[29];

  const std::string md = read_file(dir / "report.md");
  EXPECT_NE(md.find("| outcome | all (10 runs) | core_hang (5 runs) | sdc (4 runs) | unknown (1 runs) |"),
            std::string::npos)
      << md;
  std::size_t table_lines = 0;
  for (const std::string& l : lines_of(md)) {
    table_lines += l.rfind("| ", 0) == 0U || l.rfind("|---", 0) == 0U ? 1U : 0U;
  }
  EXPECT_EQ(table_lines, 2U + 8U + 2U + 1U + 3U + 1U)
      << "classes: header, rule and one row per class; coverage: header, rule, all, three kinds, one role (none "
         "given: unknown)\n"
      << md;
  // 4/10 and 3/5: Clopper-Pearson [12.2, 73.8] % and [14.7, 94.7] % (binom.test(4, 10), binom.test(3, 5)).
  EXPECT_NE(md.find("| detected_recovered | 4 (40.0 %, CP 12.2-73.8 %) | 3 (60.0 %, CP 14.7-94.7 %) |"),
            std::string::npos)
      << md;

  const std::string gp = read_file(dir / "outcomes.gp");
  EXPECT_NE(gp.find("pngcairo"), std::string::npos);
  EXPECT_NE(gp.find("'outcomes.png'"), std::string::npos);
  EXPECT_NE(gp.find("yerrorbars"), std::string::npos);
  EXPECT_NE(gp.find("3 detected_recovered 40.000000 "), std::string::npos) << gp;
  EXPECT_NE(gp.find("\"not\\ndelivered\" 0"), std::string::npos) << "the first bar\n" << gp;
}

// CST-06: with gnuplot installed the chart is made and renamed into place.
TEST(WriteReport, GnuplotMakesTheChart) {
  TempDir tmp;
  const std::vector<RunResult> runs = ten_runs();
  std::string err;
  std::string note;
  ASSERT_TRUE(tools::campaign::write_report(tools::campaign::summarize("it's a demo", runs), tmp.path(), err, note))
      << err;
  // `make deps` installs gnuplot; the no-gnuplot case has its own test.
  ASSERT_EQ(note.find("gnuplot is not installed"), std::string::npos) << note << " (make deps installs it)";
  EXPECT_TRUE(note.empty()) << note << "\n" << read_file(tmp / "plots.log");
  EXPECT_TRUE(is_png(tmp / "outcomes.png"));
  EXPECT_TRUE(hidden_entries(tmp.path()).empty()) << hidden_entries(tmp.path()).front();
}

// CST-06: without gnuplot the report is whole, the script stays and a single line on stderr says so.
TEST(WriteReport, WithoutGnuplotTheReportIsWrittenAndANoteSaysSo) {
  TempDir tmp;
  fs::create_directory(tmp / "empty_bin");
  const std::vector<RunResult> runs = ten_runs();
  const tools::campaign::Report r = tools::campaign::summarize("demo", runs);
  std::string err;
  bool ok = false;
  testing::internal::CaptureStderr();
  {
    const PathOverride path((tmp / "empty_bin").string());
    ok = tools::campaign::write_report(r, tmp / "report", err);
  }
  const std::string stderr_text = testing::internal::GetCapturedStderr();
  ASSERT_TRUE(ok) << err;
  EXPECT_NE(stderr_text.find("gnuplot is not installed"), std::string::npos) << stderr_text;
  EXPECT_EQ(lines_of(stderr_text).size(), 1U) << stderr_text;
  EXPECT_TRUE(fs::exists(tmp / "report/outcomes.gp"));
  EXPECT_TRUE(fs::exists(tmp / "report/report.json"));
  EXPECT_FALSE(fs::exists(tmp / "report/outcomes.png"));
}

// CST-06: a gnuplot that fails is a note; no half-made chart is left.
TEST(WriteReport, AGnuplotThatFailsIsANote) {
  TempDir tmp;
  fs::create_directory(tmp / "bin");
  write_file(tmp / "bin/gnuplot", "#!/bin/sh\necho broken >&2\nexit 3\n");
  fs::permissions(tmp / "bin/gnuplot", fs::perms::owner_all);
  const std::vector<RunResult> runs = ten_runs();
  std::string err;
  std::string note;
  bool ok = false;
  {
    const PathOverride path((tmp / "bin").string());
    ok = tools::campaign::write_report(tools::campaign::summarize("demo", runs), tmp / "report", err, note);
  }
  ASSERT_TRUE(ok) << err;
  EXPECT_NE(note.find("gnuplot outcomes.gp failed (exit status 3; see plots.log)"), std::string::npos) << note;
  EXPECT_FALSE(fs::exists(tmp / "report/outcomes.png"));
  EXPECT_TRUE(hidden_entries(tmp / "report").empty()) << hidden_entries(tmp / "report").front();
}

// CST-06: a second report replaces the first; kind names with separators stay one CSV field.
TEST(WriteReport, ASecondReportReplacesTheFirstAndQuotesOddNames) {
  TempDir tmp;
  std::string err;
  std::string note;
  const PathOverride path("/nonexistent");  // the chart is not what this test is about
  const std::vector<RunResult> first = ten_runs();
  ASSERT_TRUE(tools::campaign::write_report(tools::campaign::summarize("one", first), tmp.path(), err, note)) << err;
  const std::vector<RunResult> second = {run(0, "a,\"b\"", Outcome::kSdc), run(1, "a|b", Outcome::kMasked)};
  ASSERT_TRUE(tools::campaign::write_report(tools::campaign::summarize("two", second), tmp.path(), err, note)) << err;
  const nlohmann::json j = nlohmann::json::parse(read_file(tmp / "report.json"));
  EXPECT_EQ(j.at("campaign"), "two");
  EXPECT_EQ(j.at("runs"), 2);
  const std::vector<std::string> csv = lines_of(read_file(tmp / "report.csv"));
  ASSERT_EQ(csv.size(), 1U + 8U * 3U);
  EXPECT_EQ(csv[11].rfind("\"a,\"\"b\"\"\",masked,0,1,", 0), 0U) << csv[11];
  EXPECT_NE(read_file(tmp / "report.md").find("a\\|b (1 runs)"), std::string::npos);
}

// CST-06: a folder that cannot be made is an error with a message naming it; so is a file in its place.
TEST(WriteReport, AnUnwritableFolderIsAnError) {
  TempDir tmp;
  write_file(tmp / "plain_file", "not a folder\n");
  const tools::campaign::Report r = tools::campaign::summarize("demo", {});
  std::string err;
  EXPECT_FALSE(tools::campaign::write_report(r, tmp / "plain_file/report", err));
  EXPECT_NE(err.find("plain_file/report"), std::string::npos) << err;
  err.clear();
  EXPECT_FALSE(tools::campaign::write_report(r, tmp / "plain_file", err));
  EXPECT_NE(err.find("plain_file"), std::string::npos) << err;
  EXPECT_EQ(read_file(tmp / "plain_file"), "not a folder\n") << "the file in the way is untouched";
}

// CST-06: a folder without write permission is an error, and nothing is left in it.
TEST(WriteReport, AReadOnlyFolderIsAnError) {
  TempDir tmp;
  fs::create_directory(tmp / "ro");
  fs::permissions(tmp / "ro", fs::perms::owner_read | fs::perms::owner_exec);
  std::string err;
  {
    // Root writes through permission bits unless this thread lowers the capabilities that let it.
    const test_support::PermissionBitsHold bits;
    ASSERT_NE(::faccessat(AT_FDCWD, (tmp / "ro").c_str(), W_OK, AT_EACCESS), 0)
        << "the folder's permission bits do not stop this process";
    EXPECT_FALSE(tools::campaign::write_report(tools::campaign::summarize("demo", {}), tmp / "ro", err));
  }
  EXPECT_NE(err.find("report.json"), std::string::npos) << err;
  EXPECT_TRUE(fs::is_empty(tmp / "ro"));
}

}  // namespace
