/**
 * @file campaign_stats.hpp
 * @brief Fault-injection campaign statistics: outcome classes, binomial confidence intervals, runs for a margin, reports.
 *
 * A campaign is many runs of the mission image, each with injected faults and
 * one outcome class. The fraction of runs in a class is a binomial proportion:
 * it is reported with an exact (Clopper-Pearson) and a Wilson score interval,
 * over all runs and per fault kind; so is the detection coverage, also per
 * target role, beside the runs that raised each flag (docs/CAMPAIGNS.md,
 * "Statistics").
 *
 * Host code: std containers and exceptions are fine here. The interval and
 * run-count functions throw std::invalid_argument on arguments outside their
 * domain (the message names the function and the argument). Exceptions of the
 * numerics library (Boost.Math) never leave this module as its own types: a
 * failure inside it, not expected within the domain, is a std::runtime_error.
 */
#pragma once

#include "tools/common/mission/nav_integrity.hpp"

#include <array>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace tools::campaign {

/**
 * What a run ended as (docs/CAMPAIGNS.md, "Outcome classes"): first the runs where no fault mattered (none
 * reached the chip; the delivered navigation stream is the fault-free one), then from the best to the worst
 * for the mission.
 */
enum class Outcome : std::uint8_t { kNotDelivered, kNoEffect, kMasked, kRecovered, kDegraded, kLost, kSdc, kCrash };
inline constexpr std::size_t kOutcomeCount = 8;

/** Every outcome in report order (the order of the enum). */
inline constexpr std::array<Outcome, kOutcomeCount> kOutcomes = {
    Outcome::kNotDelivered, Outcome::kNoEffect, Outcome::kMasked, Outcome::kRecovered,
    Outcome::kDegraded,     Outcome::kLost,     Outcome::kSdc,    Outcome::kCrash};

/**
 * "not_delivered", "no_effect", "masked", "detected_recovered", "detected_degraded", "detected_lost", "sdc",
 * "hang_crash"; "?" for a value outside the enum.
 */
const char* outcome_name(Outcome o) noexcept;

/** The outcome named @p name (exactly as outcome_name() spells it). @return false, @p out untouched, for any other name. */
bool outcome_from_name(std::string_view name, Outcome& out) noexcept;

/** Whether @p o is one of the detected classes (detected_recovered, detected_degraded, detected_lost). */
bool is_detected(Outcome o) noexcept;

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
  std::string role;              ///< the target drawn: a role, "tile_<n>" for a tile; "mixed" when the faults' differ
  Outcome outcome = Outcome::kMasked;
  double final_error_m = 0.0;
  double max_error_m = 0.0;      ///< max position error after convergence (NaN: the filter never converged)
  double host_s = 0.0;           ///< host seconds the run took
  std::uint32_t injected = 0, detected = 0, recovered = 0;
  std::uint32_t not_delivered = 0;      ///< faults armed but never delivered to the chip
  std::uint32_t degraded_accepted = 0;  ///< detected faults whose recovery gave up a mode (e.g. TMR to simplex)
  /// Flags (docs/CAMPAIGNS.md, "Flags"): counts from the summary; they do not change the class.
  std::uint32_t misdiagnosed = 0;       ///< faults for which the flight accused the wrong tile or the wrong class
  std::uint32_t false_alarms = 0;       ///< accusations no injected fault explains
  std::uint32_t healthy_disturbed = 0;  ///< healthy tiles reset, retired, excluded or outvoted
  bool output_as_golden = false;        ///< the delivered navigation stream's CRC is the golden run's (same seed)
  std::optional<std::uint32_t> output_crc;  ///< the summary's filter_output_crc; none without a summary
  std::uint64_t seed = 0;        ///< the scenario seed the run flew
  /// Navigation integrity from the run's summary (docs/FILTER.md, "Integrity"): set only when the image
  /// exited well and its summary gave the figures.
  bool has_integrity = false;
  double fix_at_s = -1.0;        ///< when the filter's horizontal 3-sigma first fell below tools::kFixSigma3M; < 0: never
  double converged_at_s = -1.0;  ///< when it first fell to tools::kConvergedSigma3M; < 0: never
  std::uint64_t integrity_outputs = 0;          ///< outputs from the fix on held against their own 3-sigma
  std::array<std::uint64_t, 3> beyond_3sigma{};  ///< per axis (x, y, z): outputs whose error exceeds their 3-sigma
  std::array<std::uint64_t, 3> beyond_5sigma{};  ///< per axis: outputs whose error exceeds their 5-sigma
  std::array<double, 3> worst_ratio{};           ///< per axis: the largest |error| / (3 sigma)
};

/** The integrity targets a report holds the runs against (issue "navigation integrity"). */
inline constexpr double kIntegrityMaxErrorBoundM = 3.0;  ///< max error after convergence, on every run
static_assert(kIntegrityMaxErrorBoundM >= kConvergedSigma3M,
              "a run is held to its bound only once the filter claims at least that accuracy");
inline constexpr double kIntegrityFractionBound = 0.01;  ///< outputs beyond 3-sigma, per axis, over all runs

/** A distribution of one figure over runs: quantiles by linear interpolation (R's type 7). */
struct Spread {
  std::uint64_t n = 0;           ///< runs with a finite value
  double median = 0.0, p90 = 0.0, max = 0.0;
  std::uint32_t max_index = 0;   ///< the run with the largest value
  std::uint64_t max_seed = 0;    ///< its scenario seed
};

/** One axis over all runs. */
struct AxisIntegrity {
  std::uint64_t outputs = 0;
  std::uint64_t beyond_3sigma = 0;       ///< outputs beyond their 3-sigma, pooled over the runs
  std::uint64_t beyond_5sigma = 0;
  std::uint64_t runs_over_fraction = 0;  ///< runs whose own fraction beyond 3-sigma exceeds kIntegrityFractionBound
  std::uint64_t runs_beyond_5sigma = 0;  ///< runs with at least one output beyond 5-sigma
  double worst_ratio = 0.0;              ///< the largest |error| / (3 sigma) of any run
  std::uint32_t worst_index = 0;
  std::uint64_t worst_seed = 0;
};

/** The integrity of the runs that gave figures. */
struct IntegrityReport {
  std::uint64_t runs = 0;            ///< runs with integrity figures
  std::uint64_t not_converged = 0;   ///< of those, runs whose filter never converged
  Spread final_error_m;              ///< over the runs with figures
  Spread max_error_m;                ///< max error after convergence, over the converged runs
  std::uint64_t runs_over_max_error = 0;  ///< converged runs whose max error after convergence exceeds kIntegrityMaxErrorBoundM
  std::array<AxisIntegrity, 3> axes{};
};

/** The figures of @p runs that gave them (has_integrity). */
IntegrityReport summarize_integrity(std::span<const RunResult> runs);

/** The runs of one class and the intervals of their fraction. */
struct ClassCount {
  std::uint64_t count = 0;
  Interval cp{};      ///< Clopper-Pearson
  Interval wilson{};  ///< Wilson score
};

/**
 * Detection coverage: of the runs with a fault delivered to the chip (injected > 0) whose class is neither
 * no_effect nor hang_crash (no summary: delivery and detection unknown), those in a detected class.
 */
struct Coverage {
  std::uint64_t detected = 0;
  std::uint64_t eligible = 0;  ///< the denominator
  Interval cp{};               ///< Clopper-Pearson of detected / eligible ([0, 1] when none is eligible)
  Interval wilson{};
};

/** Runs with each flag raised (a count above zero in the run's summary). */
struct FlagCounts {
  std::uint64_t false_alarm = 0;        ///< runs with false_alarms > 0
  std::uint64_t misdiagnosed = 0;       ///< runs with misdiagnosed > 0
  std::uint64_t healthy_disturbed = 0;  ///< runs with healthy_tiles_disturbed > 0
};

/** The runs of one fault kind or one target role. */
struct GroupReport {
  std::string name;  ///< the kind or the role
  std::uint64_t runs = 0;
  std::array<ClassCount, kOutcomeCount> classes{};  ///< indexed by the Outcome's value
  Coverage coverage;
  FlagCounts flags;
};

/** Name given to the kind or role of a run whose kind or role is empty. */
inline constexpr const char* kUnknownKind = "unknown";

struct Report {
  std::string campaign;          ///< name
  double confidence = 0.95;
  std::uint64_t runs = 0;
  std::array<ClassCount, kOutcomeCount> classes{};   ///< over all runs, indexed by the Outcome's value
  Coverage coverage;                                 ///< over all runs
  FlagCounts flags;                                  ///< over all runs
  std::vector<GroupReport> kinds;                    ///< per fault kind, sorted by kind name
  std::vector<GroupReport> roles;                    ///< per target role, sorted by role name
  double margin_at_runs = 0.0;   ///< margin_for_runs(runs, confidence): worst case p = 0.5, infinite population
  double host_s_total = 0.0;
  IntegrityReport integrity;     ///< navigation integrity of the runs
  std::vector<RunResult> per_run;  ///< the runs with integrity figures, by index (integrity.csv and its plot)
  std::vector<RunResult> all_runs;  ///< every run, by index (runs.csv)
};

/** Coverage of @p runs at @p conf (see Coverage). @throws std::invalid_argument if conf is not inside (0, 1). */
Coverage coverage_of(std::span<const RunResult> runs, double conf = 0.95);

/**
 * Counts the runs per class, the coverage and the flags, over all, per kind and
 * per role (a run with an empty kind or role counts as kUnknownKind), with both
 * intervals at @p conf.
 * @throws std::invalid_argument if conf is not inside (0, 1).
 */
Report summarize(std::string_view campaign, std::span<const RunResult> runs, double conf = 0.95);

/** The header line of report.csv. */
inline constexpr const char* kReportCsvHeader = "kind,outcome,count,runs,fraction,cp_lo,cp_hi,wilson_lo,wilson_hi";

/** report.json: every figure of @p r (fractions too), two-space indented. */
std::string report_json(const Report& r);
/** report.csv: the header, the "all" block (one row per class), then one block per kind in the report's order. */
std::string report_csv(const Report& r);
/** report.md: a heading, the run count, confidence and margin, the table of classes by kind, coverage and flags. */
std::string report_md(const Report& r);
/** The header line of coverage.csv. */
inline constexpr const char* kCoverageCsvHeader =
    "group,name,runs,eligible,detected,coverage,cp_lo,cp_hi,wilson_lo,wilson_hi,false_alarm_runs,misdiagnosed_runs,"
    "healthy_disturbed_runs";
/** coverage.csv: the "all,all" row, then one row per kind ("kind,<k>") and per role ("role,<r>"). */
std::string coverage_csv(const Report& r);
/** The header line of runs.csv. */
inline constexpr const char* kRunsCsvHeader =
    "index,kind,role,seed,outcome,final_error_m,injected,not_delivered,detected,recovered,degraded_accepted,"
    "misdiagnosed,false_alarms,healthy_tiles_disturbed,output_as_golden";
/** runs.csv: one row per run, by index, with its class and flags. */
std::string runs_csv(const Report& r);
/** The header line of integrity.csv. */
inline constexpr const char* kIntegrityCsvHeader =
    "index,seed,outcome,final_error_m,max_error_m,fix_at_s,converged_at_s,outputs,beyond_3sigma_x,beyond_3sigma_y,"
    "beyond_3sigma_z,beyond_5sigma_x,beyond_5sigma_y,beyond_5sigma_z,worst_ratio_x,worst_ratio_y,worst_ratio_z";
/** integrity.csv: one row per run with integrity figures (an empty field: a value that is not finite). */
std::string integrity_csv(const Report& r);
/** integrity.gp: per run, the final and the maximum error after convergence, and the fraction beyond 3-sigma per axis. */
std::string integrity_gnuplot(const Report& r);

/** outcomes.gp: the bar chart of the fraction per class over all runs with Clopper-Pearson error bars. */
std::string report_gnuplot(const Report& r);

/**
 * Writes report.json, report.csv, report.md, coverage.csv, runs.csv and outcomes.gp into @p dir
 * (created if missing), each atomically (a temporary name in @p dir, then a
 * rename), and, when gnuplot is on the PATH, runs outcomes.gp to make
 * outcomes.png (also renamed into place). When runs gave integrity figures,
 * integrity.csv, integrity.gp and integrity.png too (else any of an earlier
 * report are removed, so the folder never shows figures of other runs). No gnuplot, or a gnuplot that fails,
 * is not an error: @p note says so and the report stays whole.
 * @return false with the reason in @p err if a file cannot be written.
 */
bool write_report(const Report& r, const std::filesystem::path& dir, std::string& err, std::string& note);

/** Same; a note (if any) goes to stderr as one line. */
bool write_report(const Report& r, const std::filesystem::path& dir, std::string& err);

}  // namespace tools::campaign
