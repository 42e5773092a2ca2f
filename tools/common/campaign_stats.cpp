/**
 * @file campaign_stats.cpp
 * @brief Binomial intervals (Boost.Math quantiles), runs for a margin, per-kind summaries and the campaign report files.
 */
#include "tools/common/campaign_stats.hpp"

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

/** Runs outcomes.gp in @p dir into a temporary PNG, renamed to outcomes.png on success. @return a note, "" if all went well. */
std::string make_png(const fs::path& dir) {
  const std::string gnuplot = find_on_path("gnuplot");
  if (gnuplot.empty()) {
    return "gnuplot is not installed: the chart script is " + (dir / "outcomes.gp").string() +
           " (run it there with gnuplot)";
  }
  const fs::path tmp = temp_path(dir, "outcomes.png");
  std::string failed =
      run_gnuplot(gnuplot, dir.string(), "outcomes.gp", {"-e", "out=" + gp_string(tmp.filename().string())});
  std::error_code ec;
  if (!failed.empty()) {
    fs::remove(tmp, ec);
    return failed;
  }
  fs::rename(tmp, dir / "outcomes.png", ec);
  if (ec) {
    fs::remove(tmp, ec);
    return (dir / "outcomes.png").string() + ": cannot move into place: " + ec.message();
  }
  return {};
}

}  // namespace

// ------------------------------------------------------------------ outcomes

const char* outcome_name(Outcome o) noexcept {
  switch (o) {
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

Report summarize(std::string_view campaign, std::span<const RunResult> runs, double conf) {
  check_conf("summarize", conf);
  Report r;
  r.campaign = std::string(campaign);
  r.confidence = conf;
  r.runs = runs.size();
  std::array<std::uint64_t, kOutcomeCount> all{};
  struct Tally {
    std::uint64_t runs = 0;
    std::array<std::uint64_t, kOutcomeCount> counts{};
  };
  std::map<std::string, Tally> by_kind;  // ordered: the report lists kinds sorted by name
  for (const RunResult& run : runs) {
    const auto cls = static_cast<std::size_t>(run.outcome);
    if (cls >= kOutcomeCount) {
      throw std::invalid_argument("summarize: run " + std::to_string(run.index) + " has no valid outcome (" +
                                  std::to_string(cls) + ")");
    }
    ++all[cls];
    Tally& t = by_kind[run.kind.empty() ? std::string(kUnknownKind) : run.kind];
    ++t.runs;
    ++t.counts[cls];
    r.host_s_total += run.host_s;
  }
  r.classes = classes_of(all, r.runs, conf);
  r.kinds.reserve(by_kind.size());
  for (const auto& [kind, t] : by_kind) {
    r.kinds.push_back(KindReport{kind, t.runs, classes_of(t.counts, t.runs, conf)});
  }
  r.margin_at_runs = margin_for_runs(r.runs, conf);
  return r;
}

// ------------------------------------------------------------------ report files

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
  Json j;
  j["campaign"] = r.campaign;
  j["confidence"] = num(r.confidence);
  j["runs"] = r.runs;
  j["margin_at_runs"] = num(r.margin_at_runs);
  j["host_s_total"] = num(r.host_s_total);
  j["classes"] = classes(r.classes, r.runs);
  Json kinds = Json::array();
  for (const KindReport& k : r.kinds) {
    kinds.push_back(Json{{"kind", k.kind}, {"runs", k.runs}, {"classes", classes(k.classes, k.runs)}});
  }
  j["kinds"] = kinds;
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
  for (const KindReport& k : r.kinds) {
    block(k.kind, k.classes, k.runs);
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
  for (const KindReport& k : r.kinds) {
    s += " " + md_text(k.kind) + " (" + std::to_string(k.runs) + " runs) |";
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
    for (const KindReport& k : r.kinds) {
      s += cell(k.classes[i], k.runs);
    }
    s += "\n";
  }
  return s;
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
    const std::array<std::pair<const char*, std::string>, 4> files = {{{"report.json", report_json(r)},
                                                                        {"report.csv", report_csv(r)},
                                                                        {"report.md", report_md(r)},
                                                                        {"outcomes.gp", report_gnuplot(r)}}};
    for (const auto& [name, text] : files) {
      if (!write_atomic(dir, name, text, err)) {
        return false;
      }
    }
    note = make_png(dir);
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
