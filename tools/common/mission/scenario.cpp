/**
 * @file scenario.cpp
 * @brief Table-driven TOML scenario parser: one spec per key (type, range, meaning, field).
 */
#include "tools/common/mission/scenario.hpp"

#include "tools/common/text.hpp"
#include "tools/common/toml_input.hpp"
#include "bsp_tile64/emu/profile.hpp"
#include "trn/match.hpp"
#include "trn/tasks/tile_map.hpp"

#include <cerrno>
#include <cmath>
#include <cstring>
#include <fstream>
#include <functional>
#include <initializer_list>
#include <sstream>

namespace tools {
namespace {

enum class Kind { kFloat, kInt, kBool };

struct KeySpec {
  const char* section;
  const char* key;
  Kind kind;
  double lo;
  double hi;
  const char* meaning;
  std::function<void(Scenario&, double)> set;
  std::function<double(const Scenario&)> get;
};

constexpr double kMaxSeed = 9007199254740991.0;  // 2^53 - 1: exact in a double

/** A spec bound to a double field through an accessor. */
KeySpec f(const char* sec, const char* key, double lo, double hi, const char* meaning,
          double& (*ref)(Scenario&)) {
  return {sec,
          key,
          Kind::kFloat,
          lo,
          hi,
          meaning,
          [ref](Scenario& s, double v) { ref(s) = v; },
          [ref](const Scenario& s) { return ref(const_cast<Scenario&>(s)); }};  // NOLINT(cppcoreguidelines-pro-type-const-cast): read through the one accessor
}

template <class T>
KeySpec i(const char* sec, const char* key, double lo, double hi, const char* meaning, T& (*ref)(Scenario&)) {
  return {sec,
          key,
          Kind::kInt,
          lo,
          hi,
          meaning,
          [ref](Scenario& s, double v) { ref(s) = static_cast<T>(v); },
          [ref](const Scenario& s) { return static_cast<double>(ref(const_cast<Scenario&>(s))); }};  // NOLINT(cppcoreguidelines-pro-type-const-cast): read through the one accessor
}

KeySpec b(const char* sec, const char* key, const char* meaning, bool& (*ref)(Scenario&)) {
  return {sec,
          key,
          Kind::kBool,
          0.0,
          1.0,
          meaning,
          [ref](Scenario& s, double v) { ref(s) = v != 0.0; },
          [ref](const Scenario& s) { return ref(const_cast<Scenario&>(s)) ? 1.0 : 0.0; }};  // NOLINT(cppcoreguidelines-pro-type-const-cast): read through the one accessor
}

// clang-format off
const std::vector<KeySpec>& specs() {
  static const std::vector<KeySpec> kSpecs = {
    i<std::uint64_t>("scenario", "seed", 0, kMaxSeed, "run seed: sensor noise, initial-error draws", [](Scenario& s) -> std::uint64_t& { return s.seed; }),
    i<std::uint64_t>("terrain", "seed", 0, kMaxSeed, "world seed: relief, craters, boulders", [](Scenario& s) -> std::uint64_t& { return s.terrain.seed; }),
    i<std::uint32_t>("terrain", "size_px", 64, bsp::world::kMaxTerrainPx, "grid samples per side", [](Scenario& s) -> std::uint32_t& { return s.terrain.size_px; }),
    f("terrain", "m_per_px", 0.5, 50, "grid spacing, m", [](Scenario& s) -> double& { return s.terrain.m_per_px; }),
    f("terrain", "relief_m", 0, 1000, "amplitude of the largest relief octave, m", [](Scenario& s) -> double& { return s.terrain.relief_m; }),
    f("terrain", "base_wavelength_m", 10, 1e5, "wavelength of the largest octave, m", [](Scenario& s) -> double& { return s.terrain.base_wavelength_m; }),
    i<std::uint32_t>("terrain", "octaves", 1, 10, "relief octaves (each halves wavelength and amplitude)", [](Scenario& s) -> std::uint32_t& { return s.terrain.octaves; }),
    f("terrain", "crater_density_per_km2", 0, 1000, "craters of diameter >= crater_min_d_m per km^2", [](Scenario& s) -> double& { return s.terrain.crater_density_per_km2; }),
    f("terrain", "crater_min_d_m", 1, 10000, "smallest crater diameter, m", [](Scenario& s) -> double& { return s.terrain.crater_min_d_m; }),
    f("terrain", "crater_max_d_m", 1, 20000, "largest crater diameter, m (>= crater_min_d_m)", [](Scenario& s) -> double& { return s.terrain.crater_max_d_m; }),
    f("terrain", "crater_sfd_exponent", 1, 4, "b in the cumulative law N(>D) ~ D^-b", [](Scenario& s) -> double& { return s.terrain.crater_sfd_exponent; }),
    f("terrain", "boulder_density_per_km2", 0, 1000, "boulders per km^2", [](Scenario& s) -> double& { return s.terrain.boulder_density_per_km2; }),
    f("map", "fine_m_per_px", 1, 100, "fine map resolution, m/px", [](Scenario& s) -> double& { return s.map.fine_m_per_px; }),
    f("map", "coarse_m_per_px", 1, 200, "coarse map resolution, m/px (>= fine)", [](Scenario& s) -> double& { return s.map.coarse_m_per_px; }),
    f("map", "extent_m", 0, 2e5, "side of the mapped square, m; 0: the whole terrain", [](Scenario& s) -> double& { return s.map.extent_m; }),
    f("map", "sun_azimuth_deg", 0, 360, "orbital imaging sun, clockwise from north, deg", [](Scenario& s) -> double& { return s.map.sun.azimuth_deg; }),
    f("map", "sun_elevation_deg", 5, 90, "orbital imaging sun elevation, deg", [](Scenario& s) -> double& { return s.map.sun.elevation_deg; }),
    f("map", "tie_horizontal_m", 0, 1000, "the map's horizontal accuracy against the world, 1 sigma per axis, m", [](Scenario& s) -> double& { return s.map_tie.horizontal_m; }),
    f("map", "tie_vertical_m", 0, 1000, "the map's vertical accuracy against the world, 1 sigma, m", [](Scenario& s) -> double& { return s.map_tie.vertical_m; }),
    f("trajectory", "start_altitude_m", 500, 20000, "altitude above the datum at t = 0, m", [](Scenario& s) -> double& { return s.trajectory.start_altitude_m; }),
    f("trajectory", "end_altitude_m", 0, 20000, "altitude at the end of the descent, m (< start)", [](Scenario& s) -> double& { return s.trajectory.end_altitude_m; }),
    f("trajectory", "start_x_m", -1e5, 1e5, "east position at t = 0, m", [](Scenario& s) -> double& { return s.trajectory.start_x_m; }),
    f("trajectory", "start_y_m", -1e5, 1e5, "north position at t = 0, m", [](Scenario& s) -> double& { return s.trajectory.start_y_m; }),
    f("trajectory", "start_rate_mps", 1, 200, "descent rate at t = 0, m/s", [](Scenario& s) -> double& { return s.trajectory.start_rate_mps; }),
    f("trajectory", "end_rate_mps", 1, 200, "asymptotic descent rate, m/s", [](Scenario& s) -> double& { return s.trajectory.end_rate_mps; }),
    f("trajectory", "rate_tau_s", 1, 1000, "relaxation time of the descent rate, s", [](Scenario& s) -> double& { return s.trajectory.rate_tau_s; }),
    f("trajectory", "wind_east_mps", -50, 50, "horizontal drift east, m/s", [](Scenario& s) -> double& { return s.trajectory.wind_east_mps; }),
    f("trajectory", "wind_north_mps", -50, 50, "horizontal drift north, m/s", [](Scenario& s) -> double& { return s.trajectory.wind_north_mps; }),
    f("trajectory", "sway_mps", 0, 20, "amplitude of the horizontal sway, m/s", [](Scenario& s) -> double& { return s.trajectory.sway_mps; }),
    f("trajectory", "sway_period_s", 0.5, 100, "period of the sway, s", [](Scenario& s) -> double& { return s.trajectory.sway_period_s; }),
    f("trajectory", "oscillation_deg", 0, 30, "pitch and roll amplitude, deg", [](Scenario& s) -> double& { return s.trajectory.oscillation_deg; }),
    f("trajectory", "oscillation_period_s", 0.5, 100, "pitch period (roll 1.3x), s", [](Scenario& s) -> double& { return s.trajectory.oscillation_period_s; }),
    f("trajectory", "heading_deg", -360, 360, "initial heading from north, deg", [](Scenario& s) -> double& { return s.trajectory.heading_deg; }),
    f("trajectory", "spin_dps", -90, 90, "mean yaw rate, deg/s", [](Scenario& s) -> double& { return s.trajectory.spin_dps; }),
    b("imu", "enabled", "false: a perfect IMU", [](Scenario& s) -> bool& { return s.imu.enabled; }),
    f("imu", "gyro_bias_turn_on_dph", 0, 1000, "gyro turn-on bias, deg/h (1 sigma)", [](Scenario& s) -> double& { return s.imu.gyro_bias_turn_on_dph; }),
    f("imu", "gyro_bias_in_run_dph", 0, 1000, "gyro in-run bias (Gauss-Markov), deg/h", [](Scenario& s) -> double& { return s.imu.gyro_bias_in_run_dph; }),
    f("imu", "gyro_bias_tau_s", 1, 1e5, "gyro in-run bias correlation time, s", [](Scenario& s) -> double& { return s.imu.gyro_bias_tau_s; }),
    f("imu", "gyro_arw_dpsh", 0, 100, "angle random walk, deg/sqrt(h)", [](Scenario& s) -> double& { return s.imu.gyro_arw_dpsh; }),
    f("imu", "gyro_scale_ppm", 0, 1e5, "gyro scale-factor error, ppm", [](Scenario& s) -> double& { return s.imu.gyro_scale_ppm; }),
    f("imu", "accel_bias_turn_on_ug", 0, 1e5, "accelerometer turn-on bias, micro-g", [](Scenario& s) -> double& { return s.imu.accel_bias_turn_on_ug; }),
    f("imu", "accel_bias_in_run_ug", 0, 1e5, "accelerometer in-run bias (Gauss-Markov), micro-g", [](Scenario& s) -> double& { return s.imu.accel_bias_in_run_ug; }),
    f("imu", "accel_bias_tau_s", 1, 1e5, "accelerometer in-run bias correlation time, s", [](Scenario& s) -> double& { return s.imu.accel_bias_tau_s; }),
    f("imu", "accel_vrw_mpsph", 0, 100, "velocity random walk, m/s/sqrt(h)", [](Scenario& s) -> double& { return s.imu.accel_vrw_mpsph; }),
    f("imu", "accel_scale_ppm", 0, 1e5, "accelerometer scale-factor error, ppm", [](Scenario& s) -> double& { return s.imu.accel_scale_ppm; }),
    i<std::uint32_t>("camera", "width_px", 16, bsp::kMaxCameraPx, "image width, px", [](Scenario& s) -> std::uint32_t& { return s.camera.width_px; }),
    i<std::uint32_t>("camera", "height_px", 16, bsp::kMaxCameraPx, "image height, px", [](Scenario& s) -> std::uint32_t& { return s.camera.height_px; }),
    f("camera", "fov_deg", 10, 120, "horizontal field of view, deg", [](Scenario& s) -> double& { return s.camera.fov_deg; }),
    f("camera", "rate_hz", 1, 2, "frame rate, Hz", [](Scenario& s) -> double& { return s.camera.rate_hz; }),
    f("camera", "exposure_dn", 1, 10000, "DN for Lambert radiance 1.0", [](Scenario& s) -> double& { return s.camera.exposure_dn; }),
    f("camera", "read_noise_dn", 0, 50, "pixel noise, DN (1 sigma)", [](Scenario& s) -> double& { return s.camera.read_noise_dn; }),
    b("camera", "blur", "3x3 binomial blur of each frame", [](Scenario& s) -> bool& { return s.camera.blur; }),
    f("camera", "sun_azimuth_deg", 0, 360, "descent sun, clockwise from north, deg", [](Scenario& s) -> double& { return s.camera.sun.azimuth_deg; }),
    f("camera", "sun_elevation_deg", 5, 90, "descent sun elevation, deg", [](Scenario& s) -> double& { return s.camera.sun.elevation_deg; }),
    f("initial_error", "horizontal_m", 0, 6000, "horizontal position error, m (magnitude; direction drawn from the seed)", [](Scenario& s) -> double& { return s.initial_error.horizontal_m; }),
    f("initial_error", "position_m", 1, 10000, "filter's initial horizontal sigma per axis, m", [](Scenario& s) -> double& { return s.initial_error.position_m; }),
    f("initial_error", "altitude_m", 0, 2000, "altitude error, m (1 sigma)", [](Scenario& s) -> double& { return s.initial_error.altitude_m; }),
    f("initial_error", "velocity_mps", 0, 50, "velocity error per axis, m/s (1 sigma)", [](Scenario& s) -> double& { return s.initial_error.velocity_mps; }),
    f("initial_error", "attitude_deg", 0, 10, "attitude error per axis, deg (1 sigma)", [](Scenario& s) -> double& { return s.initial_error.attitude_deg; }),
    i<std::uint32_t>("vision", "landmarks_per_frame", 1, trn::kMaxMatchesPerFrame, "landmarks the coordinator plans per frame at most (the vision load)", [](Scenario& s) -> std::uint32_t& { return s.vision.landmarks_per_frame; }),
  };
  return kSpecs;
}
// clang-format on

const std::vector<std::string>& sections() {
  static const std::vector<std::string> kSections = {"scenario", "terrain", "map",          "trajectory",
                                                     "imu",      "camera",  "initial_error", "vision"};
  return kSections;
}


std::string fmt(double v) { return format_number(v); }

std::string kind_name(Kind k) {
  switch (k) {
    case Kind::kFloat:
      return "a number";
    case Kind::kInt:
      return "an integer";
    case Kind::kBool:
      return "true or false";
  }
  return "?";
}

/** The chips a scenario may name: each has a profile and a deployment. */
constexpr const char* kChipNames = "tile64, maestro";

}  // namespace

bool chip_known(const std::string& name) {
  return bsp::find_profile(name) != nullptr && trn::tasks::find_deployment(name.c_str()) != nullptr;
}

namespace {

std::string allowed_keys(const std::string& section) {
  std::string out;
  for (const KeySpec& s : specs()) {
    if (section == s.section) {
      out += (out.empty() ? "" : ", ") + std::string(s.key);
    }
  }
  return section == "scenario" ? "name, chip, " + out : out;
}

/** Reads one value per its spec; returns an error text (empty when set). */
std::string apply(const KeySpec& spec, const toml::node& node, Scenario& s) {
  double v = 0.0;
  if (spec.kind == Kind::kBool && node.is_boolean()) {
    v = node.as_boolean()->get() ? 1.0 : 0.0;
  } else if (spec.kind != Kind::kBool && node.is_integer()) {
    v = static_cast<double>(node.as_integer()->get());
  } else if (spec.kind == Kind::kFloat && node.is_floating_point()) {
    v = node.as_floating_point()->get();
  } else {
    return "wrong type: expected " + kind_name(spec.kind);
  }
  if (spec.kind != Kind::kBool && !(std::isfinite(v) && v >= spec.lo && v <= spec.hi)) {
    return fmt(v) + " is out of range: allowed " + fmt(spec.lo) + " .. " + fmt(spec.hi);
  }
  spec.set(s, v);
  return {};
}

void parse_section(const std::string& source, const std::string& section, const toml::table& t, Scenario& s,
                   std::vector<std::string>& errors) {
  for (const auto& [k, node] : t) {
    const std::string key(k.str());
    const std::string where = cat({source, ": [", section, "] ", key, ": "});
    if (section == "scenario" && key == "name") {
      if (!node.is_string()) {
        errors.push_back(where + "wrong type: expected a string");
      } else {
        s.name = node.as_string()->get();
      }
      continue;
    }
    if (section == "scenario" && key == "chip") {
      if (!node.is_string()) {
        errors.push_back(where + "wrong type: expected a string");
      } else if (!chip_known(node.as_string()->get())) {
        errors.push_back(cat({where, "\"", node.as_string()->get(), "\": no such chip (allowed: ", kChipNames, ")"}));
      } else {
        s.chip = node.as_string()->get();
      }
      continue;
    }
    const KeySpec* spec = nullptr;
    for (const KeySpec& c : specs()) {
      if (section == c.section && key == c.key) {
        spec = &c;
      }
    }
    if (spec == nullptr) {
      errors.push_back(cat({where, "unknown key (allowed in [", section, "]: ", allowed_keys(section), ")"}));
      continue;
    }
    const std::string e = apply(*spec, node, s);
    if (!e.empty()) {
      errors.push_back(where + e);
    }
  }
}

const char* const kReliabilityNames[] = {"normal", "high"};
const char* const kPowerNames[] = {"full", "save"};

/** A phase policy by name; returns false (with @p error) for a name not in @p names. */
bool policy_value(const toml::node& node, const char* const (&names)[2], std::uint8_t& out, std::string& error) {
  const auto* v = node.as_string();
  if (v != nullptr) {
    for (std::uint8_t k = 0; k < 2U; ++k) {
      if (v->get() == names[k]) {
        out = k;
        return true;
      }
    }
  }
  error = cat({"expected \"", names[0], "\" or \"", names[1], "\""});
  return false;
}

/** One key of a [[phase]] table; returns an error text (empty when set). */
std::string phase_key(const std::string& key, const toml::node& node, MissionPhase& ph) {
  std::string e;
  if (key == "name") {
    if (!node.is_string() || node.as_string()->get().empty()) {
      return "expected a non-empty string";
    }
    ph.name = node.as_string()->get();
  } else if (key == "start_s") {
    if (!node.is_number()) {
      return "wrong type: expected a number";
    }
    ph.start_s = node.is_integer() ? static_cast<double>(node.as_integer()->get()) : node.as_floating_point()->get();
    if (!(std::isfinite(ph.start_s) && ph.start_s >= 0.0 && ph.start_s <= 3600.0)) {
      return fmt(ph.start_s) + " is out of range: allowed 0 .. 3600";
    }
  } else if (key == "reliability") {
    (void)policy_value(node, kReliabilityNames, ph.reliability, e);
  } else if (key == "power") {
    (void)policy_value(node, kPowerNames, ph.power, e);
  } else {
    e = "unknown key (allowed in [[phase]]: name, start_s, reliability, power)";
  }
  return e;
}

/** [[phase]] tables: each key checked, names unique, the first at 0 s, starts increasing. */
void parse_phases(const std::string& source, const toml::node& node, Scenario& s, std::vector<std::string>& errors) {
  const toml::array* arr = node.as_array();
  if (arr == nullptr || !arr->is_array_of_tables() || arr->empty()) {
    errors.push_back(source + ": phase: must be one or more [[phase]] tables");
    return;
  }
  if (arr->size() > kMaxScenarioPhases) {
    errors.push_back(cat({source, ": [[phase]]: ", std::to_string(arr->size()), " phases, at most ",
                          std::to_string(kMaxScenarioPhases)}));
    return;
  }
  std::vector<MissionPhase> out;
  for (std::size_t n = 0; n < arr->size(); ++n) {
    const std::string where = cat({source, ": [[phase]] ", std::to_string(n + 1U), " "});
    MissionPhase ph{};
    bool named = false;
    for (const auto& [k, v] : *arr->get(n)->as_table()) {
      const std::string key(k.str());
      named = named || key == "name";
      const std::string e = phase_key(key, v, ph);
      if (!e.empty()) {
        errors.push_back(cat({where, key, ": ", e}));
      }
    }
    if (!named) {
      errors.push_back(where + ": missing key name");
    }
    for (const MissionPhase& o : out) {
      if (named && o.name == ph.name) {
        errors.push_back(cat({where, "name: \"", ph.name, "\" is used twice"}));
      }
    }
    if (n == 0U && ph.start_s != 0.0) {
      errors.push_back(where + "start_s: the first phase must start at 0");
    } else if (n > 0U && ph.start_s <= out.back().start_s) {
      errors.push_back(cat({where, "start_s: must be after the previous phase's (", fmt(out.back().start_s), ")"}));
    }
    out.push_back(ph);
  }
  s.phases = out;
}

/** Checks that involve more than one key. */
void cross_checks(const std::string& source, const Scenario& s, std::vector<std::string>& errors) {
  auto add = [&](const char* key, const std::string& msg) { errors.push_back(source + ": " + key + ": " + msg); };
  if (s.trajectory.end_altitude_m >= s.trajectory.start_altitude_m) {
    add("[trajectory] end_altitude_m", "must be below start_altitude_m (" + fmt(s.trajectory.start_altitude_m) + ")");
  }
  if (s.terrain.crater_max_d_m < s.terrain.crater_min_d_m) {
    add("[terrain] crater_max_d_m", "must be >= crater_min_d_m (" + fmt(s.terrain.crater_min_d_m) + ")");
  }
  if (s.map.coarse_m_per_px < s.map.fine_m_per_px) {
    add("[map] coarse_m_per_px", "must be >= fine_m_per_px (" + fmt(s.map.fine_m_per_px) + ")");
  }
  const double side = static_cast<double>(s.terrain.size_px - 1U) * s.terrain.m_per_px;
  if (s.map.extent_m > side) {
    add("[map] extent_m", "must be <= the terrain side (" + fmt(side) + " m = (size_px - 1) * m_per_px)");
  }
  const double extent = s.map.extent_m > 0.0 ? s.map.extent_m : side;
  if (extent < 4.0 * s.map.coarse_m_per_px) {
    add("[map] extent_m", "must cover at least 4 coarse pixels (" + fmt(4.0 * s.map.coarse_m_per_px) + " m)");
  }
}

}  // namespace

std::vector<MissionPhase> default_phases() {
  return {MissionPhase{"approach", 0.0, 0U, 0U}, MissionPhase{"trn", 3.0, 0U, 0U}, MissionPhase{"terminal", 30.0, 1U, 0U}};
}

Scenario default_scenario() { return Scenario{}; }

ScenarioResult parse_scenario(std::string_view text, const std::string& source) {
  ScenarioResult r;
  toml::table root;
  if (!parse_toml(text, source, root, r.error)) {
    return r;
  }
  Scenario s = default_scenario();
  std::vector<std::string> errors;
  for (const auto& [k, node] : root) {
    const std::string section(k.str());
    bool known = false;
    for (const std::string& c : sections()) {
      known = known || c == section;
    }
    if (section == "phase") {
      parse_phases(source, node, s, errors);
    } else if (!known) {
      errors.push_back(cat({source, ": [", section,
                            "]: unknown section (allowed: scenario, terrain, map, trajectory, imu, camera, initial_error, vision, phase)"}));
    } else if (!node.is_table()) {
      errors.push_back(cat({source, ": ", section, ": must be a table ([", section, "])"}));
    } else {
      parse_section(source, section, *node.as_table(), s, errors);
    }
  }
  if (errors.empty()) {
    cross_checks(source, s, errors);
  }
  if (!errors.empty()) {
    for (const std::string& e : errors) {
      r.error += (r.error.empty() ? "" : "\n") + e;
    }
    return r;
  }
  r.scenario = s;
  return r;
}

ScenarioResult load_scenario(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    ScenarioResult r;
    r.error = path + ": cannot open scenario file: " + std::strerror(errno);
    return r;
  }
  std::ostringstream text;
  text << in.rdbuf();
  return parse_scenario(text.str(), path);
}

std::vector<ScenarioKeyDoc> scenario_keys() {
  std::vector<ScenarioKeyDoc> out;
  const Scenario d = default_scenario();
  out.push_back({"scenario", "name", "string", "any", "\"" + d.name + "\"", "label of the run"});
  out.push_back({"scenario", "chip", "string", kChipNames, "\"" + d.chip + "\"",
                 "the chip flown, with its deployment of the roles (docs/ARCHITECTURE.md, \"The chips\")"});
  for (const KeySpec& s : specs()) {
    const std::string type = s.kind == Kind::kFloat ? "float" : s.kind == Kind::kInt ? "integer" : "bool";
    const std::string range = s.kind == Kind::kBool ? "true/false" : fmt(s.lo) + " .. " + fmt(s.hi);
    const std::string def = s.kind == Kind::kBool ? (s.get(d) != 0.0 ? "true" : "false") : fmt(s.get(d));
    out.push_back({s.section, s.key, type, range, def, s.meaning});
  }
  return out;
}

}  // namespace tools
