/**
 * @file mission.cpp
 * @brief World, devices, boot from the tile map, initial estimate, truth comparisons.
 */
#include "tools/common/mission/mission.hpp"

#include "bsp_tile64/emu/board.hpp"
#include "bsp_tile64/emu/devices/device_bus.hpp"
#include "bsp_tile64/emu/host/frame_ahead.hpp"
#include "bsp_tile64/api/memory.hpp"
#include "bsp_tile64/emu/rng.hpp"
#include "bsp_tile64/emu/udn_net.hpp"
#include "bsp_tile64/world/refmap.hpp"
#include "bsp_tile64/world/terrain.hpp"
#include "fdir/event_log.hpp"
#include "fdir/ft_sink.hpp"
#include "fdir/transit.hpp"
#include "kernel/kernel.hpp"
#include "tools/common/mission/ram_record.hpp"
#include "trn/tasks/filter/filter_task.hpp"
#include "trn/tasks/vision/landmark_product.hpp"
#include "trn/tasks/tile_map.hpp"
#include "trn/vision/frame.hpp"

#include <Eigen/Geometry>

#include <array>

#include <cmath>
#include <memory>
#include <numbers>

namespace tools {

Chip find_chip(const std::string& name) {
  Chip c{bsp::find_profile(name), trn::tasks::find_deployment(name.c_str())};
  if (c.profile == nullptr || c.deployment == nullptr) {
    return Chip{};
  }
  return c;
}

std::uint64_t vision_exclude_mask(const trn::tasks::Deployment& d, std::uint32_t n) {
  std::array<std::uint32_t, trn::tasks::kMapTiles> vision{};
  std::uint32_t count = 0;
  for (std::uint32_t t = 0; t < d.tiles(); ++t) {
    if (trn::tasks::tile_role(d, t) == trn::tasks::Role::kVision) {
      vision[count++] = t;
    }
  }
  if (n == 0U || n >= count) {
    return 0U;
  }
  // Tile i * count / n for i < n: spread over the map, not a corner of it.
  std::uint64_t keep = 0;
  for (std::uint32_t i = 0; i < n; ++i) {
    keep |= 1ULL << vision[(static_cast<std::uint64_t>(i) * count) / n];
  }
  std::uint64_t all = 0;
  for (std::uint32_t i = 0; i < count; ++i) {
    all |= 1ULL << vision[i];
  }
  return all & ~keep;
}
namespace {

/** Stream index of the initial-estimate draws within StreamId::kSensor (IMU 1, camera 2). */
constexpr std::uint64_t kInitialStreamIndex = 7;

double gaussian(bsp::Rng& rng) {
  // Box-Muller; u1 in (0, 1] so the logarithm is finite.
  const double u1 = 1.0 - rng.uniform();
  const double u2 = rng.uniform();
  return std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * std::numbers::pi * u2);
}

/** The datasheet the filter is configured with: the IMU's specified error figures. */
trn::filter::ImuSpec imu_spec(const bsp::ImuErrorConfig& c) {
  using trn::filter::kMicroG;
  using trn::filter::kRadPerDeg;
  using trn::filter::kSecPerHour;
  trn::filter::ImuSpec s;
  s.gyro_arw_rad_sqrts = c.gyro_arw_dpsh * kRadPerDeg / 60.0;
  s.gyro_bias_on_rads = c.gyro_bias_turn_on_dph * kRadPerDeg / kSecPerHour;
  s.gyro_bias_run_rads = c.gyro_bias_in_run_dph * kRadPerDeg / kSecPerHour;
  s.gyro_bias_tau_s = c.gyro_bias_tau_s;
  s.accel_vrw_mps_sqrts = c.accel_vrw_mpsph / 60.0;
  s.accel_bias_on_mps2 = c.accel_bias_turn_on_ug * kMicroG;
  s.accel_bias_run_mps2 = c.accel_bias_in_run_ug * kMicroG;
  s.accel_bias_tau_s = c.accel_bias_tau_s;
  return s;
}

/**
 * sigma times three standard normal draws, drawn one statement at a time. The order of a call's
 * arguments is unspecified (GCC evaluates them right to left, Clang left to right), so three draws
 * inside one constructor call gave each compiler's image another initial error. The order kept is
 * z, y, x: the one GCC's images always used, so every run made before keeps its bits.
 */
Eigen::Vector3d gaussian3(bsp::Rng& rng, double sigma) {
  const double z = gaussian(rng);
  const double y = gaussian(rng);
  const double x = gaussian(rng);
  return Eigen::Vector3d(sigma * x, sigma * y, sigma * z);
}

}  // namespace

void Mission::draw_initial_estimate() {
  const InitialErrors& e = setup_.scenario.initial_error;
  bsp::Rng rng{setup_.scenario.seed, bsp::StreamId::kSensor, kInitialStreamIndex};
  const bsp::world::TruthState t0 = truth_.at(0.0);
  const double heading = rng.uniform(0.0, 2.0 * std::numbers::pi);
  const Eigen::Vector3d dp(e.horizontal_m * std::cos(heading), e.horizontal_m * std::sin(heading),
                           e.altitude_m * gaussian(rng));
  const Eigen::Vector3d dv = gaussian3(rng, e.velocity_mps);
  const double att_rad = e.attitude_deg * std::numbers::pi / 180.0;
  const Eigen::Vector3d dth = gaussian3(rng, att_rad);
  const double angle = dth.norm();
  const Eigen::Quaterniond dq =
      angle > 0.0 ? Eigen::Quaterniond(Eigen::AngleAxisd(angle, dth / angle)) : Eigen::Quaterniond::Identity();
  initial_ = trn::filter::InitialEstimate{};
  initial_.t_s = 0.0;
  initial_.x.p_m = t0.r_m + dp;
  initial_.x.v_mps = t0.v_mps + dv;
  initial_.x.q_mb = (t0.q_mb * dq).normalized();  // body-frame attitude error
  initial_.sigma_p_m = trn::filter::Vec3(e.position_m, e.position_m, std::max(e.altitude_m, 1.0));
  initial_.sigma_v_mps = trn::filter::Vec3::Constant(std::max(e.velocity_mps, 0.01));
  initial_.sigma_th_rad = trn::filter::Vec3::Constant(std::max(att_rad, 1e-4));
}

bool Mission::build(const MissionSetup& setup, std::string& error) {
  setup_ = setup;
  const Scenario& s = setup_.scenario;
  const Chip chip = find_chip(s.chip);
  if (chip.profile == nullptr) {
    error = "no such chip: \"" + s.chip + "\" (tile64 or maestro)";
    return false;
  }
  chip_ = chip;
  world_ = WorldCache(setup_.world_cache);
  if (!world_.terrain(s.terrain, error)) {
    return false;
  }
  if (truth_.init(s.trajectory) != bsp::world::WorldError::kOk) {
    error = "the trajectory of the scenario is not valid";
    return false;
  }
  draw_initial_estimate();
  return true;
}

namespace {

/** The scenario's phases for the supervisor tree, in mission ticks (1 ms). */
void configure_supervisors(const Scenario& s, trn::tasks::SupervisorsConfig& sup) {
  sup.phase_count = 0U;
  for (const MissionPhase& p : s.phases) {
    if (sup.phase_count >= trn::tasks::kMaxPhases) {
      break;  // the parser allows no more
    }
    trn::tasks::PhaseSpec& f = sup.phases[sup.phase_count++];
    f.start_tick = static_cast<std::uint32_t>(std::llround(p.start_s * 1000.0));
    f.reliability = p.reliability;
    f.power = p.power;
  }
}

}  // namespace

namespace {

/**
 * The ground's landmark table (trn/tasks/vision/landmark_product.hpp): the selection
 * the coordinator would make on the map's fine layer, with its positions,
 * carved into DDR beside the map.
 */
bool carve_landmark_product(const bsp::MapProductHeader* product, const trn::vision::SelectParams& params,
                            WorldCache& cache, const Scenario& s, std::string& error) {
  trn::vision::MapView fine{};
  if (trn::vision::map_view(product, bsp::kMapLayerFine, fine) != trn::vision::Status::kOk) {
    error = "the reference map has no fine layer to select landmarks on";
    return false;
  }
  auto table = std::make_unique<trn::vision::LandmarkTable>();
  // The selection over the whole fine layer takes a tenth of a second; a cached table is the same bytes.
  const bool made = cache.landmarks(s.terrain, s.map, params, *table, [&](trn::vision::LandmarkTable& t) {
    bsp::Work work{};
    const trn::vision::Status st =
        trn::vision::select_landmarks(fine.image, trn::vision::ConstImageF32{}, fine.geo, params, t, work);
    if (st != trn::vision::Status::kOk) {
      error = "cannot select the ground's landmarks on the map (status " + std::to_string(static_cast<int>(st)) +
              "; check the selection's cells against the map's size)";
      return false;
    }
    for (std::uint32_t i = 0; i < t.count; ++i) {
      trn::vision::Landmark& lm = t.items[i];
      bsp::map_pixel_position(product, bsp::kMapLayerFine, static_cast<std::uint32_t>(lm.col_px),
                              static_cast<std::uint32_t>(lm.row_px), lm.p_m);
    }
    return true;
  });
  if (!made) {
    return false;
  }
  const std::size_t bytes = trn::tasks::landmark_product_bytes(table->count);
  const bsp::Carve c = bsp::carve(bsp::Region{bsp::Region::kDdr}, bytes, 8U, trn::tasks::kLandmarkProductCarveName);
  const trn::tasks::ProductLayer layer{fine.image.width, fine.image.height, fine.geo};
  if (c.error != bsp::MemError::kOk ||
      !trn::tasks::landmark_product_write(
          *table, params, layer,
          std::span<std::uint8_t>(reinterpret_cast<std::uint8_t*>(c.ptr), bytes))) {  // NOLINT(cppcoreguidelines-pro-type-reinterpret-cast): carve bytes
    error = "cannot carve the ground's landmark table into DDR";
    return false;
  }
  return true;
}

}  // namespace

bool Mission::init_devices(std::string& error) {
  // The devices start afresh with every boot (a test may boot several times).
  const Scenario& s = setup_.scenario;
  if (imu_.init(&truth_, s.imu, s.seed) != bsp::ImuError::kOk) {
    error = "the IMU configuration is not valid";
    return false;
  }
  if (camera_.init(&truth_, s.camera, s.seed) != bsp::CameraError::kOk) {
    error = "cannot set up the camera";
    return false;
  }
  if (!setup_.render_ahead) {
    bsp::frame_ahead::stop();
  } else if (!bsp::frame_ahead::start(std::size_t{s.camera.width_px} * s.camera.height_px)) {
    error = "cannot start the host thread that renders camera frames ahead";
    return false;
  }
  return true;
}

bool Mission::boot(std::string& error) {
  using trn::tasks::Role;
  const Scenario& s = setup_.scenario;
  const trn::tasks::Deployment& dep = deployment();
  bsp::BoardConfig cfg = bsp::default_config(chip());
  cfg.seed = s.seed;
  // Every watchdog interrupt goes to the tile-health supervisor's tile.
  cfg.monitor_tile = trn::tasks::boot_tile(dep, Role::kTrnSupervisor);
  powered_ = 0;
  for (std::uint32_t t = 0; t < dep.tiles(); ++t) {
    const Role r = trn::tasks::tile_role(dep, t);
    if (trn::tasks::role_table(r).empty() || ((setup_.unpowered >> t) & 1ULL) != 0ULL) {
      continue;
    }
    powered_ |= 1ULL << t;
    cfg.boot[t] = &k::boot_entry;
    k::set_task_table(static_cast<bsp::TileId>(t), trn::tasks::role_table(r), cfg.tick_cycles);
  }
  // A spare boots the role the supervisor assigns it before switching it on.
  for (std::uint32_t t = 0; t < dep.tiles(); ++t) {
    if (trn::tasks::tile_role(dep, t) != Role::kSpare) {
      continue;
    }
    cfg.boot[t] = &trn::tasks::spare_boot_entry;
  }
  cfg.powered_at_start = powered_;
  // The DDR products of a previous run in this process go first (tests boot several times).
  (void)bsp::region_reset(bsp::Region{bsp::Region::kDdr});
  if (bsp::board_init(cfg) != bsp::BoardError::kOk || bsp::udn_net_init(bsp::NetConfig{}) != bsp::NetError::kOk) {
    error = "cannot initialise the board";
    return false;
  }
  // The flight event log first: its rings are DDR the tiles write from their first event.
  if (fdir::event_log_init() != fdir::LogError::kOk || !fdir::boot_slots_init()) {
    error = "cannot carve the flight event log";
    return false;
  }
  // DDR products after the board: the reference map, then the camera's frame ring.
  bsp::world::WorldError werr = bsp::world::WorldError::kOk;
  const bsp::MapProductHeader* product = world_.map(s.terrain, s.map, werr);
  if (product == nullptr) {
    error = "cannot build the reference map (check [map] against the terrain size)";
    return false;
  }
  if (setup_.ground_landmarks && !carve_landmark_product(product, setup_.select, world_, s, error)) {
    return false;
  }
  if (!init_devices(error)) {
    return false;
  }
  // Every role's configuration, given to the image in one step; the tiles the roles name come from
  // the deployment's wiring (trn/tasks/tile_map.hpp, kWiring).
  trn::tasks::ImageConfig image{};
  trn::tasks::wire_image(image, dep);
  // The boot fault map every endpoint starts from, and the health tile the probes report to.
  udn::EndpointConfig& ep = image.endpoint;
  if (udn::fault_map_init(ep.boot_map, dep.cols, dep.rows) != udn::RouteError::kOk) {
    error = "cannot make the fault map";
    return false;
  }
  std::uint64_t spares = 0;
  for (std::uint32_t t = 0; t < dep.tiles(); ++t) {
    spares |= trn::tasks::role_table(trn::tasks::tile_role(dep, t)).empty() ? (1ULL << t) : 0ULL;
  }
  // Tiles removed from a role (setup.unpowered) are not "off by design": the
  // probes find them and the health task votes them out of the fault map.
  // A spare's switch routes but nothing runs there to forward a detour.
  ep.boot_map.no_forward = spares;
  image.tile_health.watched = powered_;
  image.tile_health.spares = setup_.no_spares ? 0U : spares;
  if (setup_.no_spares) {
    image.tile_health.slot_spare.fill(bsp::kNoTile);
  }
  // The roles that move to a spare when their tile is given up (trn/tasks/tile_map.hpp, kRoles).
  image.tile_health.movable_slots = trn::tasks::movable_slots(dep);
  ep.not_probed = spares;
  ep.sink = fdir::ft_event_sink();
  image.net_health.not_voted = spares;
  // Transit probes test the switches no two live neighbours can vote on: the
  // spares' (they route but run nothing) and those of live tiles with one live
  // neighbour. The coordinator and the filter take the mission's busiest
  // inbound traffic: they are crossed by transits but neither ping nor answer
  // them (probes queued behind a frame's results would tip their queues over).
  std::uint64_t subjects = 0;
  if (trn::tasks::tile_map_transits(dep, ep.boot_map, powered_, spares, image.net_health.votes_to_fail,
                                    image.net_health.transits, subjects) != fdir::TransitError::kOk) {
    error = "cannot plan the transit probes";
    return false;
  }
  image.net_health.transit_subjects = subjects;
  for (bsp::TileId t = 0; t < dep.tiles(); ++t) {
    ep.transit_targets[t] = fdir::transit_targets(image.net_health.transits, t);
  }
  configure_supervisors(s, image.sup);
  trn::tasks::FilterTaskConfig& f = image.filter;
  f.filter.imu = imu_spec(s.imu);
  f.filter.map_tie_sigma_m[0] = s.map_tie.horizontal_m;
  f.filter.map_tie_sigma_m[1] = s.map_tie.horizontal_m;
  f.filter.map_tie_sigma_m[2] = s.map_tie.vertical_m;
  f.camera = camera_.model();
  f.initial = initial_;
  trn::tasks::VisionCoordConfig& c = image.coord;
  c.camera = camera_.model();
  c.select = setup_.select;
  c.plan.max_landmarks = s.vision.landmarks_per_frame;
  // The coordinator learns of lost tiles by their silence; tiles left out on purpose are not in its list.
  trn::tasks::tile_map_vision_tiles(dep, c, vision_exclude_mask(dep, setup_.vision_tiles));
  trn::vision::sun_direction(s.camera.sun.azimuth_deg, s.camera.sun.elevation_deg, c.descent_sun_m);
  image.vision.camera = camera_.model();
  trn::vision::sun_direction(s.camera.sun.azimuth_deg, s.camera.sun.elevation_deg, image.vision.descent_sun_m);
  const char* wrong = nullptr;
  if (trn::tasks::configure_image(image, &wrong) != trn::tasks::ImageError::kOk) {
    error = std::string("the image configuration is not valid: ") + (wrong != nullptr ? wrong : "?");
    return false;
  }
  bsp::DeviceBusConfig bus;
  bus.io_tile = trn::tasks::boot_tile(dep, Role::kIo);
  bus.backup_tile = trn::tasks::backup_tile(dep, Role::kIo);  // the cross-strap: the I/O role's one spare
  bus.imu = &imu_;
  bus.camera = &camera_;
  bus.last_time_s = setup_.duration_s;
  if (bsp::attach_devices(bus) != bsp::DeviceBusError::kOk) {
    error = "cannot attach the devices";
    return false;
  }
  return true;
}

NavSample Mission::nav() const {
  NavSample n;
  // The latest solution as the filter's tile holds it; none while the tile restarts (no record).
  trn::tasks::FilterOutput out{};
  if (tools::try_read_record(trn::tasks::slot_tile_now(trn::tasks::kSlotFilter), trn::tasks::kFilterOutputRecord,
                             out) != tools::RecordRead::kOk ||
      !out.delivered) {
    return n;
  }
  const trn::filter::NavOutput& o = out.latest;
  const bsp::world::TruthState t = truth_.at(o.t_s);
  n.valid = true;
  n.t_s = o.t_s;
  n.truth_p = t.r_m;
  n.truth_v = t.v_mps;
  n.est_p = Eigen::Vector3d(o.p_m[0], o.p_m[1], o.p_m[2]);
  n.est_v = Eigen::Vector3d(o.v_mps[0], o.v_mps[1], o.v_mps[2]);
  for (int i = 0; i < 3; ++i) {
    // Against the world: the filter's map-relative variance with the map's tie variance (what guidance trusts).
    n.sigma3_p[i] = 3.0 * std::sqrt(std::max(o.pos_var_world[i], 0.0));
  }
  n.position_error_m = (n.est_p - n.truth_p).norm();
  n.velocity_error_mps = (n.est_v - n.truth_v).norm();
  const Eigen::Quaterniond q(o.q_mb_wxyz[0], o.q_mb_wxyz[1], o.q_mb_wxyz[2], o.q_mb_wxyz[3]);
  n.attitude_error_deg = t.q_mb.angularDistance(q.normalized()) * 180.0 / std::numbers::pi;
  n.altitude_m = t.r_m.z();
  n.flags = o.flags;
  return n;
}

}  // namespace tools
