/**
 * @file tile_map.cpp
 * @brief Role names, role task tables and the configurations they point to.
 */
#include "trn/tasks/tile_map.hpp"

#include "fdir/tile_health.hpp"
#include "kernel/kernel.hpp"
#include "trn/tasks/messages.hpp"
#include "udn/endpoint.hpp"

namespace trn::tasks {

namespace detail {
ImageConfig g_image{};
}  // namespace detail

namespace {

/** A tile a role sends to: on the chip, or kNoTile (none: a role that is not flown). */
bool tile_ok(bsp::TileId t) noexcept { return t < kMapTiles || t == bsp::kNoTile; }

ImageError check(const ImageConfig& c) noexcept {
  if (!tile_ok(c.endpoint.report_to) || !tile_ok(c.io.filter_tile) || !tile_ok(c.io.coordinator_tile) ||
      !tile_ok(c.filter.nav_sink) || !tile_ok(c.coord.filter_tile) || !tile_ok(c.vision.coordinator) ||
      !tile_ok(c.agent.supervisor) || !tile_ok(c.agent.watcher) || !tile_ok(c.coord.health_tile) ||
      !tile_ok(c.sup.trn_tile) || !tile_ok(c.sup.filter_sup_tile) || !tile_ok(c.sup.vision_sup_tile) ||
      !tile_ok(c.sup.io_tile) || !tile_ok(c.sup.health_tile) || !tile_ok(c.sup.replica_tiles[0]) ||
      !tile_ok(c.sup.replica_tiles[1]) || !tile_ok(c.sup.replica_tiles[2]) || !tile_ok(c.io.trn_supervisor) || !tile_ok(c.io.filter_supervisor) || !tile_ok(c.sup.coordinator_tile) || !tile_ok(c.filter.supervisor) ||
      !tile_ok(c.coord.supervisor)) {
    return ImageError::kBadTile;
  }
  for (const bsp::TileId t : c.endpoint.roles.tile) {
    if (!tile_ok(t)) {
      return ImageError::kBadTile;
    }
  }
  if (c.coord.vision_count > kMaxVisionTiles) {
    return ImageError::kBadVisionList;
  }
  for (std::uint32_t i = 0; i < c.coord.vision_count; ++i) {
    if (c.coord.vision_tiles[i] >= kMapTiles) {
      return ImageError::kBadVisionList;
    }
  }
  // The watcher must outwait the supervisor tile's own watchdog and a boot, or both would reset it.
  if (c.agent.watcher != bsp::kNoTile &&
      (c.agent.watcher == c.agent.supervisor ||
       c.agent.watcher_timeout_ticks <= c.agent.watchdog_ticks + 2U * fdir::kAgentPeriodTicks)) {
    return ImageError::kBadConfig;
  }
  if (c.agent.watchdog_ticks < 2U * fdir::kAgentPeriodTicks || c.tile_health.max_resets == 0U ||
      c.tile_health.poll_ticks == 0U || c.tile_health.disagreements_to_fail == 0U ||
      (c.tile_health.self_test_ticks != 0U && c.tile_health.self_test_wait_ticks >= c.tile_health.self_test_ticks)) {
    return ImageError::kBadConfig;
  }
  if (c.sup.phase_count > kMaxPhases || c.sup.vision_min_half > c.sup.vision_min_full) {
    return ImageError::kBadConfig;
  }
  for (std::uint32_t i = 1U; i < c.sup.phase_count; ++i) {
    if (c.sup.phases[i].start_tick <= c.sup.phases[i - 1U].start_tick) {
      return ImageError::kBadConfig;  // phases in time order
    }
  }
  if (c.net_health.votes_to_fail < 2U || c.filter.matches_per_job == 0U ||
      c.filter.matches_per_job > kMaxMatchesPerFrame || !(c.coord.deadline_s > 0.0)) {
    return ImageError::kBadConfig;
  }
  return ImageError::kOk;
}

}  // namespace

ImageError configure_image(const ImageConfig& cfg) noexcept {
  const ImageError e = check(cfg);
  if (e == ImageError::kOk) {
    detail::g_image = cfg;
  }
  return e;
}

const ImageConfig& image_config() noexcept { return detail::g_image; }

fdir::TransitError tile_map_transits(const udn::FaultMap& map, std::uint64_t powered, std::uint64_t spares,
                                     std::uint32_t votes, fdir::TransitPlan& plan,
                                     std::uint64_t& subjects_out) noexcept {
  subjects_out = spares | fdir::under_observed(map, powered, votes);
  const std::uint64_t probers = powered & ~(std::uint64_t{1} << kCoordinatorTile) & ~(std::uint64_t{1} << kFilterTile);
  return fdir::plan_transits(map, probers, subjects_out, plan);
}

const char* role_name(Role r) noexcept {
  switch (r) {
    case Role::kTrnSupervisor: return "trn_supervisor";
    case Role::kVisionCoordinator: return "vision_coordinator";
    case Role::kFilterSupervisor: return "filter_supervisor";
    case Role::kIo: return "io";
    case Role::kFilter: return "filter";
    case Role::kFilterReplica: return "filter_replica";
    case Role::kVision: return "vision";
    case Role::kVisionSupervisor: return "vision_supervisor";
    case Role::kSpare: break;
  }
  return "spare";
}

char role_code(Role r) noexcept {
  switch (r) {
    case Role::kTrnSupervisor: return 'T';
    case Role::kVisionCoordinator: return 'V';
    case Role::kFilterSupervisor: return 'F';
    case Role::kIo: return 'I';
    case Role::kFilter: return 'N';
    case Role::kFilterReplica: return 'R';
    case Role::kVision: return 'v';
    case Role::kVisionSupervisor: return 'S';
    case Role::kSpare: break;
  }
  return '.';
}

k::TaskTable role_table(Role r) noexcept {
  switch (r) {
    case Role::kIo: return kIoRole;
    case Role::kFilter: return kFilterRole;
    case Role::kFilterReplica: return kReplicaRole;
    case Role::kVisionCoordinator: return kCoordinatorRole;
    case Role::kVision: return kVisionRole;
    case Role::kTrnSupervisor: return kSupervisorRole;
    case Role::kFilterSupervisor: return kFilterSupervisorRole;
    case Role::kVisionSupervisor: return kVisionSupervisorRole;
    case Role::kSpare: break;
  }
  return {};
}

void tile_map_vision_tiles(VisionCoordConfig& cfg, std::uint64_t exclude_mask) noexcept {
  cfg.vision_count = 0;
  for (std::uint32_t t = 0; t < kMapTiles && cfg.vision_count < kMaxVisionTiles; ++t) {
    if (kTileRoles[t] == Role::kVision && ((exclude_mask >> t) & 1ULL) == 0ULL) {
      cfg.vision_tiles[cfg.vision_count] = static_cast<bsp::TileId>(t);
      ++cfg.vision_count;
    }
  }
}

Role slot_role(std::uint32_t slot) noexcept {
  switch (slot) {
    case kSlotCoordinator: return Role::kVisionCoordinator;
    case kSlotIo: return Role::kIo;
    case kSlotFilter: return Role::kFilter;
    case kSlotReplica0:
    case kSlotReplica0 + 1U:
    case kSlotReplica0 + 2U: return Role::kFilterReplica;
    case kSlotVisionPool: return Role::kVision;
    case kSlotFilterSupervisor: return Role::kFilterSupervisor;
    case kSlotVisionSupervisor: return Role::kVisionSupervisor;
    default: return Role::kSpare;
  }
}

bsp::TileId slot_boot_tile(std::uint32_t slot) noexcept {
  switch (slot) {
    case kSlotCoordinator: return kCoordinatorTile;
    case kSlotIo: return kIoTile;
    case kSlotFilter: return kFilterTile;
    case kSlotReplica0: return kReplicaTiles[0];
    case kSlotReplica0 + 1U: return kReplicaTiles[1];
    case kSlotReplica0 + 2U: return kReplicaTiles[2];
    case kSlotFilterSupervisor: return kFilterSupervisorTile;
    case kSlotVisionSupervisor: return kVisionSupervisorTile;
    default: return bsp::kNoTile;
  }
}

bsp::TileId slot_tile_now(std::uint32_t slot) noexcept {
  if (slot >= udn::kRoleSlots) {
    return bsp::kNoTile;
  }
  const bsp::TileId t = udn::endpoint_roles_of(kSupervisorTile).tile[slot];
  return t == bsp::kNoTile ? slot_boot_tile(slot) : t;
}

void spare_boot_entry(bsp::TileId tile) noexcept {
  const k::TaskTable table = role_table(slot_role(fdir::boot_slot(tile)));
  if (table.empty()) {
    return;  // nothing assigned: the tile idles
  }
  (void)k::start(table, bsp::tick_cycles());
}

}  // namespace trn::tasks
