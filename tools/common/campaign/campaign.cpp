/**
 * @file campaign.cpp
 * @brief Campaign specs, the plans of the runs drawn from (seed, index), and outcome classes.
 */
#include "tools/common/campaign/campaign.hpp"

#include "tools/common/mission/fault_plan.hpp"
#include "tools/common/mission/scenario.hpp"
#include "tools/common/text.hpp"
#include "tools/common/toml_input.hpp"
#include "trn/tasks/sdc_points.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <optional>
#include <sstream>

namespace tools::campaign {

namespace {

constexpr std::uint32_t kMaxRuns = 10'000'000U;
constexpr std::uint32_t kMaxFaultsPerRun = 32U;
constexpr std::uint32_t kDrawAttempts = 64U;
constexpr std::uint32_t kReplicaInstances = 3U;
constexpr std::uint32_t kMaxPacketWord = 129U;
constexpr std::uint32_t kMaxSdcBit = 65535U;

constexpr std::array<std::string_view, 20> kKeys = {
    "name",  "scenario", "chip", "seed",  "seed_per_run", "campaign_seed", "runs",      "faults_per_run", "duration_s",
    "window_s", "same_time", "kinds", "roles", "tiles",  "points",        "carves",    "pass_bound_m",
    "degraded_bound_m", "timeout_s", "command"};


std::string list_of(std::span<const std::string_view> names) {
  std::string out;
  for (const std::string_view n : names) {
    out += (out.empty() ? "" : ", ") + std::string(n);
  }
  return out;
}

std::string kind_names() {
  std::string out;
  for (std::size_t i = 0; i < kFaultKinds; ++i) {
    out += (out.empty() ? "" : ", ") + fault_kind_name(static_cast<bsp::FaultKind>(i));
  }
  return out;
}

/** Reads an array of strings; each passes @p check (an error text, empty when valid). */
template <typename Check>
std::string read_names(const toml::node& node, std::vector<std::string>& out, Check check) {
  const toml::array* a = node.as_array();
  if (a == nullptr) {
    return "wrong type: expected an array of strings";
  }
  for (std::size_t i = 0; i < a->size(); ++i) {
    const toml::node& e = *a->get(i);
    if (!e.is_string()) {
      return "element " + std::to_string(i) + ": wrong type: expected a string";
    }
    const std::string v = e.as_string()->get();
    std::string err = check(v);
    if (!err.empty()) {
      return "element " + std::to_string(i) + ": " + err;
    }
    out.push_back(v);
  }
  return {};
}

struct Reader {
  const toml::table& t;
  const std::string& source;
  std::vector<std::string>& errors;

  const toml::node* get(std::string_view key) const { return t.get(key); }

  void fail(std::string_view key, const std::string& e) const {
    if (!e.empty()) {
      errors.push_back(cat({source, ": ", key, ": ", e}));
    }
  }

  void integer(std::string_view key, std::int64_t lo, std::int64_t hi, auto& out) const {
    if (const toml::node* n = get(key)) {
      std::int64_t v = 0;
      const std::string e = read_int(*n, lo, hi, v);
      fail(key, e);
      if (e.empty()) {
        out = static_cast<std::remove_reference_t<decltype(out)>>(v);
      }
    }
  }

  /** A string; @p check gives an error text for a bad value (empty: accepted). */
  template <typename Check>
  void text(std::string_view key, const char* expected, Check check, std::string& out) const {
    if (const toml::node* n = get(key)) {
      if (!n->is_string()) {
        fail(key, std::string("wrong type: expected ") + expected);
        return;
      }
      const std::string e = check(n->as_string()->get());
      fail(key, e);
      if (e.empty()) {
        out = n->as_string()->get();
      }
    }
  }

  void number(std::string_view key, double lo, double hi, const char* unit, double& out) const {
    if (const toml::node* n = get(key)) {
      fail(key, read_float(*n, lo, hi, unit, out));
    }
  }
};

void read_commands(const toml::node& node, const std::string& source, std::vector<SpecCommand>& out,
                   std::vector<std::string>& errors) {
  const toml::array* a = node.as_array();
  if (a == nullptr || !a->is_array_of_tables()) {
    errors.push_back(source + ": command: wrong type: expected [[command]] tables");
    return;
  }
  for (std::size_t i = 0; i < a->size(); ++i) {
    const toml::table& c = *a->get(i)->as_table();
    const std::string where = source + ": [[command]] #" + std::to_string(i + 1U);
    SpecCommand cmd{};
    for (const auto& [k, v] : c) {
      if (k.str() == "t_s") {
        const std::string e = read_float(v, 0.0, 1000.0, " s", cmd.t_s);
        if (!e.empty()) {
          errors.push_back(cat({where, " t_s: ", e}));
        }
      } else if (k.str() == "name") {
        if (!v.is_string()) {
          errors.push_back(where + " name: wrong type: expected a string");
        } else {
          cmd.name = v.as_string()->get();
        }
      } else {
        errors.push_back(cat({where, ": unknown key ", k.str(), " (allowed: t_s, name)"}));
      }
    }
    if (cmd.name.empty()) {
      errors.push_back(where + ": missing key name");
    }
    out.push_back(cmd);
  }
}

/** A number in [0, 1) from the top 53 bits. */
double unit(std::uint64_t x) { return static_cast<double>(x >> 11U) * 0x1.0p-53; }

/**
 * Integer in [0, n) from a 64-bit draw: the remainder, the same on every compiler (std
 * distributions are not); its bias, under n / 2^64, is nothing for the small n drawn here.
 */
std::uint64_t below(std::uint64_t x, std::uint64_t n) { return x % n; }

/** splitmix64 as a stream: the same numbers from the same seed on every host. */
struct Stream {
  std::uint64_t s;
  std::uint64_t next() {
    std::uint64_t z = (s += 0x9E37'79B9'7F4A'7C15ULL);
    z = (z ^ (z >> 30U)) * 0xBF58'476D'1CE4'E5B9ULL;
    z = (z ^ (z >> 27U)) * 0x94D0'49BB'1331'11EBULL;
    return z ^ (z >> 31U);
  }
  std::uint64_t below(std::uint64_t n) { return campaign::below(next(), n); }
  double between(double lo, double hi) { return lo + (hi - lo) * unit(next()); }
};

constexpr std::array<const char*, 4> kDirections = {"east", "west", "north", "south"};

/**
 * One drawn [[fault]] entry as plan text; its kind and its target's role ("tile_<n>" for a tile) are
 * returned too. At @p at_s when it is not negative (same_time), else at a time drawn in the window.
 */
std::string draw_fault(const Spec& spec, Stream& r, std::string& kind_out, std::string& role_out, double at_s) {
  const bsp::FaultKind kind = spec.kinds[r.below(spec.kinds.size())];
  kind_out = fault_kind_name(kind);
  const std::size_t targets = spec.roles.size() + spec.tiles.size();
  const std::size_t ti = r.below(targets);
  std::ostringstream o;
  o.precision(17);
  // Rounded to the microsecond: the time the plan says is the time flown.
  const double t = at_s >= 0.0 ? at_s : std::round(r.between(spec.window_lo_s, spec.window_hi_s) * 1e6) / 1e6;
  o << "\n[[fault]]\nt_s = " << format_number(t) << "\nkind = \"" << kind_out << "\"\n";
  if (ti < spec.roles.size()) {
    const std::string& role = spec.roles[ti];
    role_out = role;
    o << "role = \"" << role << "\"\n";
    if (role == "vision") {
      o << "instance = " << r.below(trn::tasks::count_role(spec_deployment(spec), trn::tasks::Role::kVision)) << "\n";
    } else if (role == "filter_replica") {
      o << "instance = " << r.below(kReplicaInstances) << "\n";
    }
  } else {
    role_out = "tile_" + std::to_string(spec.tiles[ti - spec.roles.size()]);
    o << "tile = " << spec.tiles[ti - spec.roles.size()] << "\n";
  }
  switch (kind) {
    case bsp::FaultKind::kSdc:
      if (!spec.points.empty()) {
        o << "point = \"" << spec.points[r.below(spec.points.size())] << "\"\n";
      }
      o << "bit = " << r.below(kMaxSdcBit + 1U) << "\n";
      break;
    case bsp::FaultKind::kSeu:
      if (!spec.carves.empty()) {
        o << "carve = \"" << spec.carves[r.below(spec.carves.size())] << "\"\n";
      }
      // Where the byte is, drawn here: the injector's own stream, seeded by the board, would pick the
      // same first byte in every run of the seed (121 single upsets on one byte, before).
      o << "position = " << format_number(r.between(0.0, 1.0)) << "\n";
      o << "bit = " << r.below(8U) << "\n";
      break;
    case bsp::FaultKind::kPacketBitFlip:
      o << "word = " << r.below(kMaxPacketWord + 1U) << "\nbit = " << r.below(32U) << "\n";
      break;
    case bsp::FaultKind::kLinkFail:
      o << "direction = \"" << kDirections[r.below(kDirections.size())] << "\"\n";
      break;
    default:
      break;
  }
  return o.str();
}

}  // namespace

std::uint64_t scenario_seed(const Spec& spec, std::uint32_t index) {
  return spec.seed_per_run ? spec.seed + index : spec.seed;
}

std::uint64_t run_seed(std::uint64_t campaign_seed, std::uint32_t index) {
  Stream s{campaign_seed ^ (0xD1B5'4A32'D192'ED03ULL * (static_cast<std::uint64_t>(index) + 1U))};
  return s.next();
}

bool parse_shard(std::string_view text, std::uint32_t& i, std::uint32_t& n) {
  const std::size_t slash = text.find('/');
  if (slash == std::string_view::npos || slash == 0U || slash + 1U >= text.size()) {
    return false;
  }
  auto num = [](std::string_view s, std::uint32_t& out) {
    if (s.empty() || s.size() > 6U || !std::all_of(s.begin(), s.end(), [](char c) { return c >= '0' && c <= '9'; })) {
      return false;
    }
    out = static_cast<std::uint32_t>(std::stoul(std::string(s)));
    return true;
  };
  std::uint32_t a = 0U;
  std::uint32_t b = 0U;
  if (!num(text.substr(0, slash), a) || !num(text.substr(slash + 1U), b) || b == 0U || a >= b) {
    return false;
  }
  i = a;
  n = b;
  return true;
}

SpecResult parse_spec(std::string_view text, const std::string& source, double max_duration_s) {
  SpecResult res;
  toml::table root;
  if (!parse_toml(text, source, root, res.error)) {
    return res;
  }
  std::vector<std::string> errors;
  for (const auto& [k, v] : root) {
    if (std::find(kKeys.begin(), kKeys.end(), k.str()) == kKeys.end()) {
      errors.push_back(cat({source, ": unknown key ", k.str(), " (allowed: ", list_of(kKeys), ")"}));
    }
  }
  Spec& s = res.spec;
  const Reader rd{root, source, errors};
  if (const toml::node* n = root.get("name")) {
    if (!n->is_string() || n->as_string()->get().empty()) {
      rd.fail("name", "wrong type: expected a non-empty string");
    } else {
      s.name = n->as_string()->get();
    }
  } else {
    errors.push_back(source + ": missing key name");
  }
  rd.text("scenario", "a path (string)", [](const std::string&) { return std::string{}; }, s.scenario);
  rd.text("chip", "a string (tile64 or maestro)", [](const std::string& c) {
    return chip_known(c) ? std::string{} : "\"" + c + "\": no such chip (allowed: tile64, maestro)";
  }, s.chip);
  rd.integer("seed", 0, INT64_MAX, s.seed);
  if (const toml::node* n = root.get("seed_per_run")) {
    if (!n->is_boolean()) {
      rd.fail("seed_per_run", "wrong type: expected true or false");
    } else {
      s.seed_per_run = n->as_boolean()->get();
    }
  }
  if (const toml::node* n = root.get("same_time")) {
    if (!n->is_boolean()) {
      rd.fail("same_time", "wrong type: expected true or false");
    } else {
      s.same_time = n->as_boolean()->get();
    }
  }
  rd.integer("campaign_seed", 0, INT64_MAX, s.campaign_seed);
  if (root.get("runs") == nullptr) {
    errors.push_back(source + ": missing key runs (1 .. " + std::to_string(kMaxRuns) + ")");
  }
  rd.integer("runs", 1, kMaxRuns, s.runs);
  rd.integer("faults_per_run", 0, kMaxFaultsPerRun, s.faults_per_run);
  if (s.seed_per_run && s.seed > static_cast<std::uint64_t>(INT64_MAX) - s.runs) {
    rd.fail("seed", "with seed_per_run the last run's seed (seed + runs - 1) must stay within 0 .. 2^63 - 1");
  }
  rd.number("duration_s", 1.0, 1000.0, " s", s.duration_s);
  rd.number("pass_bound_m", 0.001, 1e6, " m", s.pass_bound_m);
  rd.number("degraded_bound_m", 0.001, 1e6, " m", s.degraded_bound_m);
  rd.number("timeout_s", 1.0, 86400.0, " s", s.timeout_s);
  const double run_s = s.duration_s > 0.0 ? s.duration_s : max_duration_s;
  s.window_lo_s = 0.0;
  s.window_hi_s = run_s;
  if (const toml::node* n = root.get("window_s")) {
    const toml::array* a = n->as_array();
    if (a == nullptr || a->size() != 2U) {
      rd.fail("window_s", "wrong type: expected [start, end] in seconds");
    } else {
      std::string e = read_float(*a->get(0), 0.0, run_s, " s (the run's duration)", s.window_lo_s);
      if (e.empty()) {
        e = read_float(*a->get(1), 0.0, run_s, " s (the run's duration)", s.window_hi_s);
      }
      if (e.empty() && s.window_hi_s <= s.window_lo_s) {
        e = "the end must come after the start";
      }
      rd.fail("window_s", e);
    }
  }
  if (const toml::node* n = root.get("kinds")) {
    std::vector<std::string> names;
    rd.fail("kinds", read_names(*n, names, [](const std::string& v) {
              return fault_kind_from_name(v) ? std::string{} : "unknown fault kind \"" + v + "\" (allowed: " + kind_names() + ")";
            }));
    for (const std::string& k : names) {
      s.kinds.push_back(*fault_kind_from_name(k));
    }
    if (names.empty() && errors.empty() && s.faults_per_run > 0U) {
      rd.fail("kinds", "empty: name at least one fault kind");
    }
  } else if (s.faults_per_run > 0U) {
    errors.push_back(source + ": missing key kinds (allowed: " + kind_names() + ")");
  }
  if (const toml::node* n = root.get("roles")) {
    // The roles a campaign can aim at: those a fault plan names.
    const std::vector<std::string> roles = fault_plan_role_names();
    rd.fail("roles", read_names(*n, s.roles, [&roles](const std::string& v) {
              std::string all;
              for (const std::string& r : roles) {
                all += (all.empty() ? "" : ", ") + r;
              }
              return std::find(roles.begin(), roles.end(), v) != roles.end()
                         ? std::string{}
                         : "unknown role \"" + v + "\" (allowed: " + all + ")";
            }));
  }
  if (const toml::node* n = root.get("tiles")) {
    const toml::array* a = n->as_array();
    if (a == nullptr) {
      rd.fail("tiles", "wrong type: expected an array of tile numbers");
    } else {
      for (std::size_t i = 0; i < a->size(); ++i) {
        std::int64_t v = 0;
        const std::string e = read_int(*a->get(i), 0, 63, v);
        rd.fail("tiles", e.empty() ? e : "element " + std::to_string(i) + ": " + e);
        s.tiles.push_back(static_cast<std::uint32_t>(v));
      }
    }
  }
  if (const toml::node* n = root.get("points")) {
    rd.fail("points", read_names(*n, s.points, [](const std::string& v) {
              const bool known = std::any_of(trn::tasks::kSdcPoints.begin(), trn::tasks::kSdcPoints.end(),
                                             [&v](const trn::tasks::SdcPoint& p) { return v == p.name; });
              return known ? std::string{} : "unknown point \"" + v + "\" (docs/FAULT_PLANS.md, the points of an sdc)";
            }));
  }
  if (const toml::node* n = root.get("carves")) {
    rd.fail("carves", read_names(*n, s.carves, [](const std::string& v) {
              return !v.empty() && v.size() <= 23U ? std::string{} : "a carve name is 1 .. 23 characters";
            }));
  }
  if (s.faults_per_run == 0U) {
    // A fault-free campaign: a key that only shapes the draws would be silently ignored, so it is refused.
    for (const std::string_view k :
         {"kinds", "roles", "tiles", "points", "carves", "window_s", "same_time", "campaign_seed"}) {
      if (root.get(k) != nullptr) {
        rd.fail(k, "faults_per_run is 0: no fault is drawn, so this key has no meaning");
      }
    }
  } else if (s.roles.empty() && s.tiles.empty()) {
    errors.push_back(source + ": no target: give roles, tiles or both");
  }
  if (s.degraded_bound_m < s.pass_bound_m) {
    errors.push_back(source + ": degraded_bound_m (" + format_number(s.degraded_bound_m) +
                     " m) is below pass_bound_m (" + format_number(s.pass_bound_m) + " m)");
  }
  if (const toml::node* n = root.get("command")) {
    read_commands(*n, source, s.commands, errors);
  }
  for (const std::string& e : errors) {
    res.error += (res.error.empty() ? "" : "\n") + e;
  }
  return res;
}

SpecResult load_spec(const std::string& path, double max_duration_s) {
  std::ifstream in(path);
  if (!in) {
    SpecResult r;
    r.error = path + ": cannot read the campaign spec";
    return r;
  }
  std::ostringstream text;
  text << in.rdbuf();
  SpecResult r = parse_spec(text.str(), path, max_duration_s);
  if (r.ok() && !r.spec.scenario.empty()) {
    const std::filesystem::path sc(r.spec.scenario);
    if (sc.is_relative()) {
      r.spec.scenario = (std::filesystem::path(path).parent_path() / sc).lexically_normal().string();
    }
    if (!std::filesystem::exists(r.spec.scenario)) {
      r.error = path + ": scenario: no such file " + r.spec.scenario;
    }
  }
  if (r.ok() && r.spec.chip.empty()) {
    // The runs fly the scenario's chip: the plans are drawn for its deployment.
    if (r.spec.scenario.empty()) {
      r.spec.chip = default_scenario().chip;
    } else {
      const ScenarioResult sc = load_scenario(r.spec.scenario);
      if (!sc.ok()) {
        r.error = path + ": scenario: " + sc.error;
      } else {
        r.spec.chip = sc.scenario->chip;
      }
    }
  }
  return r;
}

const trn::tasks::Deployment& spec_deployment(const Spec& spec) {
  const trn::tasks::Deployment* d = trn::tasks::find_deployment(spec.chip.empty() ? "tile64" : spec.chip.c_str());
  return d != nullptr ? *d : trn::tasks::kTile64Deployment;
}

DrawnPlan draw_plan(const Spec& spec, std::uint32_t index, std::uint32_t tile_count, double run_s) {
  DrawnPlan d;
  Stream r{run_seed(spec.campaign_seed, index)};
  std::string last_error;
  for (std::uint32_t attempt = 0; attempt < kDrawAttempts; ++attempt) {
    std::ostringstream o;
    o << "# Run " << index << " of campaign " << spec.name << " (campaign_seed " << spec.campaign_seed
      << "), drawn by trn_campaign; fly it again with\n# trn_mission --faults <this file> --seed " << scenario_seed(spec, index)
      << (spec.duration_s > 0.0 ? " --duration " + format_number(spec.duration_s) : std::string{})
      << (spec.scenario.empty() ? std::string{} : " --scenario " + spec.scenario)
      << (spec.chip.empty() || spec.chip == "tile64" ? std::string{} : " --chip " + spec.chip) << "\nname = \"" << spec.name
      << "-" << index << "\"\n";
    for (const SpecCommand& c : spec.commands) {
      o << "\n[[command]]\nt_s = " << format_number(c.t_s) << "\nname = \"" << c.name << "\"\n";
    }
    std::string kind = spec.faults_per_run == 0U ? std::string("none") : std::string{};
    std::string role = kind;
    // Rounded to the microsecond, as a drawn time is; drawn only when the spec asks for it, so the other
    // campaigns draw the plans they always did.
    const double at_s =
        spec.same_time ? std::round(r.between(spec.window_lo_s, spec.window_hi_s) * 1e6) / 1e6 : -1.0;
    for (std::uint32_t f = 0; f < spec.faults_per_run; ++f) {
      std::string k;
      std::string t;
      o << draw_fault(spec, r, k, t, at_s);
      kind = f == 0U ? k : (k == kind ? kind : std::string("mixed"));
      role = f == 0U ? t : (t == role ? role : std::string("mixed"));
    }
    const std::string text = o.str();
    const FaultPlanResult check =
        parse_fault_plan(text, "run " + std::to_string(index), tile_count, run_s, spec_deployment(spec));
    if (check.ok()) {
      d.toml = text;
      d.kind = kind;
      d.role = role;
      return d;
    }
    last_error = check.error;
  }
  d.error = "run " + std::to_string(index) + ": no valid plan in " + std::to_string(kDrawAttempts) +
            " draws; the last: " + last_error;
  return d;
}

Outcome classify(const RunFacts& f, double pass_bound_m, double degraded_bound_m) {
  if (!f.exited_ok) {
    return Outcome::kCrash;
  }
  if (f.injected == 0U && f.not_delivered > 0U) {
    return Outcome::kNotDelivered;  // the image flew, but no fault reached the chip: nothing was tested
  }
  const bool correct = !f.mission_lost && f.final_error_m <= pass_bound_m;
  const bool kept = !f.mission_lost && f.final_error_m <= degraded_bound_m;
  if (f.detected == 0U) {
    if (f.output_as_golden) {
      return Outcome::kNoEffect;
    }
    return correct ? Outcome::kMasked : Outcome::kSdc;
  }
  if (!kept) {
    return Outcome::kLost;
  }
  const bool whole = f.recovered == f.detected && f.degraded_accepted == 0U;
  return correct && whole ? Outcome::kRecovered : Outcome::kDegraded;
}

}  // namespace tools::campaign
