/**
 * @file campaign_stats.cpp
 * @brief Binomial intervals (Boost.Math quantiles), runs for a margin, per-kind summaries and the campaign report files.
 */
#include "tools/common/campaign/campaign_stats.hpp"

#include "tools/common/gnuplot.hpp"

#include <boost/math/distributions/normal.hpp>
#include <boost/math/special_functions/beta.hpp>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <cmath>
#include <cstdarg>
#include <cstdio>
#include <cstring>
#include <exception>
#include <limits>
#include <map>
#include <stdexcept>
#include <system_error>
#include <utility>

#include <unistd.h>

namespace tools::campaign {
namespace fs = std::filesystem;
namespace {

/** True for a probability strictly inside (0, 1); false for NaN. */
bool open_unit(double v) noexcept { return v > 0.0 && v < 1.0; }

void check_conf(const char* fn, double conf) {
  if (!open_unit(conf)) {
    throw std::invalid_argument(std::string(fn) + ": confidence " + std::to_string(conf) +
                                " is not inside (0, 1)");
  }
}

void check_counts(const char* fn, std::uint64_t k, std::uint64_t n) {
  if (k > n) {
    throw std::invalid_argument(std::string(fn) + ": " + std::to_string(k) + " successes in " + std::to_string(n) +
                                " trials");
  }
}

/**
 * Calls @p f, turning whatever the numerics library throws into a
 * std::runtime_error that names @p what: its exception types stay inside.
 */
template <class F>
double numerics(const std::string& what, F&& f) {
  try {
    return std::forward<F>(f)();
  } catch (const std::exception& e) {
    throw std::runtime_error(what + ": the numerics failed: " + e.what());
  }
}

double to_double(std::uint64_t v) noexcept { return static_cast<double>(v); }

double fraction(std::uint64_t count, std::uint64_t runs) noexcept {
  return runs == 0U ? 0.0 : to_double(count) / to_double(runs);
}

std::array<ClassCount, kOutcomeCount> classes_of(const std::array<std::uint64_t, kOutcomeCount>& counts,
                                                 std::uint64_t runs, double conf) {
  std::array<ClassCount, kOutcomeCount> out{};
  for (std::size_t i = 0; i < kOutcomeCount; ++i) {
    out[i].count = counts[i];
    out[i].cp = clopper_pearson(counts[i], runs, conf);
    out[i].wilson = wilson(counts[i], runs, conf);
  }
  return out;
}

// ------------------------------------------------------------------ text helpers

/** printf into a std::string. */
std::string format(const char* fmt, ...) __attribute__((format(printf, 1, 2)));
std::string format(const char* fmt, ...) {
  std::array<char, 128> buf{};
  std::va_list ap;
  va_start(ap, fmt);
  std::va_list again;
  va_copy(again, ap);
  const int n = std::vsnprintf(buf.data(), buf.size(), fmt, ap);
  va_end(ap);
  std::string s;
  if (n >= 0 && static_cast<std::size_t>(n) < buf.size()) {
    s.assign(buf.data(), static_cast<std::size_t>(n));
  } else if (n >= 0) {
    s.resize(static_cast<std::size_t>(n) + 1U);
    (void)std::vsnprintf(s.data(), s.size(), fmt, again);
    s.resize(static_cast<std::size_t>(n));
  }
  va_end(again);
  return s;
}

/** A CSV field (RFC 4180): quoted, with its quotes doubled, if it holds a separator, quote or line break. */
std::string csv_field(const std::string& s) {
  if (s.find_first_of(",\"\r\n") == std::string::npos) {
    return s;
  }
  std::string out = "\"";
  for (const char c : s) {
    out += c;
    if (c == '"') {
      out += '"';
    }
  }
  return out + "\"";
}

/** Text for a Markdown table cell or heading: no line breaks, pipes escaped. */
std::string md_text(const std::string& s) {
  std::string out;
  for (const char c : s) {
    if (c == '\n' || c == '\r') {
      out += ' ';
    } else if (c == '|') {
      out += "\\|";
    } else {
      out += c;
    }
  }
  return out;
}

/** A single-quoted gnuplot string literal (quotes doubled, line breaks as spaces). */
std::string gp_string(const std::string& s) {
  std::string out = "'";
  for (const char c : s) {
    if (c == '\'') {
      out += "''";
    } else if (c == '\n' || c == '\r') {
      out += ' ';
    } else {
      out += c;
    }
  }
  return out + "'";
}

/** A proportion as percent: one decimal, or two significant digits below 0.1 %. */
std::string pct(double v) {
  const double p = 100.0 * v;
  if (p > 0.0 && p < 0.1) {
    return format("%.2g", p);
  }
  return format("%.1f", p);
}

/** A confidence as percent without trailing zeros: 95, 99.9. */
std::string conf_pct(double conf) { return format("%.10g", 100.0 * conf); }

// ------------------------------------------------------------------ files

std::atomic<std::uint32_t> g_temp_serial{0U};

/** A temporary name in @p dir for @p name: hidden, unique to this process and call. */
fs::path temp_path(const fs::path& dir, const std::string& name) {
  return dir / ("." + name + ".tmp-" + std::to_string(::getpid()) + "-" + std::to_string(g_temp_serial.fetch_add(1U)));
}

/** Writes @p text to @p dir/@p name atomically: a temporary file in @p dir, flushed to disk, then renamed. */
bool write_atomic(const fs::path& dir, const std::string& name, const std::string& text, std::string& err) {
  const fs::path tmp = temp_path(dir, name);
  const fs::path dst = dir / name;
  std::FILE* f = std::fopen(tmp.c_str(), "wb");
  if (f == nullptr) {
    err = dst.string() + ": cannot create " + tmp.string() + ": " + std::strerror(errno);
    return false;
  }
  bool ok = std::fwrite(text.data(), 1, text.size(), f) == text.size() && std::fflush(f) == 0 &&
            ::fsync(::fileno(f)) == 0;
  int e = errno;
  if (std::fclose(f) != 0 && ok) {
    ok = false;
    e = errno;
  }
  if (ok && std::rename(tmp.c_str(), dst.c_str()) != 0) {
    err = dst.string() + ": cannot move into place: " + std::strerror(errno);
    (void)std::remove(tmp.c_str());
    return false;
  }
  if (!ok) {
    err = dst.string() + ": cannot write: " + std::strerror(e);
    (void)std::remove(tmp.c_str());
    return false;
  }
  return true;
}

/** Runs @p stem.gp in @p dir into a temporary PNG, renamed to @p stem.png on success. @return a note, "" if all went well. */
std::string make_png(const fs::path& dir, const std::string& stem) {
  const std::string gnuplot = find_on_path("gnuplot");
  if (gnuplot.empty()) {
    return "gnuplot is not installed: the chart script is " + (dir / (stem + ".gp")).string() +
           " (run it there with gnuplot)";
  }
  const fs::path tmp = temp_path(dir, stem + ".png");
  std::string failed =
      run_gnuplot(gnuplot, dir.string(), stem + ".gp", {"-e", "out=" + gp_string(tmp.filename().string())});
  std::error_code ec;
  if (!failed.empty()) {
    fs::remove(tmp, ec);
    return failed;
  }
  fs::rename(tmp, dir / (stem + ".png"), ec);
  if (ec) {
    fs::remove(tmp, ec);
    return (dir / (stem + ".png")).string() + ": cannot move into place: " + ec.message();
  }
  return {};
}

/** The @p q quantile (0..1) of sorted @p v by linear interpolation between order statistics (R's type 7). */
double quantile_sorted(const std::vector<double>& v, double q) {
  if (v.empty()) {
    return 0.0;
  }
  const double h = q * static_cast<double>(v.size() - 1U);
  const auto lo = static_cast<std::size_t>(std::floor(h));
  const std::size_t hi = std::min(lo + 1U, v.size() - 1U);
  return v[lo] + (h - static_cast<double>(lo)) * (v[hi] - v[lo]);
}

/** The spread of @p value over @p runs, runs whose value is not finite left out. */
template <typename F>
Spread spread_of(std::span<const RunResult> runs, F value) {
  Spread sp;
  std::vector<double> v;
  for (const RunResult& r : runs) {
    const double x = value(r);
    if (!std::isfinite(x)) {
      continue;
    }
    v.push_back(x);
    if (sp.n == 0U || x > sp.max) {
      sp.max = x;
      sp.max_index = r.index;
      sp.max_seed = r.seed;
    }
    ++sp.n;
  }
  std::sort(v.begin(), v.end());
  sp.median = quantile_sorted(v, 0.5);
  sp.p90 = quantile_sorted(v, 0.9);
  return sp;
}

/** A number for CSV: empty when not finite. */
std::string csv_number(double v) { return std::isfinite(v) ? format("%.6g", v) : std::string{}; }

constexpr std::array<const char*, 3> kAxes = {"x", "y", "z"};

}  // namespace

// ------------------------------------------------------------------ outcomes

const char* outcome_name(Outcome o) noexcept {
  switch (o) {
    case Outcome::kNotDelivered:
      return "not_delivered";
    case Outcome::kNoEffect:
      return "no_effect";
    case Outcome::kMasked:
      return "masked";
    case Outcome::kRecovered:
      return "detected_recovered";
    case Outcome::kDegraded:
      return "detected_degraded";
    case Outcome::kLost:
      return "detected_lost";
    case Outcome::kSdc:
      return "sdc";
    case Outcome::kCrash:
      return "hang_crash";
  }
  return "?";
}

bool outcome_from_name(std::string_view name, Outcome& out) noexcept {
  for (const Outcome o : kOutcomes) {
    if (name == outcome_name(o)) {
      out = o;
      return true;
    }
  }
  return false;
}

bool is_detected(Outcome o) noexcept {
  return o == Outcome::kRecovered || o == Outcome::kDegraded || o == Outcome::kLost;
}

// ------------------------------------------------------------------ intervals

double normal_quantile(double conf) {
  check_conf("normal_quantile", conf);
  return numerics("normal_quantile(" + std::to_string(conf) + ")", [conf] {
    return boost::math::quantile(boost::math::normal_distribution<double>(), 1.0 - (1.0 - conf) / 2.0);
  });
}

Interval clopper_pearson(std::uint64_t k, std::uint64_t n, double conf) {
  check_conf("clopper_pearson", conf);
  check_counts("clopper_pearson", k, n);
  if (n == 0U) {
    return {0.0, 1.0};
  }
  const double alpha = 1.0 - conf;
  const double kd = to_double(k);
  const double nd = to_double(n);
  const std::string what = "clopper_pearson(" + std::to_string(k) + ", " + std::to_string(n) + ")";
  // The lower end is the alpha/2 quantile of Beta(k, n-k+1), the upper the 1-alpha/2 quantile of
  // Beta(k+1, n-k); both betas are undefined at the edge they would pin, which is 0 or 1 exactly.
  const double lo = k == 0U ? 0.0 : numerics(what, [&] { return boost::math::ibeta_inv(kd, nd - kd + 1.0, alpha / 2.0); });
  const double hi =
      k == n ? 1.0 : numerics(what, [&] { return boost::math::ibeta_inv(kd + 1.0, nd - kd, 1.0 - alpha / 2.0); });
  return {lo, hi};
}

Interval wilson(std::uint64_t k, std::uint64_t n, double conf) {
  check_conf("wilson", conf);
  check_counts("wilson", k, n);
  if (n == 0U) {
    return {0.0, 1.0};
  }
  const double z = normal_quantile(conf);
  const double nd = to_double(n);
  const double p = to_double(k) / nd;
  const double z2n = z * z / nd;
  const double centre = (p + z2n / 2.0) / (1.0 + z2n);
  const double half = z / (1.0 + z2n) * std::sqrt(p * (1.0 - p) / nd + z2n / (4.0 * nd));
  // At k == 0 (k == n) the lower (upper) end is 0 (1) in exact arithmetic; rounding would leave a few ulp.
  const double lo = k == 0U ? 0.0 : std::clamp(centre - half, 0.0, 1.0);
  const double hi = k == n ? 1.0 : std::clamp(centre + half, 0.0, 1.0);
  return {lo, hi};
}

std::uint64_t runs_for_margin(double margin, double conf, double p, std::uint64_t population) {
  if (!open_unit(margin) || !open_unit(p)) {
    throw std::invalid_argument("runs_for_margin: margin " + std::to_string(margin) + " and p " + std::to_string(p) +
                                " must both be inside (0, 1)");
  }
  const double t = normal_quantile(conf);
  const double infinite = t * t * p * (1.0 - p) / (margin * margin);
  double n = infinite;
  if (population != 0U) {
    const double big_n = to_double(population);
    n = big_n / (1.0 + margin * margin * (big_n - 1.0) / (t * t * p * (1.0 - p)));
  }
  // 2^64 as a double: anything at or above it does not fit the result.
  if (!(n < 18446744073709551616.0)) {
    throw std::invalid_argument("runs_for_margin: margin " + std::to_string(margin) + " needs more than 2^64 runs");
  }
  const double nearest = std::round(n);
  const double rounded = std::fabs(n - nearest) <= 1e-9 * std::max(1.0, n) ? nearest : std::ceil(n);
  return static_cast<std::uint64_t>(rounded);
}

double margin_for_runs(std::uint64_t runs, double conf) {
  const double t = normal_quantile(conf);
  return runs == 0U ? 0.5 : t / (2.0 * std::sqrt(to_double(runs)));
}

// ------------------------------------------------------------------ summary

namespace {

/** Counts @p run into @p c: eligible with a delivered fault, unless no_effect or without a summary (hang_crash). */
void tally_coverage(const RunResult& run, Coverage& c) noexcept {
  if (run.injected > 0U && run.outcome != Outcome::kNoEffect && run.outcome != Outcome::kCrash) {
    ++c.eligible;
    c.detected += is_detected(run.outcome) ? 1U : 0U;
  }
}

/** The intervals of a tallied coverage. */
void close_coverage(Coverage& c, double conf) {
  c.cp = clopper_pearson(c.detected, c.eligible, conf);
  c.wilson = wilson(c.detected, c.eligible, conf);
}

void tally_flags(const RunResult& run, FlagCounts& f) noexcept {
  f.false_alarm += run.false_alarms > 0U ? 1U : 0U;
  f.misdiagnosed += run.misdiagnosed > 0U ? 1U : 0U;
  f.healthy_disturbed += run.healthy_disturbed > 0U ? 1U : 0U;
}

/** The groups of @p runs by @p key (an empty key: kUnknownKind), sorted by name, with their classes, coverage, flags. */
template <typename Key>
std::vector<GroupReport> groups_of(std::span<const RunResult> runs, double conf, Key key) {
  struct Tally {
    std::uint64_t runs = 0;
    std::array<std::uint64_t, kOutcomeCount> counts{};
    Coverage coverage;
    FlagCounts flags;
  };
  std::map<std::string, Tally> by;  // ordered: the report lists groups sorted by name
  for (const RunResult& run : runs) {
    const std::string& k = key(run);
    Tally& t = by[k.empty() ? std::string(kUnknownKind) : k];
    ++t.runs;
    ++t.counts[static_cast<std::size_t>(run.outcome)];
    tally_coverage(run, t.coverage);
    tally_flags(run, t.flags);
  }
  std::vector<GroupReport> out;
  out.reserve(by.size());
  for (auto& [name, t] : by) {
    close_coverage(t.coverage, conf);
    out.push_back(GroupReport{name, t.runs, classes_of(t.counts, t.runs, conf), t.coverage, t.flags});
  }
  return out;
}

}  // namespace

Coverage coverage_of(std::span<const RunResult> runs, double conf) {
  check_conf("coverage_of", conf);
  Coverage c;
  for (const RunResult& run : runs) {
    tally_coverage(run, c);
  }
  close_coverage(c, conf);
  return c;
}

Report summarize(std::string_view campaign, std::span<const RunResult> runs, double conf) {
  check_conf("summarize", conf);
  Report r;
  r.campaign = std::string(campaign);
  r.confidence = conf;
  r.runs = runs.size();
  std::array<std::uint64_t, kOutcomeCount> all{};
  for (const RunResult& run : runs) {
    const auto cls = static_cast<std::size_t>(run.outcome);
    if (cls >= kOutcomeCount) {
      throw std::invalid_argument("summarize: run " + std::to_string(run.index) + " has no valid outcome (" +
                                  std::to_string(cls) + ")");
    }
    ++all[cls];
    tally_flags(run, r.flags);
    r.host_s_total += run.host_s;
  }
  r.classes = classes_of(all, r.runs, conf);
  r.coverage = coverage_of(runs, conf);
  r.kinds = groups_of(runs, conf, [](const RunResult& run) -> const std::string& { return run.kind; });
  r.roles = groups_of(runs, conf, [](const RunResult& run) -> const std::string& { return run.role; });
  r.margin_at_runs = margin_for_runs(r.runs, conf);
  r.all_runs.assign(runs.begin(), runs.end());
  std::sort(r.all_runs.begin(), r.all_runs.end(),
            [](const RunResult& a, const RunResult& b) { return a.index < b.index; });
  for (const RunResult& run : r.all_runs) {
    if (run.has_integrity) {
      r.per_run.push_back(run);
    }
  }
  r.integrity = summarize_integrity(r.per_run);
  return r;
}

IntegrityReport summarize_integrity(std::span<const RunResult> runs) {
  IntegrityReport ir;
  std::vector<RunResult> with;
  for (const RunResult& r : runs) {
    if (r.has_integrity) {
      with.push_back(r);
    }
  }
  ir.runs = with.size();
  ir.final_error_m = spread_of(with, [](const RunResult& r) { return r.final_error_m; });
  ir.max_error_m = spread_of(with, [](const RunResult& r) {
    return r.converged_at_s >= 0.0 ? r.max_error_m : std::numeric_limits<double>::quiet_NaN();
  });
  for (const RunResult& r : with) {
    if (r.converged_at_s < 0.0) {
      ++ir.not_converged;
    } else if (!(r.max_error_m <= kIntegrityMaxErrorBoundM)) {
      ++ir.runs_over_max_error;  // a NaN maximum counts as over
    }
    for (std::size_t a = 0; a < 3U; ++a) {
      AxisIntegrity& ax = ir.axes[a];
      ax.outputs += r.integrity_outputs;
      ax.beyond_3sigma += r.beyond_3sigma[a];
      ax.beyond_5sigma += r.beyond_5sigma[a];
      if (r.integrity_outputs > 0U &&
          static_cast<double>(r.beyond_3sigma[a]) > kIntegrityFractionBound * static_cast<double>(r.integrity_outputs)) {
        ++ax.runs_over_fraction;
      }
      if (r.beyond_5sigma[a] > 0U) {
        ++ax.runs_beyond_5sigma;
      }
      if (std::isfinite(r.worst_ratio[a]) && r.worst_ratio[a] > ax.worst_ratio) {
        ax.worst_ratio = r.worst_ratio[a];
        ax.worst_index = r.index;
        ax.worst_seed = r.seed;
      }
    }
  }
  return ir;
}

// ------------------------------------------------------------------ report files

namespace {

/** report.md's coverage section: one row for all runs, then one per kind and one per role. */
std::string coverage_md(const Report& r) {
  const std::string cpct = conf_pct(r.confidence);
  std::string s =
      "\n## Detection coverage and flags\n\nCoverage: of the runs with a fault delivered to the chip whose class is "
      "neither no_effect nor hang_crash (the eligible runs), those detected (detected_recovered, detected_degraded, "
      "detected_lost), with the Clopper-Pearson " + cpct +
      " % interval. Flags: runs whose flight accused a tile no injected fault explains (false alarm), accused the "
      "wrong tile or class (misdiagnosed), or reset, retired, excluded or outvoted a healthy tile.\n\n"
      "| runs of | runs | eligible | detected | coverage | false alarm | misdiagnosed | healthy tile disturbed |\n"
      "|---|---:|---:|---:|---:|---:|---:|---:|\n";
  const auto row = [&s](const std::string& name, std::uint64_t runs, const Coverage& c, const FlagCounts& f) {
    const std::string cov = c.eligible == 0U ? std::string("-")
                                             : pct(fraction(c.detected, c.eligible)) + " % (CP " + pct(c.cp.lo) + "-" +
                                                   pct(c.cp.hi) + " %)";
    s += "| " + md_text(name) + " | " + std::to_string(runs) + " | " + std::to_string(c.eligible) + " | " +
         std::to_string(c.detected) + " | " + cov + " | " + std::to_string(f.false_alarm) + " | " +
         std::to_string(f.misdiagnosed) + " | " + std::to_string(f.healthy_disturbed) + " |\n";
  };
  row("all", r.runs, r.coverage, r.flags);
  for (const GroupReport& g : r.kinds) {
    row("kind " + g.name, g.runs, g.coverage, g.flags);
  }
  for (const GroupReport& g : r.roles) {
    row("role " + g.name, g.runs, g.coverage, g.flags);
  }
  return s;
}

}  // namespace


std::string report_json(const Report& r) {
  using Json = nlohmann::ordered_json;
  const auto num = [](double v) { return std::isfinite(v) ? Json(v) : Json(); };
  const auto classes = [&num](const std::array<ClassCount, kOutcomeCount>& cs, std::uint64_t runs) {
    Json o = Json::object();
    for (const Outcome out : kOutcomes) {
      const ClassCount& c = cs[static_cast<std::size_t>(out)];
      o[outcome_name(out)] = Json{{"count", c.count},
                                  {"fraction", num(fraction(c.count, runs))},
                                  {"cp", {{"lo", num(c.cp.lo)}, {"hi", num(c.cp.hi)}}},
                                  {"wilson", {{"lo", num(c.wilson.lo)}, {"hi", num(c.wilson.hi)}}}};
    }
    return o;
  };
  const auto coverage = [&num](const Coverage& c) {
    return Json{{"detected", c.detected},
                {"eligible", c.eligible},
                {"fraction", c.eligible == 0U ? Json() : num(fraction(c.detected, c.eligible))},
                {"cp", {{"lo", num(c.cp.lo)}, {"hi", num(c.cp.hi)}}},
                {"wilson", {{"lo", num(c.wilson.lo)}, {"hi", num(c.wilson.hi)}}}};
  };
  const auto flags = [](const FlagCounts& f) {
    return Json{{"false_alarm_runs", f.false_alarm},
                {"misdiagnosed_runs", f.misdiagnosed},
                {"healthy_disturbed_runs", f.healthy_disturbed}};
  };
  const auto groups = [&](const std::vector<GroupReport>& gs, const char* key) {
    Json a = Json::array();
    for (const GroupReport& g : gs) {
      a.push_back(Json{{key, g.name},
                       {"runs", g.runs},
                       {"classes", classes(g.classes, g.runs)},
                       {"coverage", coverage(g.coverage)},
                       {"flags", flags(g.flags)}});
    }
    return a;
  };
  Json j;
  j["campaign"] = r.campaign;
  j["confidence"] = num(r.confidence);
  j["runs"] = r.runs;
  j["margin_at_runs"] = num(r.margin_at_runs);
  j["host_s_total"] = num(r.host_s_total);
  j["classes"] = classes(r.classes, r.runs);
  j["coverage"] = coverage(r.coverage);
  j["flags"] = flags(r.flags);
  j["kinds"] = groups(r.kinds, "kind");
  j["roles"] = groups(r.roles, "role");
  const IntegrityReport& ir = r.integrity;
  const auto spread = [&num](const Spread& sp) {
    return Json{{"runs", sp.n}, {"median", num(sp.median)}, {"p90", num(sp.p90)}, {"max", num(sp.max)},
                {"max_run", sp.max_index}, {"max_seed", sp.max_seed}};
  };
  Json integ{{"runs", ir.runs},
             {"not_converged", ir.not_converged},
             {"final_error_m", spread(ir.final_error_m)},
             {"max_error_after_convergence_m", spread(ir.max_error_m)},
             {"max_error_bound_m", kIntegrityMaxErrorBoundM},
             {"runs_over_max_error_bound", ir.runs_over_max_error},
             {"fraction_bound", kIntegrityFractionBound}};
  for (std::size_t a = 0; a < 3U; ++a) {
    const AxisIntegrity& ax = ir.axes[a];
    integ[kAxes[a]] = Json{{"outputs", ax.outputs},
                           {"beyond_3sigma", ax.beyond_3sigma},
                           {"beyond_3sigma_fraction", num(fraction(ax.beyond_3sigma, ax.outputs))},
                           {"beyond_5sigma", ax.beyond_5sigma},
                           {"runs_over_fraction_bound", ax.runs_over_fraction},
                           {"runs_beyond_5sigma", ax.runs_beyond_5sigma},
                           {"worst_ratio", num(ax.worst_ratio)},
                           {"worst_run", ax.worst_index},
                           {"worst_seed", ax.worst_seed}};
  }
  j["integrity"] = integ;
  // A name that is not valid UTF-8 is replaced, not thrown.
  return j.dump(2, ' ', false, Json::error_handler_t::replace) + "\n";
}

std::string report_csv(const Report& r) {
  std::string s = std::string(kReportCsvHeader) + "\n";
  const auto block = [&s](const std::string& kind, const std::array<ClassCount, kOutcomeCount>& cs,
                          std::uint64_t runs) {
    for (const Outcome out : kOutcomes) {
      const ClassCount& c = cs[static_cast<std::size_t>(out)];
      s += csv_field(kind) + "," + outcome_name(out) + "," + std::to_string(c.count) + "," + std::to_string(runs) +
           format(",%.6f,%.6f,%.6f,%.6f,%.6f\n", fraction(c.count, runs), c.cp.lo, c.cp.hi, c.wilson.lo,
                  c.wilson.hi);
    }
  };
  block("all", r.classes, r.runs);
  for (const GroupReport& k : r.kinds) {
    block(k.name, k.classes, k.runs);
  }
  return s;
}

std::string report_md(const Report& r) {
  const std::string cpct = conf_pct(r.confidence);
  std::string s = "# Campaign " + md_text(r.campaign) + "\n\n" + std::to_string(r.runs) + " runs at " + cpct +
                  " % confidence: the margin of error of a fraction over all runs is at most " +
                  pct(r.margin_at_runs) + " % (worst case p = 0.5). Host time " + format("%.1f", r.host_s_total) +
                  " s.\n\nA cell: runs in the class (percent of the column's runs, Clopper-Pearson " + cpct +
                  " % interval).\n\n| outcome | all (" + std::to_string(r.runs) + " runs) |";
  std::string rule = "|---|---:|";
  for (const GroupReport& k : r.kinds) {
    s += " " + md_text(k.name) + " (" + std::to_string(k.runs) + " runs) |";
    rule += "---:|";
  }
  s += "\n" + rule + "\n";
  const auto cell = [](const ClassCount& c, std::uint64_t runs) {
    return " " + std::to_string(c.count) + " (" + pct(fraction(c.count, runs)) + " %, CP " + pct(c.cp.lo) + "-" +
           pct(c.cp.hi) + " %) |";
  };
  for (const Outcome out : kOutcomes) {
    const auto i = static_cast<std::size_t>(out);
    s += std::string("| ") + outcome_name(out) + " |" + cell(r.classes[i], r.runs);
    for (const GroupReport& k : r.kinds) {
      s += cell(k.classes[i], k.runs);
    }
    s += "\n";
  }
  s += coverage_md(r);
  const IntegrityReport& ir = r.integrity;
  s += "\n## Navigation integrity\n\n";
  if (ir.runs == 0U) {
    return s + "No run gave integrity figures.\n";
  }
  const auto spread = [](const Spread& sp) {
    return format("median %.3g, 90th percentile %.3g, max %.3g (run %u, seed %llu)", sp.median, sp.p90, sp.max,
                  sp.max_index, static_cast<unsigned long long>(sp.max_seed));
  };
  s += format("%llu runs with figures; %llu never converged (the filter's horizontal 3-sigma never within %.3g m). "
              "Targets: every converged run's maximum error after convergence within %.3g m; from the fix on "
              "(horizontal 3-sigma below %.3g m), at most %.3g %% of the outputs beyond their 3-sigma on each axis, "
              "none beyond 5-sigma. Per run: integrity.csv, integrity.png.\n\n",
              static_cast<unsigned long long>(ir.runs), static_cast<unsigned long long>(ir.not_converged),
              kConvergedSigma3M, kIntegrityMaxErrorBoundM, kFixSigma3M, 100.0 * kIntegrityFractionBound);
  s += "- final position error (m): " + spread(ir.final_error_m) + "\n";
  s += "- maximum error after convergence (m): " +
       (ir.max_error_m.n > 0U ? spread(ir.max_error_m) : std::string("no run converged")) +
       format("; %llu of %llu converged runs beyond %.3g m\n", static_cast<unsigned long long>(ir.runs_over_max_error),
              static_cast<unsigned long long>(ir.max_error_m.n), kIntegrityMaxErrorBoundM);
  s += "\n| axis | outputs | beyond 3-sigma | runs beyond " + format("%.3g", 100.0 * kIntegrityFractionBound) +
       " % | beyond 5-sigma | runs with one beyond 5-sigma | worst error / 3-sigma |\n|---|---:|---:|---:|---:|---:|---:|\n";
  for (std::size_t a = 0; a < 3U; ++a) {
    const AxisIntegrity& ax = ir.axes[a];
    s += format("| %s | %llu | %llu (%.2f %%) | %llu | %llu | %llu | %.3g (run %u, seed %llu) |\n", kAxes[a],
                static_cast<unsigned long long>(ax.outputs), static_cast<unsigned long long>(ax.beyond_3sigma),
                100.0 * fraction(ax.beyond_3sigma, ax.outputs), static_cast<unsigned long long>(ax.runs_over_fraction),
                static_cast<unsigned long long>(ax.beyond_5sigma), static_cast<unsigned long long>(ax.runs_beyond_5sigma),
                ax.worst_ratio, ax.worst_index, static_cast<unsigned long long>(ax.worst_seed));
  }
  return s;
}

std::string coverage_csv(const Report& r) {
  std::string s = std::string(kCoverageCsvHeader) + "\n";
  const auto row = [&s](const char* group, const std::string& name, std::uint64_t runs, const Coverage& c,
                        const FlagCounts& f) {
    s += std::string(group) + "," + csv_field(name) + "," + std::to_string(runs) + "," + std::to_string(c.eligible) +
         "," + std::to_string(c.detected) + "," +
         (c.eligible == 0U ? std::string{} : format("%.6f", fraction(c.detected, c.eligible))) +
         format(",%.6f,%.6f,%.6f,%.6f,", c.cp.lo, c.cp.hi, c.wilson.lo, c.wilson.hi) +
         std::to_string(f.false_alarm) + "," + std::to_string(f.misdiagnosed) + "," +
         std::to_string(f.healthy_disturbed) + "\n";
  };
  row("all", "all", r.runs, r.coverage, r.flags);
  for (const GroupReport& g : r.kinds) {
    row("kind", g.name, g.runs, g.coverage, g.flags);
  }
  for (const GroupReport& g : r.roles) {
    row("role", g.name, g.runs, g.coverage, g.flags);
  }
  return s;
}

std::string runs_csv(const Report& r) {
  std::string s = std::string(kRunsCsvHeader) + "\n";
  for (const RunResult& run : r.all_runs) {
    s += std::to_string(run.index) + "," + csv_field(run.kind) + "," + csv_field(run.role) + "," +
         std::to_string(run.seed) + "," + outcome_name(run.outcome) + "," + csv_number(run.final_error_m) + "," +
         std::to_string(run.injected) + "," + std::to_string(run.not_delivered) + "," + std::to_string(run.detected) +
         "," + std::to_string(run.recovered) + "," + std::to_string(run.degraded_accepted) + "," +
         std::to_string(run.misdiagnosed) + "," + std::to_string(run.false_alarms) + "," +
         std::to_string(run.healthy_disturbed) + "," + (run.output_as_golden ? "1" : "0") + "\n";
  }
  return s;
}

std::string integrity_csv(const Report& r) {
  std::string s = std::string(kIntegrityCsvHeader) + "\n";
  for (const RunResult& run : r.per_run) {
    s += std::to_string(run.index) + "," + std::to_string(run.seed) + "," + outcome_name(run.outcome) + "," +
         csv_number(run.final_error_m) + "," + csv_number(run.converged_at_s >= 0.0 ? run.max_error_m : NAN) + "," +
         csv_number(run.fix_at_s >= 0.0 ? run.fix_at_s : NAN) + "," +
         csv_number(run.converged_at_s >= 0.0 ? run.converged_at_s : NAN) + "," + std::to_string(run.integrity_outputs);
    for (const std::uint64_t c : run.beyond_3sigma) {
      s += "," + std::to_string(c);
    }
    for (const std::uint64_t c : run.beyond_5sigma) {
      s += "," + std::to_string(c);
    }
    for (const double w : run.worst_ratio) {
      s += "," + csv_number(w);
    }
    s += "\n";
  }
  return s;
}

std::string integrity_gnuplot(const Report& r) {
  std::string data;
  for (const RunResult& run : r.per_run) {
    const double n = static_cast<double>(run.integrity_outputs);
    const auto pct_of = [n](std::uint64_t c) { return n > 0.0 ? 100.0 * static_cast<double>(c) / n : NAN; };
    const auto gp_num = [](double v) { return std::isfinite(v) ? format("%.6g", v) : std::string("NaN"); };
    data += format("%u %llu ", run.index, static_cast<unsigned long long>(run.seed)) + gp_num(run.final_error_m) + " " +
            gp_num(run.converged_at_s >= 0.0 ? run.max_error_m : NAN) + " " + gp_num(pct_of(run.beyond_3sigma[0])) +
            " " + gp_num(pct_of(run.beyond_3sigma[1])) + " " + gp_num(pct_of(run.beyond_3sigma[2])) + "\n";
  }
  const IntegrityReport& ir = r.integrity;
  double seed_lo = r.per_run.empty() ? 0.0 : static_cast<double>(r.per_run.front().seed);
  double seed_hi = seed_lo;
  for (const RunResult& run : r.per_run) {
    seed_lo = std::min(seed_lo, static_cast<double>(run.seed));
    seed_hi = std::max(seed_hi, static_cast<double>(run.seed));
  }
  double top_pct = 0.0;  // the largest share beyond 3-sigma: the target line stays in view below it
  for (const RunResult& run : r.per_run) {
    for (const std::uint64_t c : run.beyond_3sigma) {
      if (run.integrity_outputs > 0U) {
        top_pct = std::max(top_pct, 100.0 * static_cast<double>(c) / static_cast<double>(run.integrity_outputs));
      }
    }
  }
  // A seed sweep is plotted by seed; runs of one seed (a fault campaign) by run index.
  const bool by_seed = seed_hi > seed_lo;
  const double x_lo = by_seed ? seed_lo : static_cast<double>(r.per_run.empty() ? 0U : r.per_run.front().index);
  const double x_hi = by_seed ? seed_hi : static_cast<double>(r.per_run.empty() ? 0U : r.per_run.back().index);
  const std::string x = by_seed ? "2" : "1";
  return "# Navigation integrity per run: the final and the maximum position error after convergence (top), and\n"
         "# the outputs after convergence whose error exceeds their own 3-sigma, per axis (bottom).\n"
         "# Run in this folder: gnuplot integrity.gp (writes integrity.png; gnuplot -e \"out='x.png'\" integrity.gp "
         "writes x.png)\n" +
         gnuplot_png_terminal("1000,760") +
         "if (!exists('out')) { out = 'integrity.png' }\n"
         "set output out\n"
         "# run index, scenario seed, final error (m), max error after convergence (m), beyond 3-sigma x, y, z (%)\n"
         "$runs << EOD\n" +
         data +
         "EOD\n"
         "set multiplot layout 2,1 title " +
         gp_string("Campaign " + r.campaign + ": navigation integrity of " + std::to_string(ir.runs) + " runs") +
         "\n"
         "set grid\n"
         "set key below horizontal\n"  // not over the points: the worst run may sit in any corner
         "set xlabel '" + (by_seed ? std::string("scenario seed") : std::string("run")) + "'\n" +
         format("set xrange [%.0f:%.0f]\n", x_lo - 1.0, x_hi + 1.0) +
         "set logscale y\n"
         "set ylabel 'position error (m)'\n" +
         "plot $runs using " + x + ":4 with points pt 7 ps 0.7 lc rgb '#c44e52' title 'max after convergence', \\\n"
         "     $runs using " + x + ":3 with points pt 5 ps 0.6 lc rgb '#4c72b0' title 'final', \\\n" +
         format("     %.6g with lines dt 2 lc rgb '#000000' title '%.3g m target'\n", kIntegrityMaxErrorBoundM,
                kIntegrityMaxErrorBoundM) +
         "unset logscale y\n"
         "set ylabel 'outputs beyond 3-sigma (%)'\n" +
         format("set yrange [0:%.6g]\n", std::max(2.0 * 100.0 * kIntegrityFractionBound, 1.1 * top_pct)) +
         "plot $runs using ($" + x + "-0.2):5 with impulses lw 2 lc rgb '#4c72b0' title 'x', \\\n"
         "     $runs using " + x + ":6 with impulses lw 2 lc rgb '#55a868' title 'y', \\\n"
         "     $runs using ($" + x + "+0.2):7 with impulses lw 2 lc rgb '#c44e52' title 'z', \\\n" +
         format("     %.6g with lines dt 2 lc rgb '#000000' title '%.3g %% target'\n", 100.0 * kIntegrityFractionBound,
                100.0 * kIntegrityFractionBound) +
         "unset multiplot\n";
}

std::string report_gnuplot(const Report& r) {
  std::string data;
  std::string tics;  // the class names as tick labels, broken at the underscore to fit under their bars
  for (const Outcome out : kOutcomes) {
    const auto i = static_cast<std::size_t>(out);
    const ClassCount& c = r.classes[i];
    data += format("%zu %s %.6f %.6f %.6f %llu\n", i, outcome_name(out), 100.0 * fraction(c.count, r.runs),
                   100.0 * c.cp.lo, 100.0 * c.cp.hi, static_cast<unsigned long long>(c.count));
    tics += tics.empty() ? "\"" : ", \"";
    for (const char* ch = outcome_name(out); *ch != '\0'; ++ch) {
      tics += *ch == '_' ? std::string("\\n") : std::string(1, *ch);  // a gnuplot "\n" in a double-quoted string
    }
    tics += "\" " + std::to_string(i);
  }
  const std::string cpct = conf_pct(r.confidence);
  return "# Fraction of the runs per outcome class over all runs, with the Clopper-Pearson " + cpct +
         " % interval as error bars.\n"
         "# Run in this folder: gnuplot outcomes.gp (writes outcomes.png; gnuplot -e \"out='x.png'\" outcomes.gp "
         "writes x.png)\n" +
         gnuplot_png_terminal("900,560") +
         "if (!exists('out')) { out = 'outcomes.png' }\n"
         "set output out\n"
         "# class index, class, percent of runs, CP low, CP high (percent), runs\n"
         "$outcomes << EOD\n" +
         data +
         "EOD\n"
         "set title " +
         gp_string("Campaign " + r.campaign + ": outcomes of " + std::to_string(r.runs) + " runs (error bars: " +
                   "Clopper-Pearson " + cpct + " %)") +
         "\n"
         "set ylabel 'runs (%)'\n"
         "set yrange [0:105]\n"
         "set xrange [-0.6:" +
         std::to_string(kOutcomeCount - 1U) +
         ".6]\n"
         "set boxwidth 0.6\n"
         "set style fill solid 0.75 border lc rgb '#404040'\n"
         "set grid ytics\n"
         "set key off\n"
         "set bmargin 4\n"
         "set xtics (" +
         tics +
         ")\n"
         "plot $outcomes using 1:3 with boxes lc rgb '#4c72b0', \\\n"
         "     $outcomes using 1:3:4:5 with yerrorbars pt 7 ps 0.6 lw 1.5 lc rgb '#000000', \\\n"
         "     $outcomes using 1:5:(sprintf('%d', int(column(6)))) with labels offset 0,0.8\n";
}

bool write_report(const Report& r, const fs::path& dir, std::string& err, std::string& note) {
  note.clear();
  try {
    std::error_code ec;
    fs::create_directories(dir, ec);
    if (ec || !fs::is_directory(dir, ec)) {
      err = dir.string() + ": cannot create the report folder: " +
            (ec ? ec.message() : std::string("exists and is not a folder"));
      return false;
    }
    const std::array<std::pair<const char*, std::string>, 6> files = {{{"report.json", report_json(r)},
                                                                        {"report.csv", report_csv(r)},
                                                                        {"report.md", report_md(r)},
                                                                        {"coverage.csv", coverage_csv(r)},
                                                                        {"runs.csv", runs_csv(r)},
                                                                        {"outcomes.gp", report_gnuplot(r)}}};
    for (const auto& [name, text] : files) {
      if (!write_atomic(dir, name, text, err)) {
        return false;
      }
    }
    note = make_png(dir, "outcomes");
    const std::array<std::pair<const char*, std::string>, 2> integrity = {
        {{"integrity.csv", r.per_run.empty() ? std::string{} : integrity_csv(r)},
         {"integrity.gp", r.per_run.empty() ? std::string{} : integrity_gnuplot(r)}}};
    for (const auto& [name, text] : integrity) {
      if (text.empty()) {
        fs::remove(dir / name, ec);  // no figures: none of an earlier report stays beside this one
      } else if (!write_atomic(dir, name, text, err)) {
        return false;
      }
    }
    if (r.per_run.empty()) {
      fs::remove(dir / "integrity.png", ec);
    } else {
      const std::string n = make_png(dir, "integrity");
      note += n.empty() || note == n ? std::string{} : (note.empty() ? "" : "; ") + n;
    }
    return true;
  } catch (const std::exception& e) {
    err = dir.string() + ": cannot write the report: " + e.what();
    return false;
  }
}

bool write_report(const Report& r, const fs::path& dir, std::string& err) {
  std::string note;
  const bool ok = write_report(r, dir, err, note);
  if (ok && !note.empty()) {
    std::fprintf(stderr, "campaign report: %s\n", note.c_str());
  }
  return ok;
}

}  // namespace tools::campaign
