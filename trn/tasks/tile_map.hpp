/**
 * @file tile_map.hpp
 * @brief The mission's tile map: which role, and so which task table, each of the 64 tiles runs.
 *
 * One static table (kTileRoles) is the single source: the image powers the
 * tiles whose role is not a spare, registers each role's task table, and
 * configures every role in one step before boot (configure_image). Default 8x8 layout (tile = row * 8 + col):
 *
 *   row 0:  T  V  .  .  .  .  F  S     T TRN supervisor, V vision coordinator,
 *   row 1:  .  I  .  .  .  .  .  .     F filter supervisor, S vision supervisor,
 *   row 2:  .  .  N  R  R  R  .  .     I I/O tile, N navigation filter (and TMR voter),
 *   rows 3-7: v v v v v v v v          R filter replica (idle until TMR),
 *                                      v vision tile, . spare (powered off)
 *
 * The TRN supervisor's tile runs the top of the supervisor tree
 * (trn/tasks/supervisors.hpp: mission phases, policies, escalations) beside
 * the network-health task (switch and link voting, fault-map publication:
 * fdir/net_health.hpp) and the tile-health supervisor (watchdog interrupts,
 * resets, spares: fdir/tile_health.hpp). The filter and vision supervisors sit
 * at the far end of row 0, away from the spares the coordinator, the filter
 * and the replicas move to. Every role tile runs a health agent that kicks
 * its hardware watchdog while its tasks check in.
 */
#pragma once

#include "fdir/net_health.hpp"
#include "fdir/tile_health.hpp"
#include "kernel/task_table.hpp"
#include "trn/tasks/filter_task.hpp"
#include "trn/tasks/filter_tmr.hpp"
#include "trn/tasks/io_task.hpp"
#include "trn/tasks/messages.hpp"
#include "trn/tasks/supervisors.hpp"
#include "trn/tasks/vision_coord.hpp"
#include "trn/tasks/vision_worker.hpp"
#include "udn/endpoint.hpp"

#include <array>
#include <cstdint>

namespace trn::tasks {

enum class Role : std::uint8_t {
  kSpare,
  kTrnSupervisor,
  kVisionCoordinator,
  kFilterSupervisor,
  kIo,
  kFilter,
  kVision,
  kFilterReplica,
  kVisionSupervisor,
};

inline constexpr std::uint32_t kMapTiles = 64;

/** Names for displays and outputs ("spare", "trn_supervisor", "vision_coordinator", ...). */
const char* role_name(Role r) noexcept;
/** One-letter codes of the diagram above. */
char role_code(Role r) noexcept;

namespace detail {
constexpr std::array<Role, kMapTiles> make_roles() noexcept {
  std::array<Role, kMapTiles> r{};
  for (Role& x : r) {
    x = Role::kSpare;
  }
  r[0] = Role::kTrnSupervisor;
  r[1] = Role::kVisionCoordinator;
  r[6] = Role::kFilterSupervisor;
  r[7] = Role::kVisionSupervisor;
  r[9] = Role::kIo;
  r[18] = Role::kFilter;
  r[21] = Role::kFilterReplica;
  r[19] = Role::kFilterReplica;
  r[20] = Role::kFilterReplica;
  for (std::uint32_t t = 24; t < kMapTiles; ++t) {
    r[t] = Role::kVision;
  }
  return r;
}
}  // namespace detail

/** The default tile map. */
inline constexpr std::array<Role, kMapTiles> kTileRoles = detail::make_roles();

constexpr bsp::TileId kSupervisorTile = 0;
constexpr bsp::TileId kCoordinatorTile = 1;
constexpr bsp::TileId kIoTile = 9;
constexpr bsp::TileId kFilterTile = 18;
constexpr bsp::TileId kFilterSupervisorTile = 6;
constexpr bsp::TileId kVisionSupervisorTile = 7;
/** The filter's TMR replicas, by replica index (role slots kSlotReplica0 + i). */
constexpr std::array<bsp::TileId, 3> kReplicaTiles{19, 20, 21};

constexpr std::uint32_t count_role(Role r) noexcept {
  std::uint32_t n = 0;
  for (Role x : kTileRoles) {
    n += (x == r) ? 1U : 0U;
  }
  return n;
}
static_assert(count_role(Role::kVision) == 40, "40 vision tiles");
static_assert(kTileRoles[kReplicaTiles[0]] == Role::kFilterReplica && kTileRoles[kReplicaTiles[1]] == Role::kFilterReplica &&
                  kTileRoles[kReplicaTiles[2]] == Role::kFilterReplica,
              "replica tiles match the map");
static_assert(kTileRoles[kCoordinatorTile] == Role::kVisionCoordinator && kTileRoles[kIoTile] == Role::kIo &&
                  kTileRoles[kFilterTile] == Role::kFilter && kTileRoles[kFilterSupervisorTile] == Role::kFilterSupervisor &&
                  kTileRoles[kVisionSupervisorTile] == Role::kVisionSupervisor,
              "named tiles match the map");

/** Everything the image's tasks are configured with: one value, given before boot. */
struct ImageConfig {
  udn::EndpointConfig endpoint{};        ///< every tile's messaging endpoint (boot map, probes, report tile, sink)
  fdir::HealthAgentConfig agent{};       ///< every tile's health agent (supervisor tile, watchdog timeout)
  fdir::NetHealthConfig net_health{};    ///< the TRN supervisor's network-health task
  fdir::TileHealthConfig tile_health{};  ///< the TRN supervisor's tile-health task
  IoTaskConfig io{};                     ///< the I/O tile's driver
  FilterTaskConfig filter{};             ///< the navigation filter
  VisionCoordConfig coord{};             ///< the vision coordinator
  VisionWorkerConfig vision{};           ///< every vision tile
  SupervisorsConfig sup{};               ///< the TRN supervisor tree (phases, node tiles)
};

enum class ImageError : std::uint8_t {
  kOk,
  kBadTile,        ///< a tile a role sends to or reports to is off the chip
  kBadVisionList,  ///< more vision tiles than a coordinator drives, or one off the chip
  kBadConfig,      ///< a role's own setting out of range (votes to fail < 2, matches per job, deadline)
};

/**
 * The image's one configuration step: checks @p cfg and makes it what every
 * role's task reads at its start. Call before the board boots the tiles (a
 * running task keeps the pointer it was given). [host, before boot]
 * @return kOk, or what is wrong (nothing is changed then).
 */
[[nodiscard]] ImageError configure_image(const ImageConfig& cfg) noexcept;

/** The configuration the tasks read (what configure_image last accepted). */
const ImageConfig& image_config() noexcept;

/**
 * The image's transit probes (fdir/transit.hpp) on @p map: subjects are the
 * @p spares and the tiles of @p powered with fewer than @p votes live
 * neighbours (no neighbour vote can fail their switch); probers are the
 * tiles of @p powered but the coordinator and the filter, which take the
 * mission's busiest inbound traffic and neither ping nor answer transits
 * (they are still crossed). @p subjects_out: the subjects. [host, before boot]
 */
[[nodiscard]] fdir::TransitError tile_map_transits(const udn::FaultMap& map, std::uint64_t powered,
                                                   std::uint64_t spares, std::uint32_t votes,
                                                   fdir::TransitPlan& plan, std::uint64_t& subjects_out) noexcept;

namespace detail {
/** The storage the task tables point into; written only by configure_image. */
extern ImageConfig g_image;
}  // namespace detail

/** The endpoint service every TRN tile runs first in its table. */
inline constexpr k::TaskSpec kCommTask = udn::endpoint_task_spec(&detail::g_image.endpoint);
/** The health agent every TRN tile runs second (task watchdog, hardware watchdog kicks, boot report). */
inline constexpr k::TaskSpec kAgentTask = fdir::health_agent_task_spec(&detail::g_image.agent);

/**
 * Check-in budgets (ticks) of the role tasks with their tile's health agent:
 * a few times the longest gap between two check-ins measured in flight
 * (docs/FDIR.md, "Core health").
 */
inline constexpr std::uint32_t kWatchSupervisor = 50U;
inline constexpr std::uint32_t kWatchIo = 100U;
inline constexpr std::uint32_t kWatchFilter = 50U;
inline constexpr std::uint32_t kWatchCoordinator = 3000U;
inline constexpr std::uint32_t kWatchVision = 500U;

/** The TRN supervisor's tile: network health (suspect voting, fault map) and tile health (watchdogs). */
inline constexpr k::TaskSpec kSupervisorRole[] = {
    kCommTask,
    kAgentTask,
    {"tile_health", &fdir::tile_health_task_main, &detail::g_image.tile_health, 2, 0, 0, 16U * 1024U,
     k::Policy::kPreemptive, kWatchSupervisor},
    {"net_health", &fdir::net_health_task_main, &detail::g_image.net_health, 3, 0, 0, 16U * 1024U,
     k::Policy::kPreemptive, kWatchSupervisor},
    {"trn_sup", &trn_supervisor_main, &detail::g_image.sup, 4, 0, 0, 16U * 1024U, k::Policy::kPreemptive,
     kWatchSupervisor},
};
/** The filter supervisor's tile: simplex or TMR, judged from the filter's status. */
inline constexpr k::TaskSpec kFilterSupervisorRole[] = {
    kCommTask,
    kAgentTask,
    {"filter_sup", &filter_supervisor_main, &detail::g_image.sup, 2, 0, 0, 16U * 1024U, k::Policy::kPreemptive,
     kWatchSupervisor},
};
/** The vision supervisor's tile: the image rate the healthy vision tiles can keep. */
inline constexpr k::TaskSpec kVisionSupervisorRole[] = {
    kCommTask,
    kAgentTask,
    {"vision_sup", &vision_supervisor_main, &detail::g_image.sup, 2, 0, 0, 16U * 1024U, k::Policy::kPreemptive,
     kWatchSupervisor},
};
/** I/O tile: the device driver, most urgent after its messaging service and agent. */
inline constexpr k::TaskSpec kIoRole[] = {
    kCommTask,
    kAgentTask,
    {"io", &io_task_main, &detail::g_image.io, 2, 0, 0, 32U * 1024U, k::Policy::kPreemptive, kWatchIo},
};
/**
 * Filter tile: the messaging service (IMU and match batches in, solutions out)
 * and the navigation filter, 100 Hz (10 ticks of 1 ms), deadline one period.
 */
inline constexpr k::TaskSpec kFilterRole[] = {
    kCommTask,
    kAgentTask,
    {"filter", &filter_task_main, &detail::g_image.filter, 2, kFilterPeriodTicks, kFilterPeriodTicks, 32U * 1024U, k::Policy::kPreemptive,
     kWatchFilter},
};
/**
 * A TMR replica of the filter: idle while the filter is simplex; in TMR it
 * runs the filter's job records (100 Hz like the filter, up to
 * kReplicaJobsPerRelease records a release) and sends the voter its outputs:
 * a record the front wrote after the replica's release runs at the next one,
 * still before the front votes it kVoteLag jobs later.
 */
inline constexpr k::TaskSpec kReplicaRole[] = {
    kCommTask,
    kAgentTask,
    {"replica", &filter_replica_main, &detail::g_image.filter, 2, kFilterPeriodTicks, kFilterPeriodTicks, 32U * 1024U, k::Policy::kPreemptive,
     kWatchFilter},
};
/** Vision coordinator. */
inline constexpr k::TaskSpec kCoordinatorRole[] = {
    kCommTask,
    kAgentTask,
    {"vision_coord", &vision_coord_main, &detail::g_image.coord, 2, 0, 0, 32U * 1024U, k::Policy::kPreemptive,
     kWatchCoordinator},
};
/** A vision tile. */
inline constexpr k::TaskSpec kVisionRole[] = {
    kCommTask,
    kAgentTask,
    {"vision", &vision_worker_main, &detail::g_image.vision, 2, 0, 0, 32U * 1024U, k::Policy::kPreemptive,
     kWatchVision},
};

static_assert(k::check_table(kSupervisorRole) == k::TableError::kOk);
static_assert(k::check_table(kIoRole) == k::TableError::kOk);
static_assert(k::check_table(kFilterRole) == k::TableError::kOk);
static_assert(k::check_table(kCoordinatorRole) == k::TableError::kOk);
static_assert(k::check_table(kReplicaRole) == k::TableError::kOk);
static_assert(k::check_table(kVisionRole) == k::TableError::kOk);
static_assert(k::check_table(kFilterSupervisorRole) == k::TableError::kOk);
static_assert(k::check_table(kVisionSupervisorRole) == k::TableError::kOk);

/** Task table of role @p r (empty for spares and roles without tasks yet). */
k::TaskTable role_table(Role r) noexcept;

/** The role behind a role slot of the directory (kSlotFilter -> kFilter, ...); kSpare for none. */
Role slot_role(std::uint32_t slot) noexcept;

/** The tile the map boots a role slot on (kNoTile for none). */
bsp::TileId slot_boot_tile(std::uint32_t slot) noexcept;

/**
 * Where role slot @p slot runs now as the supervisor's directory says (the
 * boot tile before the supervisor's endpoint opens). [host: scoring, fault plans]
 */
bsp::TileId slot_tile_now(std::uint32_t slot) noexcept;

/**
 * Boot entry of a spare: starts the task table of the role slot the
 * tile-health supervisor assigned it before switching it on
 * (fdir::boot_slot); a spare with no assignment idles.
 */
void spare_boot_entry(bsp::TileId tile) noexcept;

/** Fills @p cfg's vision tile list from kTileRoles (skipping tiles in @p exclude_mask). */
void tile_map_vision_tiles(VisionCoordConfig& cfg, std::uint64_t exclude_mask) noexcept;

}  // namespace trn::tasks
