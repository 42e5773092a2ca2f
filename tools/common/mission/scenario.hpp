/**
 * @file scenario.hpp
 * @brief Scenario files (TOML): the world, the sensors and the initial estimate errors of one run.
 *
 * Every key is validated: an unknown section or key, a value of the wrong
 * type or out of its allowed range is an error whose message names the file,
 * the key and the allowed range. Keys left out keep their defaults (the
 * built-in default scenario, documented in docs/SCENARIO.md). Host code: the
 * image parses the scenario before boot and prints the error with exit status 2.
 */
#pragma once

#include "bsp_tile64/emu/devices/camera.hpp"
#include "bsp_tile64/emu/devices/imu.hpp"
#include "bsp_tile64/world/refmap.hpp"
#include "bsp_tile64/world/terrain.hpp"
#include "bsp_tile64/world/trajectory.hpp"

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace tools {

/** The vision side's load: how many landmarks the coordinator plans per frame. */
struct VisionLoad {
  std::uint32_t landmarks_per_frame = 150;  ///< trn::vision::FramePlanParams::max_landmarks of the coordinator
};

/** 1-sigma errors of the navigation filter's initial estimate (the run draws them from its seed). */
struct InitialErrors {
  double horizontal_m = 3000.0;  ///< magnitude of the horizontal error; its direction is drawn from the seed
  double position_m = 2000.0;  ///< per horizontal axis: the filter's initial 1-sigma
  double altitude_m = 100.0;   ///< vertical
  double velocity_mps = 2.0;   ///< per axis
  double attitude_deg = 0.5;   ///< per axis
};

/**
 * The map product's stated accuracy against the world (1 sigma): how far the
 * landmarks the matches lock on sit, as a body, from where the map puts them.
 * The defaults are what `make integrity` measured for the default map (6 m/px,
 * imaged under a sun at 250 / 50 deg against the descent's 135 / 35): the RMS
 * over seeds 1-100 of each descent's mean error after 5 s, the worse
 * horizontal axis (east, 0.34 m; north 0.18 m) for both, and 0.23 m vertical
 * (docs/FILTER.md, "Integrity"). Another map needs its own measurement.
 */
struct MapTie {
  double horizontal_m = 0.34;  ///< per horizontal axis
  double vertical_m = 0.23;
};

/**
 * A mission phase: from its start time on, the TRN supervisor's policies.
 * Reliability "high" runs the filter as TMR; power "save" switches off the
 * tiles the phase does not need (the idle filter replicas), woken before a
 * phase that needs them.
 */
struct MissionPhase {
  std::string name;
  double start_s = 0.0;          ///< mission time the phase begins, s (the first phase at 0)
  std::uint8_t reliability = 0;  ///< 0 normal, 1 high (fdir::kReliabilityNormal / kReliabilityHigh)
  std::uint8_t power = 0;        ///< 0 full, 1 save (fdir::kPowerFull / kPowerSave)
};

/** Phases a scenario may list (the flight's table is fixed). */
inline constexpr std::size_t kMaxScenarioPhases = 8;

/**
 * The built-in phases: approach (the coarse fix), trn (fine frames), terminal
 * (TMR from 30 s), all at power full: power save is a scenario's choice
 * (docs/SCENARIO.md says why).
 */
std::vector<MissionPhase> default_phases();

struct Scenario {
  std::string name = "default";
  std::string chip = "tile64";  ///< the chip flown (chip_known()): its profile and the roles' deployment on it
  std::uint64_t seed = 1;  ///< run seed: sensor noise and initial-error draws
  bsp::world::TerrainConfig terrain;
  bsp::world::MapConfig map;
  MapTie map_tie;  ///< the map's accuracy, given to the filter (FilterConfig::map_tie_sigma_m)
  bsp::world::TrajectoryConfig trajectory;
  bsp::ImuErrorConfig imu;
  bsp::CameraConfig camera;
  InitialErrors initial_error;
  VisionLoad vision;
  std::vector<MissionPhase> phases = default_phases();  ///< [[phase]] tables, in time order
};

/** A parsed scenario, or the message saying why there is none. */
struct ScenarioResult {
  std::optional<Scenario> scenario;
  std::string error;  ///< empty when scenario is set
  bool ok() const { return scenario.has_value(); }
};

/** Whether @p name is a chip with a profile (bsp_tile64/emu/profile.hpp) and a deployment (trn/tasks/tile_map.hpp). */
bool chip_known(const std::string& name);

/** The built-in default scenario (what an empty file gives). */
Scenario default_scenario();

/** Parses TOML text; @p source names it in messages (a path, or "<built-in>"). */
ScenarioResult parse_scenario(std::string_view text, const std::string& source);

/** Reads and parses a scenario file; a missing or unreadable file is an error naming it. */
ScenarioResult load_scenario(const std::string& path);

/** One documented key, for docs and --help: section, key, type, allowed range, default. */
struct ScenarioKeyDoc {
  std::string section;
  std::string key;
  std::string type;
  std::string range;
  std::string default_value;
  std::string meaning;
};

/** Every key the parser accepts, in file order. */
std::vector<ScenarioKeyDoc> scenario_keys();

}  // namespace tools
