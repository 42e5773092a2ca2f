/**
 * @file tile_map.hpp
 * @brief The mission's tile map: which role, and so which task table, each tile of the chip runs.
 *
 * The deployment is declared once, in three tables: kRoles (each role's
 * names, task table, and whether it moves to a spare), a Deployment per chip
 * (where each role instance boots, and its directory slot: the tile map and
 * the named tiles follow from it; kTile64Deployment, kMaestroDeployment) and
 * kWiring (every tile a role's configuration names, and whose it is:
 * wire_image() fills them from the chip's deployment, configure_image()
 * checks them). The image powers the tiles whose role is not a spare, registers each
 * role's task table, and configures every role in one step before boot
 * (configure_image). Default 8x8 layout (tile = row * 8 + col):
 *
 *   row 0:  T  V  .  .  .  .  F  S     T TRN supervisor, V vision coordinator,
 *   row 1:  i  I  .  .  .  .  .  .     F filter supervisor, S vision supervisor,
 *   row 2:  t  .  N  R  R  R  .  .     I I/O tile, N navigation filter (and TMR voter),
 *   rows 3-7: v v v v v v v v          R filter replica (idle until TMR),
 *                                      v vision tile, . spare (powered off),
 *                                      i the I/O role's backup (a spare kept for it:
 *                                        the devices' second attachment),
 *                                      t the TRN supervisor's standby (a spare kept
 *                                        for it: its watcher switches it on)
 *
 * The TRN supervisor's tile runs the top of the supervisor tree
 * (trn/tasks/supervisors/supervisors.hpp: mission phases, policies, escalations) beside
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
#include "trn/tasks/filter/filter_task.hpp"
#include "trn/tasks/filter/filter_tmr.hpp"
#include "trn/tasks/io/io_task.hpp"
#include "trn/tasks/messages.hpp"
#include "trn/tasks/roles.hpp"
#include "trn/tasks/supervisors/supervisors.hpp"
#include "trn/tasks/vision/vision_coord.hpp"
#include "trn/tasks/vision/vision_worker.hpp"
#include "udn/endpoint.hpp"

#include <array>
#include <cstdint>
#include <type_traits>

namespace trn::tasks {

/** Tiles of the largest chip a deployment is declared for (the TILE64's 64: masks are 64-bit). */
inline constexpr std::uint32_t kMapTiles = 64;

/** Names for displays and outputs ("spare", "trn_supervisor", "vision_coordinator", ...). */
const char* role_name(Role r) noexcept;
/** One-letter codes of the diagram above. */
char role_code(Role r) noexcept;

/** No directory slot: senders name the role's tile, and the role does not move. */
inline constexpr std::uint32_t kNoSlot = 0xFFFF'FFFFU;

/** Where one role (or one of a role's instances) boots, and its directory slot. */
struct Placement {
  Role role;
  std::uint32_t slot;  ///< its role-directory slot (kNoSlot: senders name its tile, it does not move)
  bsp::TileId tile;
  /**
   * The one spare the role moves to (kNoTile: the nearest free one): the
   * I/O role's is the tile the devices' second attachment is on (the
   * cross-strap, bsp_tile64/api/device_io.hpp), kept for it.
   */
  bsp::TileId backup;
};

/**
 * The mission deployed on one chip: its grid, one row per role instance
 * (its placements) and the first vision tile. Every tile from there to the
 * chip's last is a vision tile; the other tiles below it are spares.
 */
struct Deployment {
  const char* chip;     ///< the chip profile it is for (bsp_tile64/emu/profile.hpp: "tile64", "maestro")
  std::uint32_t cols;   ///< the chip's grid (tile = row * cols + col)
  std::uint32_t rows;
  std::array<Placement, 9> placements;
  bsp::TileId vision_first;  ///< the vision tiles: every tile from here to the last

  [[nodiscard]] constexpr std::uint32_t tiles() const noexcept { return cols * rows; }
};

/** The TILE64's deployment (the diagram at the top of this file). */
inline constexpr Deployment kTile64Deployment{
    "tile64", 8U, 8U,
    {{
        {Role::kTrnSupervisor, kSlotTrnSupervisor, 0, 16},
        {Role::kVisionCoordinator, kSlotCoordinator, 1, bsp::kNoTile},
        {Role::kFilterSupervisor, kSlotFilterSupervisor, 6, bsp::kNoTile},
        {Role::kVisionSupervisor, kSlotVisionSupervisor, 7, bsp::kNoTile},
        {Role::kIo, kSlotIo, 9, 8},
        {Role::kFilter, kSlotFilter, 18, bsp::kNoTile},
        {Role::kFilterReplica, kSlotReplica0, 19, bsp::kNoTile},
        {Role::kFilterReplica, kSlotReplica0 + 1U, 20, bsp::kNoTile},
        {Role::kFilterReplica, kSlotReplica0 + 2U, 21, bsp::kNoTile},
    }},
    24};

/**
 * Maestro's deployment (7x7, tile = row * 7 + col): the same roles in two
 * rows, three free spares, and 35 vision tiles in rows 2-6.
 *
 *   row 0:  T  V  .  .  .  F  S     (letters as in the TILE64's diagram)
 *   row 1:  i  I  N  R  R  R  t
 *   rows 2-6: v v v v v v v
 */
inline constexpr Deployment kMaestroDeployment{
    "maestro", 7U, 7U,
    {{
        {Role::kTrnSupervisor, kSlotTrnSupervisor, 0, 13},
        {Role::kVisionCoordinator, kSlotCoordinator, 1, bsp::kNoTile},
        {Role::kFilterSupervisor, kSlotFilterSupervisor, 5, bsp::kNoTile},
        {Role::kVisionSupervisor, kSlotVisionSupervisor, 6, bsp::kNoTile},
        {Role::kIo, kSlotIo, 8, 7},
        {Role::kFilter, kSlotFilter, 9, bsp::kNoTile},
        {Role::kFilterReplica, kSlotReplica0, 10, bsp::kNoTile},
        {Role::kFilterReplica, kSlotReplica0 + 1U, 11, bsp::kNoTile},
        {Role::kFilterReplica, kSlotReplica0 + 2U, 12, bsp::kNoTile},
    }},
    14};

/** Every deployment, by chip. */
inline constexpr std::array<const Deployment*, 2> kDeployments{&kTile64Deployment, &kMaestroDeployment};

/** The deployment for chip @p name ("tile64", "maestro"); nullptr for a chip with none. */
const Deployment* find_deployment(const char* name) noexcept;

/** The backup tile of the first instance of role @p r (Placement::backup); kNoTile if it has none. */
constexpr bsp::TileId backup_tile(const Deployment& d, Role r) noexcept {
  for (const Placement& p : d.placements) {
    if (p.role == r) {
      return p.backup;
    }
  }
  return bsp::kNoTile;
}

/** The tile of the @p index-th instance of role @p r in @p d; kNoTile if it has none. */
constexpr bsp::TileId boot_tile(const Deployment& d, Role r, std::uint32_t index = 0U) noexcept {
  std::uint32_t seen = 0U;
  for (const Placement& p : d.placements) {
    if (p.role == r && seen++ == index) {
      return p.tile;
    }
  }
  return bsp::kNoTile;
}

/** The role tile @p t boots (kSpare for a spare, and for a tile off @p d's chip). */
constexpr Role tile_role(const Deployment& d, std::uint32_t t) noexcept {
  if (t >= d.tiles()) {
    return Role::kSpare;
  }
  for (const Placement& p : d.placements) {
    if (p.tile == t) {
      return p.role;
    }
  }
  return t >= d.vision_first ? Role::kVision : Role::kSpare;
}

/** Every tile's boot role (kSpare beyond the chip's last tile). */
constexpr std::array<Role, kMapTiles> tile_roles(const Deployment& d) noexcept {
  std::array<Role, kMapTiles> r{};
  for (std::uint32_t t = 0; t < kMapTiles; ++t) {
    r[t] = tile_role(d, t);
  }
  return r;
}

/** Tiles of @p d that boot role @p r. */
constexpr std::uint32_t count_role(const Deployment& d, Role r) noexcept {
  std::uint32_t n = 0;
  for (std::uint32_t t = 0; t < d.tiles(); ++t) {
    n += (tile_role(d, t) == r) ? 1U : 0U;
  }
  return n;
}

namespace detail {
constexpr bool placements_ok(const Deployment& d) noexcept {
  if (d.tiles() > kMapTiles || d.vision_first >= d.tiles()) {
    return false;
  }
  const auto& pl = d.placements;
  for (std::size_t i = 0; i < pl.size(); ++i) {
    const bsp::TileId b = pl[i].backup;
    if (pl[i].tile >= d.vision_first || (b != bsp::kNoTile && (b >= d.vision_first || pl[i].slot == kNoSlot))) {
      return false;
    }
    for (std::size_t j = 0; j < pl.size(); ++j) {
      if (b != bsp::kNoTile && (pl[j].tile == b || (j != i && pl[j].backup == b))) {
        return false;  // a backup is a spare, kept for one role
      }
    }
    for (std::size_t j = i + 1U; j < pl.size(); ++j) {
      if (pl[i].tile == pl[j].tile || (pl[i].slot == pl[j].slot && pl[i].slot != kNoSlot)) {
        return false;
      }
    }
  }
  return true;
}
/** The same roles and directory slots, in the same order, on every chip (only the tiles differ). */
constexpr bool same_roles(const Deployment& a, const Deployment& b) noexcept {
  for (std::size_t i = 0; i < a.placements.size(); ++i) {
    if (a.placements[i].role != b.placements[i].role || a.placements[i].slot != b.placements[i].slot) {
      return false;
    }
  }
  return true;
}
}  // namespace detail
static_assert(detail::placements_ok(kTile64Deployment) && detail::placements_ok(kMaestroDeployment),
              "each tile and each directory slot placed once, below the vision tiles; a backup is a spare of one role with a slot");
static_assert(detail::same_roles(kTile64Deployment, kMaestroDeployment), "the chips deploy the same role instances");
static_assert(count_role(kTile64Deployment, Role::kVision) == 40, "40 vision tiles on the TILE64");
static_assert(count_role(kMaestroDeployment, Role::kVision) == 35, "35 vision tiles on Maestro");
static_assert(count_role(kTile64Deployment, Role::kFilterReplica) == 3 &&
                  count_role(kMaestroDeployment, Role::kFilterReplica) == 3,
              "three replicas");

// The TILE64 deployment's tiles by name (its tests and docs use them; the image takes
// its deployment from its configuration, ImageConfig::deployment).
/** The TILE64's placements. */
inline constexpr const std::array<Placement, 9>& kPlacements = kTile64Deployment.placements;
/** The TILE64's vision tiles: every tile from here to the last (rows 3-7). */
inline constexpr bsp::TileId kVisionFirstTile = kTile64Deployment.vision_first;
/** The TILE64's tile map. */
inline constexpr std::array<Role, kMapTiles> kTileRoles = tile_roles(kTile64Deployment);

/** The backup tile of the first instance of role @p r on the TILE64. */
constexpr bsp::TileId backup_tile(Role r) noexcept { return backup_tile(kTile64Deployment, r); }
/** The tile of the @p index-th instance of role @p r on the TILE64. */
constexpr bsp::TileId boot_tile(Role r, std::uint32_t index = 0U) noexcept {
  return boot_tile(kTile64Deployment, r, index);
}

constexpr bsp::TileId kSupervisorTile = boot_tile(Role::kTrnSupervisor);
constexpr bsp::TileId kCoordinatorTile = boot_tile(Role::kVisionCoordinator);
constexpr bsp::TileId kIoTile = boot_tile(Role::kIo);
/** The cross-strap's second attachment of the devices: the I/O role's one spare. */
constexpr bsp::TileId kIoBackupTile = backup_tile(Role::kIo);
/** The TRN supervisor's standby: a spare kept for it, which its watcher switches on when it is cut off. */
constexpr bsp::TileId kSupervisorStandbyTile = backup_tile(Role::kTrnSupervisor);
constexpr bsp::TileId kFilterTile = boot_tile(Role::kFilter);
constexpr bsp::TileId kFilterSupervisorTile = boot_tile(Role::kFilterSupervisor);
constexpr bsp::TileId kVisionSupervisorTile = boot_tile(Role::kVisionSupervisor);
/** The filter's TMR replicas, by replica index (role slots kSlotReplica0 + i). */
constexpr std::array<bsp::TileId, 3> kReplicaTiles{boot_tile(Role::kFilterReplica, 0U),
                                                   boot_tile(Role::kFilterReplica, 1U),
                                                   boot_tile(Role::kFilterReplica, 2U)};

/** Tiles of the TILE64 that boot role @p r. */
constexpr std::uint32_t count_role(Role r) noexcept { return count_role(kTile64Deployment, r); }

/** Everything the image's tasks are configured with: one value, given before boot. */
struct ImageConfig {
  /** Where the roles boot (the chip's grid and role tiles): wire_image() sets it. */
  const Deployment* deployment = &kTile64Deployment;
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
 * The image's one configuration step: checks @p cfg (every tile of kWiring,
 * every FDIR parameter of kFdirParams against its range, and the rules that
 * tie parameters together) and makes it what every role's task reads at its
 * start. Call before the board boots the tiles (a running task keeps the
 * pointer it was given). [host, before boot]
 * @param what if not null: the name of the field that is wrong (nullptr when kOk).
 * @return kOk, or what is wrong (nothing is changed then).
 */
[[nodiscard]] ImageError configure_image(const ImageConfig& cfg, const char** what = nullptr) noexcept;

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
[[nodiscard]] fdir::TransitError tile_map_transits(const Deployment& d, const udn::FaultMap& map, std::uint64_t powered,
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
 * a record the voter wrote after the replica's release runs at the next one,
 * still before the voter votes it kVoteLag jobs later.
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

/** One role: its names, its task table and whether it moves to a spare. */
struct RoleDecl {
  Role role;
  const char* name;    ///< for displays and outputs
  char code;           ///< the diagram's letter
  k::TaskTable table;  ///< empty: nothing runs there (a spare)
  /**
   * Moves to a spare (its directory slot then names the spare) when its tile
   * is given up. The I/O role moves only to its backup (the devices' second
   * attachment, Placement::backup); the TRN supervisor is moved by its
   * watcher, to its standby (fdir/health_agent.hpp), not by itself; a vision
   * tile is replaced by the coordinator's pool, not moved.
   */
  bool movable;
};

/** Every role once, in the order of the enum. */
inline constexpr std::array<RoleDecl, 9> kRoles{{
    {Role::kSpare, "spare", '.', {}, false},
    {Role::kTrnSupervisor, "trn_supervisor", 'T', kSupervisorRole, false},
    {Role::kVisionCoordinator, "vision_coordinator", 'V', kCoordinatorRole, true},
    {Role::kFilterSupervisor, "filter_supervisor", 'F', kFilterSupervisorRole, true},
    {Role::kIo, "io", 'I', kIoRole, true},
    {Role::kFilter, "filter", 'N', kFilterRole, true},
    {Role::kVision, "vision", 'v', kVisionRole, false},
    {Role::kFilterReplica, "filter_replica", 'R', kReplicaRole, true},
    {Role::kVisionSupervisor, "vision_supervisor", 'S', kVisionSupervisorRole, true},
}};

namespace detail {
constexpr bool roles_in_order() noexcept {
  for (std::size_t i = 0; i < kRoles.size(); ++i) {
    if (static_cast<std::size_t>(kRoles[i].role) != i) {
      return false;
    }
  }
  return true;
}
}  // namespace detail
static_assert(detail::roles_in_order(), "kRoles[r] declares role r");

/** The declaration of role @p r. */
constexpr const RoleDecl& role_decl(Role r) noexcept {
  const auto i = static_cast<std::size_t>(r);
  return kRoles[i < kRoles.size() ? i : 0U];
}

/** Directory slots whose role moves to a spare (bit per slot): the tile-health supervisor's movable_slots. */
constexpr std::uint32_t movable_slots(const Deployment& d = kTile64Deployment) noexcept {
  std::uint32_t m = 0U;
  for (const Placement& p : d.placements) {
    m |= role_decl(p.role).movable && p.slot != kNoSlot ? (1U << p.slot) : 0U;
  }
  return m;
}

/** Task table of role @p r (empty for spares). */
constexpr k::TaskTable role_table(Role r) noexcept { return role_decl(r).table; }

/**
 * A tile one role's configuration names: the field (its name for errors and
 * docs) and the role instance whose boot tile it is. kWiring lists them all;
 * wire_image() fills them and configure_image() checks them from that list.
 */
struct Wire {
  const char* field;
  Role to;
  std::uint32_t index;  ///< which of the role's instances (a replica's index)
  bsp::TileId& (*set)(ImageConfig&) noexcept;
  bsp::TileId (*get)(const ImageConfig&) noexcept;
};

namespace detail {
template <std::size_t I, class T>
constexpr auto& tile_element(T& v) noexcept {
  if constexpr (std::is_same_v<std::remove_const_t<T>, bsp::TileId>) {
    return v;
  } else {
    return v[I];
  }
}
template <auto Part, auto Field, std::size_t I>
struct TileField {
  static bsp::TileId& set(ImageConfig& c) noexcept { return tile_element<I>((c.*Part).*Field); }
  static bsp::TileId get(const ImageConfig& c) noexcept { return tile_element<I>((c.*Part).*Field); }
};
}  // namespace detail

/** The wire of field @p Field of the part @p Part of the image's configuration (element @p I of an array). */
template <auto Part, auto Field, std::size_t I = 0U>
constexpr Wire wire(const char* field, Role to) noexcept {
  // The pointers are to static member functions, which live as long as the program.
  // cppcheck-suppress returnDanglingLifetime
  return {field, to, static_cast<std::uint32_t>(I), &detail::TileField<Part, Field, I>::set,
          &detail::TileField<Part, Field, I>::get};
}

/** Every tile a role's configuration names, and whose it is. */
inline constexpr std::array<Wire, 25> kWiring{{
    // Suspect reports, boot reports and watchdog interrupts go to the tile-health supervisor.
    wire<&ImageConfig::endpoint, &udn::EndpointConfig::health_tile>("endpoint.health_tile", Role::kTrnSupervisor),
    wire<&ImageConfig::agent, &fdir::HealthAgentConfig::health_tile>("agent.health_tile", Role::kTrnSupervisor),
    // The I/O role watches the supervisor's tile (and the watching moves with it, agent.watcher_slot);
    // the supervisor watches it in turn.
    wire<&ImageConfig::agent, &fdir::HealthAgentConfig::watcher_tile>("agent.watcher_tile", Role::kIo),
    wire<&ImageConfig::io, &IoTaskConfig::filter_tile>("io.filter_tile", Role::kFilter),
    wire<&ImageConfig::io, &IoTaskConfig::coordinator_tile>("io.coordinator_tile", Role::kVisionCoordinator),
    wire<&ImageConfig::io, &IoTaskConfig::trn_supervisor_tile>("io.trn_supervisor_tile", Role::kTrnSupervisor),
    wire<&ImageConfig::io, &IoTaskConfig::filter_supervisor_tile>("io.filter_supervisor_tile", Role::kFilterSupervisor),
    wire<&ImageConfig::sup, &SupervisorsConfig::trn_supervisor_tile>("sup.trn_supervisor_tile", Role::kTrnSupervisor),
    wire<&ImageConfig::sup, &SupervisorsConfig::filter_supervisor_tile>("sup.filter_supervisor_tile", Role::kFilterSupervisor),
    wire<&ImageConfig::sup, &SupervisorsConfig::vision_supervisor_tile>("sup.vision_supervisor_tile", Role::kVisionSupervisor),
    wire<&ImageConfig::sup, &SupervisorsConfig::io_tile>("sup.io_tile", Role::kIo),
    wire<&ImageConfig::sup, &SupervisorsConfig::coordinator_tile>("sup.coordinator_tile", Role::kVisionCoordinator),
    wire<&ImageConfig::sup, &SupervisorsConfig::replica_tiles, 0U>("sup.replica_tiles[0]", Role::kFilterReplica),
    wire<&ImageConfig::sup, &SupervisorsConfig::replica_tiles, 1U>("sup.replica_tiles[1]", Role::kFilterReplica),
    wire<&ImageConfig::sup, &SupervisorsConfig::replica_tiles, 2U>("sup.replica_tiles[2]", Role::kFilterReplica),
    wire<&ImageConfig::sup, &SupervisorsConfig::health_tile>("sup.health_tile", Role::kTrnSupervisor),
    wire<&ImageConfig::filter, &FilterTaskConfig::coordinator_tile>("filter.coordinator_tile", Role::kVisionCoordinator),
    wire<&ImageConfig::filter, &FilterTaskConfig::replica_tiles, 0U>("filter.replica_tiles[0]", Role::kFilterReplica),
    wire<&ImageConfig::filter, &FilterTaskConfig::replica_tiles, 1U>("filter.replica_tiles[1]", Role::kFilterReplica),
    wire<&ImageConfig::filter, &FilterTaskConfig::replica_tiles, 2U>("filter.replica_tiles[2]", Role::kFilterReplica),
    wire<&ImageConfig::filter, &FilterTaskConfig::filter_supervisor_tile>("filter.filter_supervisor_tile", Role::kFilterSupervisor),
    wire<&ImageConfig::coord, &VisionCoordConfig::filter_tile>("coord.filter_tile", Role::kFilter),
    wire<&ImageConfig::coord, &VisionCoordConfig::health_tile>("coord.health_tile", Role::kTrnSupervisor),
    wire<&ImageConfig::coord, &VisionCoordConfig::vision_supervisor_tile>("coord.vision_supervisor_tile", Role::kVisionSupervisor),
    wire<&ImageConfig::vision, &VisionWorkerConfig::coordinator_tile>("vision.coordinator_tile", Role::kVisionCoordinator),
}};

/**
 * Deploys the image on @p d's chip: sets cfg.deployment and fills every tile
 * of @p cfg that kWiring names with its role's boot tile, the role
 * directory's slots with their boot tiles, the spares kept for a slot
 * (Placement::backup) and the watcher's slot. [host, before boot]
 */
void wire_image(ImageConfig& cfg, const Deployment& d) noexcept;

/** The role behind a role slot of the directory (kSlotFilter -> kFilter, ...; the same on every chip); kSpare for none. */
Role slot_role(std::uint32_t slot) noexcept;

/** The tile @p d boots a role slot on (kNoTile for none). */
bsp::TileId slot_boot_tile(const Deployment& d, std::uint32_t slot) noexcept;

/**
 * Where role slot @p slot runs now as the supervisor's directory says (the
 * boot tile of the configured deployment before the supervisor's endpoint
 * opens). [host: scoring, fault plans]
 */
bsp::TileId slot_tile_now(std::uint32_t slot) noexcept;

/**
 * Boot entry of a spare: starts the task table of the role slot the
 * tile-health supervisor assigned it before switching it on
 * (fdir::boot_slot); a spare with no assignment idles.
 */
void spare_boot_entry(bsp::TileId tile) noexcept;

/** Fills @p cfg's vision tile list from @p d's vision tiles (skipping tiles in @p exclude_mask). */
void tile_map_vision_tiles(const Deployment& d, VisionCoordConfig& cfg, std::uint64_t exclude_mask) noexcept;

}  // namespace trn::tasks
