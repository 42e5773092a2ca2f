/**
 * @file mission.hpp
 * @brief The mission's host side: the world and devices from a scenario, the chip booted from
 *        the tile map, the initial estimate drawn from the seed, and truth comparisons.
 *
 * Shared by the mission image and the integration tests, so both fly the same
 * system. One Mission per process (the board is one). build() may allocate;
 * nothing after boot() does, so the image seals the heap between boot() and
 * the flight. Truth is read here, on the host, to score the run: flight code
 * never sees it.
 */
#pragma once

#include "bsp_tile64/emu/devices/camera.hpp"
#include "bsp_tile64/emu/devices/imu.hpp"
#include "bsp_tile64/emu/profile.hpp"
#include "bsp_tile64/world/trajectory.hpp"
#include "tools/common/mission/scenario.hpp"
#include "tools/common/mission/world_cache.hpp"
#include "trn/filter/nav_state.hpp"
#include "trn/tasks/tile_map.hpp"
#include "trn/tasks/vision/vision_coord.hpp"

#include <Eigen/Core>

#include <cstdint>
#include <string>

namespace tools {

struct MissionSetup {
  Scenario scenario = default_scenario();
  double duration_s = 46.0;       ///< emulated seconds the devices deliver for
  std::uint64_t unpowered = 0;    ///< role tiles left switched off (bit t: tile t), e.g. removed vision tiles
  /**
   * Vision tiles the coordinator is given (1..40; 0: all 40), spread evenly
   * over the map's vision tiles; the others stay on, routing, with no work.
   */
  std::uint32_t vision_tiles = 0;
  /** Folder of world products kept between runs (tools/common/mission/world_cache.hpp); empty: built every run. */
  std::string world_cache;
  /** The coordinator's landmark selection (its own settings, trn::tasks::coord_select_params(), by default). */
  trn::vision::SelectParams select = trn::tasks::coord_select_params();
  /**
   * The map comes with the ground's landmark table, selected with `select`
   * (trn/tasks/vision/landmark_product.hpp): the coordinator takes it instead of
   * selecting on board. False: the map alone, selected on board.
   */
  bool ground_landmarks = true;
  /**
   * A second host thread renders each camera frame while the board runs the
   * second before it (bsp_tile64/emu/host/frame_ahead.hpp): the same frames and
   * trace, less host time. False: every frame rendered at its capture, on one host thread.
   */
  bool render_ahead = true;
  /**
   * The tile-health supervisor is given no spares (nor the I/O role's backup or the supervisor's
   * standby): a tile it gives up is not replaced and its role is not moved. For degradation studies.
   */
  bool no_spares = false;
};

/** The tiles excluded from the coordinator's list when it is given @p n of @p d's vision tiles (0: none). */
std::uint64_t vision_exclude_mask(const trn::tasks::Deployment& d, std::uint32_t n);

/** A chip a scenario names: its profile and the mission's deployment on it. */
struct Chip {
  const bsp::ChipProfile* profile = nullptr;
  const trn::tasks::Deployment* deployment = nullptr;
};

/** The chip named @p name (Scenario::chip); both null for a name with no profile or no deployment. */
Chip find_chip(const std::string& name);

/** The navigation solution against the truth at its time. */
struct NavSample {
  bool valid = false;           ///< false before the filter's first solution
  double t_s = 0.0;
  Eigen::Vector3d truth_p = Eigen::Vector3d::Zero();
  Eigen::Vector3d est_p = Eigen::Vector3d::Zero();
  Eigen::Vector3d truth_v = Eigen::Vector3d::Zero();
  Eigen::Vector3d est_v = Eigen::Vector3d::Zero();
  Eigen::Vector3d sigma3_p = Eigen::Vector3d::Zero();  ///< 3-sigma of the position per axis
  double position_error_m = 0.0;
  double velocity_error_mps = 0.0;
  double attitude_error_deg = 0.0;
  double altitude_m = 0.0;        ///< truth height above the datum
  std::uint32_t flags = 0;        ///< the solution's validity flags
};

class Mission {
 public:
  /** Builds terrain, map product, trajectory, IMU and camera from the scenario; draws the initial estimate. */
  bool build(const MissionSetup& setup, std::string& error);

  /** Initialises the board and network, registers the role tables, attaches the devices. */
  bool boot(std::string& error);

  /** The filter's latest solution against the truth. */
  [[nodiscard]] NavSample nav() const;

  /** Changes which role tiles stay off at the next boot() (the world is kept). */
  void set_unpowered(std::uint64_t mask) { setup_.unpowered = mask; }
  /** Changes the coordinator's landmark selection at the next boot(). */
  void set_select(const trn::vision::SelectParams& p) { setup_.select = p; }
  /** Whether the next boot() carves the ground's landmark table beside the map (MissionSetup::ground_landmarks). */
  void set_ground_landmarks(bool on) { setup_.ground_landmarks = on; }

  [[nodiscard]] const MissionSetup& setup() const { return setup_; }
  [[nodiscard]] const bsp::world::Trajectory& truth() const { return truth_; }
  [[nodiscard]] const bsp::CameraModel& camera_model() const { return camera_.model(); }
  [[nodiscard]] const trn::filter::InitialEstimate& initial_estimate() const { return initial_; }
  /** Tiles switched on at boot (bit t: tile t). */
  [[nodiscard]] std::uint64_t powered_mask() const { return powered_; }
  /** The chip of the scenario (set by build()). */
  [[nodiscard]] const bsp::ChipProfile& chip() const { return *chip_.profile; }
  /** The roles' deployment on it (set by build()). */
  [[nodiscard]] const trn::tasks::Deployment& deployment() const { return *chip_.deployment; }

 private:
  void draw_initial_estimate();
  /** The IMU and camera afresh, and the host thread that renders frames ahead (MissionSetup::render_ahead). */
  bool init_devices(std::string& error);

  MissionSetup setup_{};
  bsp::world::Trajectory truth_{};
  bsp::ImuModel imu_{};
  bsp::CameraDevice camera_{};
  trn::filter::InitialEstimate initial_{};
  std::uint64_t powered_ = 0;
  Chip chip_{&bsp::kTile64, &trn::tasks::kTile64Deployment};
  WorldCache world_{};
};

}  // namespace tools
