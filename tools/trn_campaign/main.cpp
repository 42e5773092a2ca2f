/**
 * @file main.cpp
 * @brief trn_campaign: fault-injection campaigns over the mission image - runs in parallel,
 *        resumable, sharded, merged; outcome classes with confidence intervals; a Slurm job array.
 *
 *   trn_campaign run SPEC [--out DIR] [-j N] [--shard i/N]   fly the campaign (or one shard of it)
 *   trn_campaign merge --out DIR SHARD...                    one report from shard folders
 *   trn_campaign sbatch SPEC --out DIR --tasks N             a Slurm job-array script for it
 *   trn_campaign margin --margin E [--confidence C]          runs needed for a margin of error
 *   trn_campaign shrink RUN_DIR                              a failing run's plan reduced (ddmin)
 *
 * Each run is a process of build/trn_mission with the run's drawn plan
 * (docs/CAMPAIGNS.md): a crash or a hang of the image is the run's outcome,
 * not the campaign's end. Every run's result is written atomically into its
 * folder, so an interrupted campaign resumes where it stopped.
 */
#include "bsp_tile64/emu/board.hpp"
#include "bsp_tile64/world/trajectory.hpp"
#include "tools/common/campaign/campaign.hpp"
#include "tools/common/campaign/campaign_stats.hpp"
#include "tools/common/cli_checks.hpp"
#include "tools/common/mission/image_id.hpp"
#include "tools/common/mission/scenario.hpp"
#include "tools/common/text.hpp"
#include "tools/common/toml_input.hpp"

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <optional>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

extern char** environ;

namespace {

namespace fs = std::filesystem;
namespace cp = tools::campaign;
using Clock = std::chrono::steady_clock;

/** The golden run's index in results (no fault). */
constexpr std::uint32_t kGolden = 0xFFFF'FFFFU;

/**
 * The format of a run's result.json. 2: the strict classes (not_delivered, no_effect) and the flags; a
 * result without it was judged by older rules and is refused by name, never read as a class of today's.
 */
constexpr int kResultFormat = 2;

/** What the runs' delivered navigation streams are compared with: the golden run's seed and stream CRC. */
struct Golden {
  std::uint64_t seed = 0U;
  std::uint32_t crc = 0U;
};

std::string read_text(const fs::path& p) {
  std::ifstream in(p);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

/** Writes @p text to @p p through a temporary name in the same folder and a rename. */
bool write_atomic(const fs::path& p, const std::string& text, std::string& err) {
  const fs::path tmp = p.string() + ".tmp" + std::to_string(::getpid());
  {
    std::ofstream out(tmp, std::ios::trunc);
    out << text;
    out.flush();
    if (!out) {
      err = tmp.string() + ": cannot write";
      return false;
    }
  }
  std::error_code ec;
  fs::rename(tmp, p, ec);
  if (ec) {
    err = p.string() + ": cannot rename into place: " + ec.message();
    return false;
  }
  return true;
}

/** The image next to this program (build/trn_mission), unless given. */
std::string default_mission() {
  std::error_code ec;
  const fs::path self = fs::read_symlink("/proc/self/exe", ec);
  return ec ? std::string("build/trn_mission") : (self.parent_path() / "trn_mission").string();
}

/** Seconds of the scenario's whole descent (the runs' length when the spec gives none). */
bool descent_seconds(const std::string& scenario_path, double& out, std::string& err) {
  tools::Scenario sc = tools::default_scenario();
  if (!scenario_path.empty()) {
    tools::ScenarioResult r = tools::load_scenario(scenario_path);
    if (!r.ok()) {
      err = r.error;
      return false;
    }
    sc = *r.scenario;
  }
  bsp::world::Trajectory probe;
  if (probe.init(sc.trajectory) != bsp::world::WorldError::kOk) {
    err = "the scenario's trajectory is not valid";
    return false;
  }
  out = std::floor(probe.duration_s());
  return true;
}

struct Loaded {
  cp::Spec spec;
  std::string text;  ///< the spec file as written (copied into the campaign folder)
  double run_s = 0.0;
};

bool load(const std::string& path, Loaded& l, std::string& err) {
  // The scenario decides the longest window: read its path first, then validate against its descent.
  cp::SpecResult first = cp::load_spec(path, 1000.0);
  if (!first.ok()) {
    err = first.error;
    return false;
  }
  double descent = 0.0;
  if (!descent_seconds(first.spec.scenario, descent, err)) {
    err = path + ": scenario: " + err;
    return false;
  }
  cp::SpecResult r = cp::load_spec(path, descent);
  if (!r.ok()) {
    err = r.error;
    return false;
  }
  if (r.spec.duration_s > descent) {
    err = path + ": duration_s: " + tools::format_number(r.spec.duration_s) + " s is longer than the descent (" +
          tools::format_number(descent) + " s)";
    return false;
  }
  l.spec = r.spec;
  l.text = read_text(path);
  l.run_s = r.spec.duration_s > 0.0 ? r.spec.duration_s : descent;
  return true;
}

// ------------------------------------------------------------------ one run

struct Job {
  std::uint32_t index = 0U;  ///< kGolden: the fault-free run
  fs::path dir;
  std::string kind;
  std::string role;  ///< the target drawn (DrawnPlan::role)
  pid_t pid = -1;
  Clock::time_point started;
  bool timed_out = false;
};

std::vector<std::string> mission_args(const std::string& mission, const cp::Spec& s, const Job& j,
                                      const fs::path& world) {
  const std::uint64_t seed = j.index == kGolden ? s.seed : cp::scenario_seed(s, j.index);
  std::vector<std::string> a = {mission, "--quiet", "--no-plots", "--seed", std::to_string(seed), "--out",
                                (j.dir / "out").string(), "--world-cache", world.string()};
  if (s.duration_s > 0.0) {
    a.insert(a.end(), {"--duration", tools::format_number(s.duration_s)});
  }
  if (!s.scenario.empty()) {
    a.insert(a.end(), {"--scenario", s.scenario});
  }
  if (!s.chip.empty()) {
    a.insert(a.end(), {"--chip", s.chip});
  }
  if (j.index != kGolden) {
    a.insert(a.end(), {"--faults", (j.dir / "plan.toml").string()});
  }
  return a;
}

bool start(const std::string& mission, const cp::Spec& s, Job& j, const fs::path& world, std::string& err) {
  std::error_code ec;
  fs::remove_all(j.dir / "out", ec);  // a run cut short before: fly it again from nothing
  std::vector<std::string> args = mission_args(mission, s, j, world);
  std::vector<char*> argv;
  argv.reserve(args.size() + 1U);
  for (std::string& a : args) {
    argv.push_back(a.data());  // posix_spawn takes char* const[]: the strings outlive the call
  }
  argv.push_back(nullptr);
  posix_spawn_file_actions_t fa;
  posix_spawn_file_actions_init(&fa);
  const std::string log = (j.dir / "run.log").string();
  posix_spawn_file_actions_addopen(&fa, 1, log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  posix_spawn_file_actions_adddup2(&fa, 1, 2);
  posix_spawn_file_actions_addopen(&fa, 0, "/dev/null", O_RDONLY, 0);
  const int rc = posix_spawn(&j.pid, args[0].c_str(), &fa, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&fa);
  if (rc != 0) {
    err = "cannot start " + args[0] + ": " + std::strerror(rc);
    return false;
  }
  j.started = Clock::now();
  return true;
}

/** A number of a summary or a result; null (how a value that is not finite is written) reads as NaN. */
double number_or_nan(const nlohmann::json& j, const char* key) {
  const nlohmann::json& v = j.at(key);
  return v.is_null() ? std::nan("") : v.get<double>();
}

constexpr std::array<const char*, 3> kAxes = {"x", "y", "z"};

/** The navigation-integrity figures of a summary (docs/FILTER.md, "Integrity"); throws if one is missing. */
void read_integrity(const nlohmann::json& sj, cp::RunResult& r) {
  r.fix_at_s = number_or_nan(sj, "fix_at_s");
  if (!(r.fix_at_s >= 0.0)) {
    r.fix_at_s = -1.0;
  }
  r.converged_at_s = number_or_nan(sj, "converged_at_s");
  if (!(r.converged_at_s >= 0.0)) {
    r.converged_at_s = -1.0;
  }
  const double outputs = number_or_nan(sj, "integrity_outputs");
  r.integrity_outputs = std::isfinite(outputs) && outputs > 0.0 ? static_cast<std::uint64_t>(outputs) : 0U;
  for (std::size_t a = 0; a < 3U; ++a) {
    const std::string axis = kAxes[a];
    const double f = number_or_nan(sj, ("integrity_beyond_3sigma_fraction_" + axis).c_str());
    // The summary gives the fraction of a count of outputs: the count is its nearest integer.
    r.beyond_3sigma[a] = std::isfinite(f) ? static_cast<std::uint64_t>(std::llround(f * outputs)) : r.integrity_outputs;
    const double n5 = number_or_nan(sj, ("integrity_beyond_5sigma_" + axis).c_str());
    r.beyond_5sigma[a] = std::isfinite(n5) && n5 > 0.0 ? static_cast<std::uint64_t>(n5) : 0U;
    r.worst_ratio[a] = number_or_nan(sj, ("integrity_worst_ratio_" + axis).c_str());
  }
  r.has_integrity = true;
}

/** A count of a summary (written as a number, often a double); throws if @p key is absent or not a number. */
std::uint32_t count_of(const nlohmann::json& sj, const char* key) {
  const double v = sj.at(key).get<double>();
  return v > 0.0 ? static_cast<std::uint32_t>(std::min(v, 4294967295.0)) : 0U;  // NaN and negatives: none
}

/** The summary's filter_output_crc (throws if absent); none if it is not a 32-bit value. */
std::optional<std::uint32_t> output_crc_of(const nlohmann::json& sj) {
  const double v = number_or_nan(sj, "filter_output_crc");
  if (!(v >= 0.0 && v <= 4294967295.0) || v != std::floor(v)) {
    return std::nullopt;
  }
  return static_cast<std::uint32_t>(v);
}

/** The facts and counts of a summary the image wrote, into @p f and @p r. Throws a json exception if one is missing. */
void read_summary(const nlohmann::json& sj, const std::optional<Golden>& golden, cp::RunFacts& f, cp::RunResult& r,
                  nlohmann::json& rec) {
  f.exited_ok = true;
  f.mission_lost = sj.value("mission_lost", 0.0) != 0.0;
  // A final error that is not finite (written as null) is a lost navigation, not an unreadable summary.
  f.final_error_m = number_or_nan(sj, "final_position_error_m");
  if (!std::isfinite(f.final_error_m)) {
    f.final_error_m = std::numeric_limits<double>::infinity();
  }
  f.injected = count_of(sj, "faults_injected");
  f.not_delivered = count_of(sj, "faults_not_delivered");
  f.detected = count_of(sj, "faults_detected");
  f.recovered = count_of(sj, "faults_recovered");
  f.degraded_accepted = count_of(sj, "faults_degraded_accepted");
  f.misdiagnosed = count_of(sj, "faults_misdiagnosed");
  f.false_alarms = count_of(sj, "false_alarms");
  f.healthy_disturbed = count_of(sj, "healthy_tiles_disturbed");
  r.output_crc = output_crc_of(sj);
  // Bit for bit the fault-free stream: the same seed (the same world and sensors) and the same CRC.
  f.output_as_golden = golden.has_value() && r.output_crc.has_value() && r.seed == golden->seed &&
                       *r.output_crc == golden->crc;
  r.final_error_m = f.final_error_m;
  r.max_error_m = number_or_nan(sj, "max_position_error_after_convergence_m");  // NaN: never converged
  r.injected = f.injected;
  r.not_delivered = f.not_delivered;
  r.detected = f.detected;
  r.recovered = f.recovered;
  r.degraded_accepted = f.degraded_accepted;
  r.misdiagnosed = f.misdiagnosed;
  r.false_alarms = f.false_alarms;
  r.healthy_disturbed = f.healthy_disturbed;
  r.output_as_golden = f.output_as_golden;
  rec["mission_lost"] = f.mission_lost;
  rec["trace_hash"] = sj.value("trace_hash", std::string{});
  rec["deadline_misses"] = sj.value("deadline_misses", 0);
}

/**
 * The result of a finished run from its exit status and summary; its delivered stream is compared with
 * @p golden's (none: the golden run itself, or a shrink without one).
 */
cp::RunResult finish(const cp::Spec& s, const Job& j, int status, nlohmann::json& rec,
                     const std::optional<Golden>& golden) {
  cp::RunResult r;
  r.index = j.index;
  r.kind = j.index == kGolden ? std::string("none") : j.kind;
  r.role = j.index == kGolden ? std::string("none") : j.role;
  r.seed = j.index == kGolden ? s.seed : cp::scenario_seed(s, j.index);
  r.host_s = std::chrono::duration<double>(Clock::now() - j.started).count();
  cp::RunFacts f;
  const fs::path summary = j.dir / "out" / "summary.json";
  const bool exited = WIFEXITED(status) && WEXITSTATUS(status) == 0;
  rec["exit"] = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  rec["signal"] = WIFSIGNALED(status) ? WTERMSIG(status) : 0;
  rec["timed_out"] = j.timed_out;
  if (exited && fs::exists(summary)) {
    cp::RunResult read = r;  // kept only when the whole summary was read
    try {
      const nlohmann::json sj = nlohmann::json::parse(read_text(summary));
      read_summary(sj, golden, f, read, rec);
      try {
        read_integrity(sj, read);
      } catch (const nlohmann::json::exception& e) {
        read.has_integrity = false;  // an image without the figures: its outcome stands, its integrity is unknown
        rec["integrity_error"] = e.what();
      }
      r = std::move(read);
    } catch (const nlohmann::json::exception& e) {
      f = cp::RunFacts{};  // an unreadable summary is the image's failure
      rec["summary_error"] = e.what();
    }
  }
  r.outcome = cp::classify(f, s.pass_bound_m, s.degraded_bound_m);
  return r;
}

nlohmann::json to_json(const cp::RunResult& r, nlohmann::json rec) {
  rec["result_format"] = kResultFormat;
  rec["index"] = r.index == kGolden ? nlohmann::json("golden") : nlohmann::json(r.index);
  rec["kind"] = r.kind;
  rec["role"] = r.role;
  rec["outcome"] = cp::outcome_name(r.outcome);
  const auto num = [](double v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(); };
  rec["seed"] = r.seed;
  rec["final_error_m"] = num(r.final_error_m);
  rec["max_error_m"] = num(r.max_error_m);
  rec["host_s"] = r.host_s;
  rec["injected"] = r.injected;
  rec["not_delivered"] = r.not_delivered;
  rec["detected"] = r.detected;
  rec["recovered"] = r.recovered;
  rec["degraded_accepted"] = r.degraded_accepted;
  rec["misdiagnosed"] = r.misdiagnosed;
  rec["false_alarms"] = r.false_alarms;
  rec["healthy_tiles_disturbed"] = r.healthy_disturbed;
  rec["filter_output_crc"] = r.output_crc ? nlohmann::json(*r.output_crc) : nlohmann::json();
  rec["output_as_golden"] = r.output_as_golden;
  if (r.has_integrity) {
    nlohmann::json in{{"fix_at_s", r.fix_at_s}, {"converged_at_s", r.converged_at_s}, {"outputs", r.integrity_outputs}};
    for (std::size_t a = 0; a < 3U; ++a) {
      in[kAxes[a]] = {{"beyond_3sigma", r.beyond_3sigma[a]},
                      {"beyond_5sigma", r.beyond_5sigma[a]},
                      {"worst_ratio", num(r.worst_ratio[a])}};
    }
    rec["integrity"] = in;
  }
  return rec;
}

/** A result.json's record into @p r; throws a json exception on a missing key or a wrong type. */
void from_json(const nlohmann::json& j, cp::RunResult& r) {
  r.index = j.at("index").is_string() ? kGolden : j.at("index").get<std::uint32_t>();
  r.kind = j.at("kind").get<std::string>();
  r.role = j.at("role").get<std::string>();
  if (!cp::outcome_from_name(j.at("outcome").get<std::string>(), r.outcome)) {
    throw std::invalid_argument("unknown outcome \"" + j.at("outcome").get<std::string>() + "\"");
  }
  r.final_error_m = number_or_nan(j, "final_error_m");
  r.max_error_m = number_or_nan(j, "max_error_m");
  r.host_s = j.at("host_s").get<double>();
  r.injected = j.at("injected").get<std::uint32_t>();
  r.not_delivered = j.at("not_delivered").get<std::uint32_t>();
  r.detected = j.at("detected").get<std::uint32_t>();
  r.recovered = j.at("recovered").get<std::uint32_t>();
  r.degraded_accepted = j.at("degraded_accepted").get<std::uint32_t>();
  r.misdiagnosed = j.at("misdiagnosed").get<std::uint32_t>();
  r.false_alarms = j.at("false_alarms").get<std::uint32_t>();
  r.healthy_disturbed = j.at("healthy_tiles_disturbed").get<std::uint32_t>();
  const nlohmann::json& crc = j.at("filter_output_crc");
  r.output_crc = crc.is_null() ? std::nullopt : std::optional<std::uint32_t>(crc.get<std::uint32_t>());
  r.output_as_golden = j.at("output_as_golden").get<bool>();
  r.seed = j.value("seed", std::uint64_t{0});  // results of a campaign before seeds were recorded have none
  if (const auto in = j.find("integrity"); in != j.end()) {
    r.fix_at_s = in->at("fix_at_s").get<double>();
    r.converged_at_s = in->at("converged_at_s").get<double>();
    r.integrity_outputs = in->at("outputs").get<std::uint64_t>();
    for (std::size_t a = 0; a < 3U; ++a) {
      const nlohmann::json& ax = in->at(kAxes[a]);
      r.beyond_3sigma[a] = ax.at("beyond_3sigma").get<std::uint64_t>();
      r.beyond_5sigma[a] = ax.at("beyond_5sigma").get<std::uint64_t>();
      r.worst_ratio[a] = number_or_nan(ax, "worst_ratio");
    }
    r.has_integrity = true;
  }
}

/** What reading a run's result.json gave. */
enum class ReadResult : std::uint8_t {
  kNone,     ///< no result: none written, or one that is not JSON (torn): the run is flown again
  kOk,       ///< read
  kRefused,  ///< a result of an older trn_campaign or a record that is not a result: the reason names the file
};

/** Reads @p file into @p r; on kRefused, @p err says why, naming the file. */
ReadResult read_result(const fs::path& file, cp::RunResult& r, std::string& err) {
  if (!fs::exists(file)) {
    return ReadResult::kNone;
  }
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(read_text(file));
  } catch (const nlohmann::json::exception&) {
    return ReadResult::kNone;  // torn: the run is flown again
  }
  if (!j.is_object() || !j.contains("result_format")) {
    err = file.string() + ": a result of an older trn_campaign (no result_format): its class was judged without "
                          "not_delivered and no_effect and it has no flags, so it is not read as one of today's; fly "
                          "the campaign into another --out, or remove the runs' result.json files to fly them again";
    return ReadResult::kRefused;
  }
  try {
    if (j.at("result_format").get<int>() != kResultFormat) {
      err = file.string() + ": result_format " + j.at("result_format").dump() + ", this trn_campaign reads " +
            std::to_string(kResultFormat) + ": fly the campaign into another --out";
      return ReadResult::kRefused;
    }
    from_json(j, r);
  } catch (const std::exception& e) {
    err = file.string() + ": not a campaign result: " + e.what();
    return ReadResult::kRefused;
  }
  return ReadResult::kOk;
}

/** The golden run's seed and stream CRC from its result @p g (read from @p file); none, with @p err set, if none. */
std::optional<Golden> golden_of(const cp::RunResult& g, const fs::path& file, std::string& err) {
  if (!g.output_crc) {
    err = file.string() + ": the golden run's result has no filter_output_crc to compare the runs with";
    return std::nullopt;
  }
  return Golden{g.seed, *g.output_crc};
}

/**
 * The golden run's stream from its result @p file, when it has one (it is not flown again): kOk with
 * @p out set, kNone, or kRefused with @p err naming the file (an older result, or one without a CRC).
 */
ReadResult read_golden(const fs::path& file, std::optional<Golden>& out, std::string& err) {
  cp::RunResult g;
  const ReadResult got = read_result(file, g, err);
  if (got == ReadResult::kOk) {
    out = golden_of(g, file, err);
    return out ? ReadResult::kOk : ReadResult::kRefused;
  }
  return got;
}

/**
 * The golden run @p r, just flown: judged against no stream it must be masked (correct, nothing detected),
 * and its stream becomes @p out, what the runs are compared with. @return false with @p err otherwise.
 */
bool accept_golden(const cp::Spec& s, const Job& j, const cp::RunResult& r, std::optional<Golden>& out,
                   std::string& err) {
  if (r.outcome != cp::Outcome::kMasked) {
    err = "the fault-free run is not correct (" + std::string(cp::outcome_name(r.outcome)) + ", " +
          tools::format_number(r.final_error_m) + " m against the pass bound of " +
          tools::format_number(s.pass_bound_m) + " m): see " + (j.dir / "run.log").string();
    return false;
  }
  out = golden_of(r, j.dir / "result.json", err);
  return out.has_value();
}

// ------------------------------------------------------------------ progress

void progress(bool quiet, std::size_t done, std::size_t total, std::size_t running, Clock::time_point t0,
              std::size_t done_at_start) {
  if (quiet) {
    return;
  }
  const double el = std::chrono::duration<double>(Clock::now() - t0).count();
  const std::size_t new_done = done - done_at_start;
  const double eta = new_done > 0U ? el / static_cast<double>(new_done) * static_cast<double>(total - done) : 0.0;
  constexpr int kBar = 30;
  const int fill = total > 0U ? static_cast<int>(kBar * done / total) : kBar;
  std::fprintf(stderr, "\r[%s%s] %zu/%zu runs, %zu running, ETA %dm%02ds   ", std::string(static_cast<std::size_t>(fill), '#').c_str(),
               std::string(static_cast<std::size_t>(kBar - fill), '.').c_str(), done, total, running,
               static_cast<int>(eta) / 60, static_cast<int>(eta) % 60);
  if (!::isatty(2)) {
    std::fprintf(stderr, "\n");
  }
}

// ------------------------------------------------------------------ commands

struct RunOptions {
  std::string spec;
  std::string out;
  std::uint32_t jobs = 0U;
  std::string shard = "0/1";
  std::string mission;
  std::string world;  ///< world cache folder (default <out>/world)
  bool quiet = false;
};

/** The campaign folder holds this campaign (or is new): the spec text must match. */
bool claim_folder(const fs::path& out, const Loaded& l, std::string& err) {
  std::error_code ec;
  fs::create_directories(out / "runs", ec);
  if (ec) {
    err = out.string() + ": cannot create: " + ec.message();
    return false;
  }
  const fs::path copy = out / "campaign.toml";
  if (fs::exists(copy)) {
    if (read_text(copy) != l.text) {
      err = out.string() + " holds another campaign (its campaign.toml differs from the spec): choose another --out";
      return false;
    }
    return true;
  }
  return write_atomic(copy, l.text, err);
}

/** The mission image's identity: its build (image_id.hpp), as the world cache keys its products. */
std::string image_stamp(const std::string& image) { return tools::image_identity(image); }

/**
 * The folder's runs were flown by this build of the image, or it has none yet: a campaign resumed with
 * a rebuilt image would report old and new runs as one. The stamp is written before the first run.
 */
bool claim_image(const fs::path& out, const std::string& image, std::string& err) {
  const std::string stamp = image_stamp(image);
  const fs::path file = out / "image.stamp";
  if (fs::exists(file)) {
    if (read_text(file) == stamp + "\n") {
      return true;
    }
    err = out.string() + " holds runs flown by another build of the mission image (" + image +
          " changed since): choose another --out, or remove the folder to fly the campaign again";
    return false;
  }
  std::error_code ec;
  for (const fs::directory_entry& e : fs::directory_iterator(out / "runs", ec)) {
    if (fs::exists(e.path() / "result.json")) {
      err = out.string() + " holds runs of a build it did not record (no image.stamp): choose another --out, "
                           "or remove the folder to fly the campaign again";
      return false;
    }
  }
  return write_atomic(file, stamp + "\n", err);
}

int cmd_run(const RunOptions& o) {
  Loaded l;
  std::string err;
  if (!load(o.spec, l, err)) {
    std::fprintf(stderr, "trn_campaign: %s\n", err.c_str());
    return 2;
  }
  std::uint32_t shard = 0U;
  std::uint32_t shards = 1U;
  if (!cp::parse_shard(o.shard, shard, shards)) {
    std::fprintf(stderr, "trn_campaign: --shard %s: expected i/N with 0 <= i < N\n", o.shard.c_str());
    return 2;
  }
  const fs::path out = o.out.empty() ? fs::path("out") / ("campaign-" + l.spec.name) : fs::path(o.out);
  if (!claim_folder(out, l, err)) {
    std::fprintf(stderr, "trn_campaign: %s\n", err.c_str());
    return 2;
  }
  const std::string mission = o.mission.empty() ? default_mission() : o.mission;
  if (::access(mission.c_str(), X_OK) != 0) {
    std::fprintf(stderr, "trn_campaign: the mission image %s is missing (make build/trn_mission)\n", mission.c_str());
    return 2;
  }
  if (!claim_image(out, mission, err)) {
    std::fprintf(stderr, "trn_campaign: %s\n", err.c_str());
    return 2;
  }
  // The runs of this shard, their plans drawn and written first: a bad spec fails before any flight.
  std::vector<Job> todo;
  std::vector<cp::RunResult> results;
  Job golden;
  golden.index = kGolden;
  golden.dir = out / "golden";
  std::error_code ec;
  fs::create_directories(golden.dir, ec);
  std::optional<Golden> golden_stream;  // known once the golden run has a result
  const ReadResult golden_read = read_golden(golden.dir / "result.json", golden_stream, err);
  if (golden_read == ReadResult::kRefused) {
    std::fprintf(stderr, "trn_campaign: %s\n", err.c_str());
    return 2;
  }
  if (golden_read == ReadResult::kNone) {
    todo.push_back(golden);
  }
  std::size_t total = 0U;
  for (std::uint32_t i = shard; i < l.spec.runs; i += shards) {
    ++total;
    Job j;
    j.index = i;
    char name[16];
    std::snprintf(name, sizeof name, "%06u", i);
    j.dir = out / "runs" / name;
    cp::RunResult r;
    const ReadResult got = read_result(j.dir / "result.json", r, err);
    if (got == ReadResult::kRefused) {
      std::fprintf(stderr, "trn_campaign: %s\n", err.c_str());
      return 2;
    }
    if (got == ReadResult::kOk) {
      results.push_back(r);
      continue;
    }
    const cp::DrawnPlan p = cp::draw_plan(l.spec, i, cp::spec_deployment(l.spec).tiles(), l.run_s);
    if (!p.error.empty()) {
      std::fprintf(stderr, "trn_campaign: %s\n", p.error.c_str());
      return 2;
    }
    fs::create_directories(j.dir, ec);
    if (!write_atomic(j.dir / "plan.toml", p.toml, err)) {
      std::fprintf(stderr, "trn_campaign: %s\n", err.c_str());
      return 1;
    }
    j.kind = p.kind;
    j.role = p.role;
    todo.push_back(j);
  }
  const std::uint32_t jobs = o.jobs > 0U ? o.jobs : std::max(1U, std::thread::hardware_concurrency());
  if (!o.quiet) {
    std::fprintf(stderr, "trn_campaign: %s, shard %u/%u: %zu runs, %zu done before, %u in parallel; folder %s\n",
                 l.spec.name.c_str(), shard, shards, total, results.size(), jobs, out.string().c_str());
  }
  const std::size_t done_at_start = results.size();
  const Clock::time_point t0 = Clock::now();
  std::vector<Job> running;
  std::size_t next = 0U;
  while (next < todo.size() || !running.empty()) {
    // The golden run goes first and alone: the campaign's bounds are checked against it.
    const bool golden_running = !running.empty() && running[0].index == kGolden;
    while (next < todo.size() && running.size() < jobs && !golden_running) {
      Job j = todo[next++];
      if (!start(mission, l.spec, j, o.world.empty() ? out / "world" : fs::path(o.world), err)) {
        std::fprintf(stderr, "\ntrn_campaign: %s\n", err.c_str());
        return 1;
      }
      running.push_back(j);
      if (j.index == kGolden) {
        break;
      }
    }
    int status = 0;
    const pid_t pid = ::waitpid(-1, &status, WNOHANG);
    if (pid <= 0) {
      for (Job& j : running) {
        if (!j.timed_out && std::chrono::duration<double>(Clock::now() - j.started).count() > l.spec.timeout_s) {
          j.timed_out = true;  // a hung image: killed, and the run's outcome says so
          (void)::kill(j.pid, SIGKILL);
        }
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
      continue;
    }
    const auto it = std::find_if(running.begin(), running.end(), [pid](const Job& j) { return j.pid == pid; });
    if (it == running.end()) {
      continue;
    }
    const Job j = *it;
    running.erase(it);
    nlohmann::json rec;
    const cp::RunResult r = finish(l.spec, j, status, rec, golden_stream);
    if (j.index != kGolden) {
      results.push_back(r);
    } else if (!accept_golden(l.spec, j, r, golden_stream, err)) {  // the runs start after it: none finished before
      std::fprintf(stderr, "trn_campaign: %s\n", err.c_str());
      return 1;
    }
    if (!write_atomic(j.dir / "result.json", to_json(r, rec).dump(2) + "\n", err)) {
      std::fprintf(stderr, "\ntrn_campaign: %s\n", err.c_str());
      return 1;
    }
    progress(o.quiet, results.size(), total, running.size(), t0, done_at_start);
  }
  if (!o.quiet) {
    std::fprintf(stderr, "\n");
  }
  std::sort(results.begin(), results.end(), [](const cp::RunResult& a, const cp::RunResult& b) { return a.index < b.index; });
  const cp::Report rep = cp::summarize(l.spec.name, results);
  if (!cp::write_report(rep, out, err)) {
    std::fprintf(stderr, "trn_campaign: %s\n", err.c_str());
    return 1;
  }
  if (!o.quiet) {
    std::printf("%s", read_text(out / "report.md").c_str());
    std::printf("report in %s/ (report.json, report.csv, report.md, coverage.csv, runs.csv, outcomes.png)\n",
                out.string().c_str());
  }
  return 0;
}

/** Flies one job to its end (killed at the spec's timeout) and returns its result, judged against @p golden. */
cp::RunResult fly_one(const std::string& mission, const cp::Spec& s, Job& j, const fs::path& world,
                      const std::optional<Golden>& golden, std::string& err, bool& ok) {
  ok = start(mission, s, j, world, err);
  if (!ok) {
    return {};
  }
  int status = 0;
  while (::waitpid(j.pid, &status, WNOHANG) == 0) {
    if (!j.timed_out && std::chrono::duration<double>(Clock::now() - j.started).count() > s.timeout_s) {
      j.timed_out = true;
      (void)::kill(j.pid, SIGKILL);
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  nlohmann::json rec;
  return finish(s, j, status, rec, golden);
}

/** A plan's text with the faults of @p keep only (its name and commands kept). */
std::string plan_subset(const toml::table& plan, const std::vector<std::size_t>& keep) {
  toml::table out;
  if (const toml::node* n = plan.get("name")) {
    out.insert("name", *n);
  }
  if (const toml::node* n = plan.get("command")) {
    out.insert("command", *n);
  }
  toml::array faults;
  const toml::array* all = plan.get_as<toml::array>("fault");
  for (const std::size_t i : keep) {
    faults.push_back(*all->get(i));
  }
  out.insert("fault", faults);
  std::ostringstream o;
  o << out << "\n";
  return o.str();
}

/**
 * Delta debugging (Zeller and Hildebrandt, ddmin) over a failing run's faults:
 * the smallest subset found that still ends in the run's outcome class,
 * written beside the plan as plan.min.toml.
 */
int cmd_shrink(const std::string& run_dir, const std::string& mission_opt, const std::string& world_opt, bool quiet) {
  const fs::path run(run_dir);
  const fs::path campaign_dir = run.parent_path().parent_path();
  cp::RunResult original;
  std::string err;
  const ReadResult got = read_result(run / "result.json", original, err);
  if (got == ReadResult::kRefused) {
    std::fprintf(stderr, "trn_campaign: shrink: %s\n", err.c_str());
    return 2;
  }
  if (got != ReadResult::kOk || !fs::exists(run / "plan.toml")) {
    std::fprintf(stderr, "trn_campaign: shrink: %s is not a finished campaign run (plan.toml, result.json)\n",
                 run_dir.c_str());
    return 2;
  }
  Loaded l;
  if (!load((campaign_dir / "campaign.toml").string(), l, err)) {
    std::fprintf(stderr, "trn_campaign: shrink: %s\n", err.c_str());
    return 2;
  }
  // The candidates' streams are compared with the golden run's when the campaign has one; without it a
  // candidate that changed nothing is masked instead of no_effect, neither of them a failure.
  std::optional<Golden> golden;
  {
    cp::RunResult g;
    std::string ignored;
    if (read_result(campaign_dir / "golden" / "result.json", g, ignored) == ReadResult::kOk) {
      golden = golden_of(g, campaign_dir / "golden" / "result.json", ignored);
    }
  }
  const cp::Outcome o = original.outcome;
  const bool failed = o == cp::Outcome::kDegraded || o == cp::Outcome::kLost || o == cp::Outcome::kSdc ||
                      o == cp::Outcome::kCrash;
  if (!failed) {
    std::fprintf(stderr, "trn_campaign: shrink: run %s ended %s: nothing failed to shrink\n", run_dir.c_str(),
                 cp::outcome_name(original.outcome));
    return 2;
  }
  toml::table plan;
  if (!tools::parse_toml(read_text(run / "plan.toml"), (run / "plan.toml").string(), plan, err) ||
      plan.get_as<toml::array>("fault") == nullptr) {
    std::fprintf(stderr, "trn_campaign: shrink: %s\n", err.empty() ? "the plan has no [[fault]]" : err.c_str());
    return 2;
  }
  const std::string mission = mission_opt.empty() ? default_mission() : mission_opt;
  const fs::path world = world_opt.empty() ? campaign_dir / "world" : fs::path(world_opt);
  const std::size_t n_all = plan.get_as<toml::array>("fault")->size();
  std::uint32_t flights = 0U;
  bool broken = false;
  // Whether the faults @p c still end in the run's class (each candidate flown once, in its own folder).
  auto fails = [&](const std::vector<std::size_t>& c) {
    Job j;
    j.index = original.index;
    j.dir = run / "shrink" / ("try-" + std::to_string(flights++));
    std::error_code ec;
    fs::create_directories(j.dir, ec);
    std::string e;
    bool ok = write_atomic(j.dir / "plan.toml", plan_subset(plan, c), e);
    const cp::RunResult r = ok ? fly_one(mission, l.spec, j, world, golden, e, ok) : cp::RunResult{};
    if (!ok) {
      broken = true;
      err = e;
      return false;
    }
    if (!quiet) {
      std::fprintf(stderr, "trn_campaign: shrink: %zu faults -> %s\n", c.size(), cp::outcome_name(r.outcome));
    }
    return r.outcome == original.outcome;
  };
  std::vector<std::size_t> c(n_all);
  for (std::size_t i = 0; i < n_all; ++i) {
    c[i] = i;
  }
  std::size_t n = 2U;
  while (c.size() >= 2U && !broken) {
    const std::size_t chunk = (c.size() + n - 1U) / n;
    bool reduced = false;
    for (std::size_t start_i = 0; start_i < c.size() && !reduced && !broken; start_i += chunk) {
      const std::vector<std::size_t> part(c.begin() + static_cast<std::ptrdiff_t>(start_i),
                                          c.begin() + static_cast<std::ptrdiff_t>(std::min(c.size(), start_i + chunk)));
      if (fails(part)) {
        c = part;
        n = 2U;
        reduced = true;
        break;
      }
      if (n > 2U) {
        std::vector<std::size_t> rest;
        for (const std::size_t k : c) {
          if (std::find(part.begin(), part.end(), k) == part.end()) {
            rest.push_back(k);
          }
        }
        if (fails(rest)) {
          c = rest;
          n = std::max<std::size_t>(n - 1U, 2U);
          reduced = true;
        }
      }
    }
    if (!reduced) {
      if (n >= c.size()) {
        break;
      }
      n = std::min(c.size(), 2U * n);
    }
  }
  if (broken) {
    std::fprintf(stderr, "trn_campaign: shrink: %s\n", err.c_str());
    return 1;
  }
  std::string text = "# Shrunk from " + (run / "plan.toml").string() + " by trn_campaign shrink (ddmin): " +
                     std::to_string(c.size()) + " of " + std::to_string(n_all) + " faults still end " +
                     cp::outcome_name(original.outcome) + " (" + std::to_string(flights) + " flights)\n" +
                     plan_subset(plan, c);
  if (!write_atomic(run / "plan.min.toml", text, err)) {
    std::fprintf(stderr, "trn_campaign: shrink: %s\n", err.c_str());
    return 1;
  }
  std::printf("%zu of %zu faults still end %s (%u flights): %s\n", c.size(), n_all, cp::outcome_name(original.outcome),
              flights, (run / "plan.min.toml").string().c_str());
  return 0;
}

int cmd_merge(const std::string& out_dir, const std::vector<std::string>& inputs, bool quiet) {
  std::string spec_text;
  std::string stamp;
  std::map<std::uint32_t, cp::RunResult> by_index;
  for (const std::string& in : inputs) {
    const fs::path d(in);
    if (!fs::exists(d / "campaign.toml")) {
      std::fprintf(stderr, "trn_campaign: merge: %s is not a campaign folder (no campaign.toml)\n", in.c_str());
      return 2;
    }
    const std::string t = read_text(d / "campaign.toml");
    if (spec_text.empty()) {
      spec_text = t;
    } else if (t != spec_text) {
      std::fprintf(stderr, "trn_campaign: merge: %s holds another campaign than %s\n", in.c_str(), inputs[0].c_str());
      return 2;
    }
    const std::string st = fs::exists(d / "image.stamp") ? read_text(d / "image.stamp") : std::string("none");
    if (stamp.empty()) {
      stamp = st;
    } else if (st != stamp) {
      std::fprintf(stderr, "trn_campaign: merge: %s was flown by another build of the mission image than %s\n",
                   in.c_str(), inputs[0].c_str());
      return 2;
    }
    std::error_code ec;
    for (const fs::directory_entry& e : fs::directory_iterator(d / "runs", ec)) {
      cp::RunResult r;
      std::string why;
      const ReadResult got = read_result(e.path() / "result.json", r, why);
      if (got == ReadResult::kRefused) {
        std::fprintf(stderr, "trn_campaign: merge: %s\n", why.c_str());
        return 2;
      }
      if (got == ReadResult::kOk) {
        by_index.emplace(r.index, r);  // a run in two shards: the same plan, the first one read
      }
    }
  }
  if (spec_text.empty()) {
    std::fprintf(stderr, "trn_campaign: merge: no input folders\n");
    return 2;
  }
  const cp::SpecResult sr = cp::parse_spec(spec_text, inputs[0] + "/campaign.toml", 1000.0);
  if (!sr.ok()) {
    std::fprintf(stderr, "trn_campaign: merge: %s\n", sr.error.c_str());
    return 2;
  }
  std::vector<cp::RunResult> results;
  results.reserve(by_index.size());
  for (const auto& [i, r] : by_index) {
    results.push_back(r);
  }
  std::string err;
  const fs::path out(out_dir);
  std::error_code ec;
  fs::create_directories(out, ec);
  if (!write_atomic(out / "campaign.toml", spec_text, err) ||
      (stamp != "none" && !write_atomic(out / "image.stamp", stamp, err))) {
    std::fprintf(stderr, "trn_campaign: %s\n", err.c_str());
    return 1;
  }
  if (results.size() < sr.spec.runs) {
    std::fprintf(stderr, "trn_campaign: merge: %zu of %u runs have a result (the report covers those)\n",
                 results.size(), sr.spec.runs);
  }
  const cp::Report rep = cp::summarize(sr.spec.name, results);
  if (!cp::write_report(rep, out, err)) {
    std::fprintf(stderr, "trn_campaign: %s\n", err.c_str());
    return 1;
  }
  if (!quiet) {
    std::printf("%s", read_text(out / "report.md").c_str());
  }
  return 0;
}

int cmd_sbatch(const std::string& spec_path, const std::string& out_dir, std::uint32_t tasks, const std::string& mission) {
  Loaded l;
  std::string err;
  if (!load(spec_path, l, err)) {
    std::fprintf(stderr, "trn_campaign: %s\n", err.c_str());
    return 2;
  }
  std::error_code ec;
  const fs::path out = fs::absolute(out_dir, ec);
  fs::create_directories(out, ec);
  const fs::path spec_abs = fs::absolute(spec_path, ec);
  const fs::path self = fs::read_symlink("/proc/self/exe", ec);
  const std::string image = fs::absolute(mission.empty() ? default_mission() : mission, ec).string();
  std::ostringstream s;
  s << "#!/bin/bash\n"
    << "# Campaign " << l.spec.name << " as a Slurm job array: task i flies shard i/" << tasks
    << " into its own folder;\n# merge them after with: " << self.string() << " merge --out " << out.string()
    << "/merged " << out.string() << "/shard-*\n"
    << "#SBATCH --job-name=trn-campaign-" << l.spec.name << "\n"
    << "#SBATCH --array=0-" << (tasks - 1U) << "\n"
    << "#SBATCH --ntasks=1\n#SBATCH --cpus-per-task=1\n"
    << "#SBATCH --output=" << out.string() << "/slurm-%A_%a.out\n"
    << "set -euo pipefail\n"
    << "exec " << self.string() << " run " << spec_abs.string() << " --quiet -j 1 --shard \"${SLURM_ARRAY_TASK_ID}/" << tasks
    << "\" --out \"" << out.string() << "/shard-${SLURM_ARRAY_TASK_ID}\" --world-cache " << out.string()
    << "/world --mission " << image << "\n";
  if (!write_atomic(out / "campaign.sbatch", s.str(), err)) {
    std::fprintf(stderr, "trn_campaign: %s\n", err.c_str());
    return 1;
  }
  fs::permissions(out / "campaign.sbatch", fs::perms::owner_exec, fs::perm_options::add, ec);
  std::printf("%s\n", (out / "campaign.sbatch").string().c_str());
  return 0;
}

int run_main(int argc, char** argv) {
  CLI::App app{"trn_campaign: fault-injection campaigns over the mission image"};
  app.require_subcommand(1);
  RunOptions ro;
  CLI::App* run = app.add_subcommand("run", "Fly a campaign (or one shard of it) and write its report");
  run->add_option("spec", ro.spec, "Campaign spec (TOML, docs/CAMPAIGNS.md)")->required();
  run->add_option("--out", ro.out, "Campaign folder (default out/campaign-<name>); resumed if it holds this campaign");
  run->add_option("-j,--jobs", ro.jobs, "Runs in parallel (default: the host's cores)")->check(CLI::Range(1U, 256U));
  run->add_option("--shard", ro.shard, "Fly only runs i, i+N, i+2N, ... (i/N)");
  run->add_option("--mission", ro.mission, "The mission image (default: trn_mission beside this program)");
  run->add_option("--world-cache", ro.world, "Folder of built worlds shared by the runs (default <out>/world)");
  run->add_flag("--quiet", ro.quiet, "No progress bar and no report on stdout");
  std::string merge_out;
  std::vector<std::string> merge_in;
  bool merge_quiet = false;
  CLI::App* merge = app.add_subcommand("merge", "One report from campaign folders (shards) of the same spec");
  merge->add_option("--out", merge_out, "Folder of the merged report")->required();
  merge->add_option("folders", merge_in, "Campaign or shard folders")->required();
  merge->add_flag("--quiet", merge_quiet, "No report on stdout");
  std::string sb_spec;
  std::string sb_out;
  std::string sb_mission;
  std::uint32_t sb_tasks = 2U;
  CLI::App* sb = app.add_subcommand("sbatch", "Write a Slurm job-array script that flies the campaign in shards");
  sb->add_option("spec", sb_spec, "Campaign spec")->required();
  sb->add_option("--out", sb_out, "Campaign folder (shards go to shard-<i>)")->required();
  sb->add_option("--tasks", sb_tasks, "Array tasks (shards)")->check(CLI::Range(1U, 10000U));
  sb->add_option("--mission", sb_mission, "The mission image (default: trn_mission beside this program)");
  std::string sh_run;
  std::string sh_mission;
  std::string sh_world;
  bool sh_quiet = false;
  CLI::App* sh = app.add_subcommand("shrink", "Reduce a failing run's plan to a minimal one that fails the same way");
  sh->add_option("run", sh_run, "The run's folder (<campaign>/runs/<i>)")->required();
  sh->add_option("--mission", sh_mission, "The mission image (default: trn_mission beside this program)");
  sh->add_option("--world-cache", sh_world, "World cache folder (default <campaign>/world)");
  sh->add_flag("--quiet", sh_quiet, "No line per flight");
  double margin = 0.01;
  double confidence = 0.95;
  double expected = 0.5;
  std::uint64_t population = 0U;
  CLI::App* mg = app.add_subcommand("margin", "Runs a campaign needs for a margin of error (Leveugle et al., DATE 2009)");
  mg->add_option("--margin", margin, "Half-width of the interval, as a fraction (default 0.01)")->check(CLI::Range(1e-6, 0.5));
  mg->add_option("--confidence", confidence, "Confidence (default 0.95)")->check(CLI::Range(0.5, 0.999999));
  mg->add_option("--p", expected, "Expected fraction (default 0.5, the worst case)")->check(CLI::Range(0.0, 1.0));
  mg->add_option("--population", population, "Faults in the whole fault space (default: infinite)")
      ->check(tools::kWholeNumber);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int rc = app.exit(e);
    return rc == 0 ? 0 : 2;
  }
  if (mg->parsed()) {
    std::printf("%llu runs for a margin of %.4g %% at %.4g %% confidence (p = %.3g, population %s)\n",
                static_cast<unsigned long long>(cp::runs_for_margin(margin, confidence, expected, population)),
                margin * 100.0, confidence * 100.0, expected,
                population == 0U ? "infinite" : std::to_string(population).c_str());
    return 0;
  }
  if (run->parsed()) {
    return cmd_run(ro);
  }
  if (sh->parsed()) {
    return cmd_shrink(sh_run, sh_mission, sh_world, sh_quiet);
  }
  if (merge->parsed()) {
    return cmd_merge(merge_out, merge_in, merge_quiet);
  }
  return cmd_sbatch(sb_spec, sb_out, sb_tasks, sb_mission);
}

}  // namespace

int main(int argc, char** argv) {
  try {
    return run_main(argc, argv);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "trn_campaign: %s\n", e.what());
    return 1;
  }
}
