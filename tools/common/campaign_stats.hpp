/**
 * @file campaign_stats.hpp
 * @brief Fault-injection campaign statistics: outcome classes, binomial confidence intervals, runs for a margin, reports.
 *
 * A campaign is many runs of the mission image, each with injected faults and
 * one outcome class. The fraction of runs in a class is a binomial proportion:
 * it is reported with an exact (Clopper-Pearson) and a Wilson score interval,
 * over all runs and per fault kind (docs/CAMPAIGNS.md, "Statistics").
 *
 * Host code: std containers and exceptions are fine here. The interval and
 * run-count functions throw std::invalid_argument on arguments outside their
 * domain (the message names the function and the argument). Exceptions of the
 * numerics library (Boost.Math) never leave this module as its own types: a
 * failure inside it, not expected within the domain, is a std::runtime_error.
 */
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace tools::campaign {

/** What a run ended as, from the best to the worst for the mission. */
enum class Outcome : std::uint8_t { kMasked, kRecovered, kDegraded, kLost, kSdc, kCrash };
inline constexpr std::size_t kOutcomeCount = 6;

/** Every outcome in report order (the order of the enum). */
inline constexpr std::array<Outcome, kOutcomeCount> kOutcomes = {Outcome::kMasked, Outcome::kRecovered,
                                                                 Outcome::kDegraded, Outcome::kLost,
                                                                 Outcome::kSdc,      Outcome::kCrash};

/** "masked", "detected_recovered", "detected_degraded", "detected_lost", "sdc", "hang_crash"; "?" for a value outside the enum. */
const char* outcome_name(Outcome o) noexcept;

/** The outcome named @p name (exactly as outcome_name() spells it). @return false, @p out untouched, for any other name. */
bool outcome_from_name(std::string_view name, Outcome& out) noexcept;

/** A closed interval of a proportion, both ends in [0, 1]. */
struct Interval {
  double lo;
  double hi;
};

/**
 * Exact (Clopper-Pearson) two-sided interval for @p k successes in @p n trials
 * at confidence @p conf: the ends are quantiles of beta distributions,
 * lo = B^-1(alpha/2; k, n-k+1), hi = B^-1(1-alpha/2; k+1, n-k), alpha = 1 - conf.
 * n == 0 gives {0, 1}; k == 0 gives lo 0; k == n gives hi 1.
 * @throws std::invalid_argument if k > n or conf is not inside (0, 1).
 */
Interval clopper_pearson(std::uint64_t k, std::uint64_t n, double conf = 0.95);

/**
 * Wilson score interval: (p + z^2/2n -+ z sqrt(p(1-p)/n + z^2/4n^2)) / (1 + z^2/n),
 * p = k/n, z the two-sided normal quantile for @p conf. n == 0 gives {0, 1};
 * k == 0 gives lo 0 and k == n hi 1 exactly.
 * @throws std::invalid_argument if k > n or conf is not inside (0, 1).
 */
Interval wilson(std::uint64_t k, std::uint64_t n, double conf = 0.95);

/** The two-sided standard normal quantile for @p conf (1.959964 for 0.95). @throws std::invalid_argument outside (0, 1). */
double normal_quantile(double conf);

/**
 * Runs needed for an error margin @p margin (a proportion, 0.01 = 1 %) at
 * confidence @p conf, for an expected proportion @p p (0.5 is the worst case),
 * out of a population of @p population possible faults (Leveugle et al.,
 * DATE 2009, "Statistical fault injection: quantified error and confidence"):
 * n = N / (1 + e^2 (N - 1) / (t^2 p (1 - p))), t the normal quantile for conf.
 * population == 0 means infinite: n = t^2 p (1 - p) / e^2. Rounded up (a value
 * within 1e-9 of an integer counts as that integer).
 * @throws std::invalid_argument if margin, conf or p is not inside (0, 1).
 */
std::uint64_t runs_for_margin(double margin, double conf = 0.95, double p = 0.5, std::uint64_t population = 0);

/**
 * The inverse of runs_for_margin() for the worst case p = 0.5 and an infinite
 * population: the half-width t / (2 sqrt(runs)) that @p runs give at @p conf;
 * 0.5 (the half-width of [0, 1]) for no runs.
 * @throws std::invalid_argument if conf is not inside (0, 1).
 */
double margin_for_runs(std::uint64_t runs, double conf = 0.95);

/** One run of a campaign, as the campaign driver collected it. */
struct RunResult {
  std::uint32_t index = 0;       ///< run index in the campaign
  std::string kind;              ///< the fault kind of the run ("core_hang", "sdc", ...; "mixed" when several kinds)
  Outcome outcome = Outcome::kMasked;
  double final_error_m = 0.0;
  double max_error_m = 0.0;      ///< max position error after convergence
  double host_s = 0.0;           ///< host seconds the run took
  std::uint32_t injected = 0, detected = 0, recovered = 0;
};

/** The runs of one class and the intervals of their fraction. */
struct ClassCount {
  std::uint64_t count = 0;
  Interval cp{};      ///< Clopper-Pearson
  Interval wilson{};  ///< Wilson score
};

/** The classes of the runs of one fault kind. */
struct KindReport {
  std::string kind;
  std::uint64_t runs = 0;
  std::array<ClassCount, kOutcomeCount> classes{};  ///< indexed by the Outcome's value
};

/** Name given to the kind of a run whose kind is empty. */
inline constexpr const char* kUnknownKind = "unknown";

struct Report {
  std::string campaign;          ///< name
  double confidence = 0.95;
  std::uint64_t runs = 0;
  std::array<ClassCount, kOutcomeCount> classes{};   ///< over all runs, indexed by the Outcome's value
  std::vector<KindReport> kinds;                     ///< per fault kind, sorted by kind name
  double margin_at_runs = 0.0;   ///< margin_for_runs(runs, confidence): worst case p = 0.5, infinite population
  double host_s_total = 0.0;
};

/**
 * Counts the runs per class, over all and per kind (a run with an empty kind
 * counts as kUnknownKind), with both intervals at @p conf.
 * @throws std::invalid_argument if conf is not inside (0, 1).
 */
Report summarize(std::string_view campaign, std::span<const RunResult> runs, double conf = 0.95);

/** The header line of report.csv. */
inline constexpr const char* kReportCsvHeader = "kind,outcome,count,runs,fraction,cp_lo,cp_hi,wilson_lo,wilson_hi";

/** report.json: every figure of @p r (fractions too), two-space indented. */
std::string report_json(const Report& r);
/** report.csv: the header, the "all" block (one row per class), then one block per kind in the report's order. */
std::string report_csv(const Report& r);
/** report.md: a heading, the run count, confidence and margin, and the table of classes by kind. */
std::string report_md(const Report& r);
/** outcomes.gp: the bar chart of the fraction per class over all runs with Clopper-Pearson error bars. */
std::string report_gnuplot(const Report& r);

/**
 * Writes report.json, report.csv, report.md and outcomes.gp into @p dir
 * (created if missing), each atomically (a temporary name in @p dir, then a
 * rename), and, when gnuplot is on the PATH, runs outcomes.gp to make
 * outcomes.png (also renamed into place). No gnuplot, or a gnuplot that fails,
 * is not an error: @p note says so and the report stays whole.
 * @return false with the reason in @p err if a file cannot be written.
 */
bool write_report(const Report& r, const std::filesystem::path& dir, std::string& err, std::string& note);

/** Same; a note (if any) goes to stderr as one line. */
bool write_report(const Report& r, const std::filesystem::path& dir, std::string& err);

}  // namespace tools::campaign
