/**
 * @file tile_map.cpp
 * @brief Role names, role task tables and the configurations they point to.
 */
#include "trn/tasks/tile_map.hpp"

#include "trn/tasks/fdir_params.hpp"

#include "fdir/tile_health.hpp"
#include "kernel/kernel.hpp"
#include "trn/tasks/messages.hpp"
#include "udn/endpoint.hpp"

#include <string_view>

namespace trn::tasks {

namespace detail {
ImageConfig g_image{};
}  // namespace detail

namespace {

/** A tile a role sends to: on @p d's chip, or kNoTile (none: a role that is not flown). */
bool tile_ok(const Deployment& d, bsp::TileId t) noexcept { return t < d.tiles() || t == bsp::kNoTile; }

/** The first tile of the configuration that is off the chip, and in @p what its name. */
ImageError check_tiles(const ImageConfig& c, const char*& what) noexcept {
  bool known = false;
  for (const Deployment* d : kDeployments) {
    known = known || d == c.deployment;
  }
  if (!known) {
    what = "deployment";
    return ImageError::kBadTile;
  }
  const Deployment& d = *c.deployment;
  for (const Wire& w : kWiring) {
    if (!tile_ok(d, w.get(c))) {
      what = w.field;
      return ImageError::kBadTile;
    }
  }
  for (const bsp::TileId t : c.endpoint.roles.tile) {
    if (!tile_ok(d, t)) {
      what = "endpoint.roles";
      return ImageError::kBadTile;
    }
  }
  for (const bsp::TileId t : c.tile_health.slot_spare) {
    if (!tile_ok(d, t)) {
      what = "tile_health.slot_spare";
      return ImageError::kBadTile;
    }
  }
  what = "coord.vision_tiles";
  if (c.coord.vision_count > kMaxVisionTiles) {
    return ImageError::kBadVisionList;
  }
  for (std::uint32_t i = 0; i < c.coord.vision_count; ++i) {
    if (c.coord.vision_tiles[i] >= d.tiles()) {
      return ImageError::kBadVisionList;
    }
  }
  what = nullptr;
  return ImageError::kOk;
}

/** The first value of the configuration out of its range or its ties to others, and in @p what its name. */
ImageError check_values(const ImageConfig& c, const char*& what) noexcept {
  if (const FdirParam* p = fdir_param_out_of_range(c); p != nullptr) {
    what = p->name;
    return ImageError::kBadConfig;
  }
  // The watcher must outwait the supervisor tile's own watchdog and a boot, or both would reset it.
  what = "agent.watcher_tile";
  if (c.agent.watcher_tile != bsp::kNoTile && c.agent.watcher_tile == c.agent.health_tile) {
    return ImageError::kBadConfig;
  }
  what = "agent.watcher_timeout_ticks";
  if (c.agent.watcher_tile != bsp::kNoTile &&
      c.agent.watcher_timeout_ticks <= c.agent.watchdog_ticks + 2U * fdir::kAgentPeriodTicks) {
    return ImageError::kBadConfig;
  }
  what = "tile_health.self_test_wait_ticks";
  if (c.tile_health.self_test_ticks != 0U && c.tile_health.self_test_wait_ticks >= c.tile_health.self_test_ticks) {
    return ImageError::kBadConfig;
  }
  what = "sup.vision_min_half";
  if (c.sup.vision_min_half > c.sup.vision_min_full) {
    return ImageError::kBadConfig;
  }
  what = "sup.phases";
  if (c.sup.phase_count > kMaxPhases) {
    return ImageError::kBadConfig;
  }
  for (std::uint32_t i = 1U; i < c.sup.phase_count; ++i) {
    if (c.sup.phases[i].start_tick <= c.sup.phases[i - 1U].start_tick) {
      return ImageError::kBadConfig;  // phases in time order
    }
  }
  what = "filter.matches_per_job";
  if (c.filter.matches_per_job == 0U || c.filter.matches_per_job > kMaxMatchesPerFrame) {
    return ImageError::kBadConfig;
  }
  what = "coord.deadline_s";
  if (!(c.coord.deadline_s > 0.0)) {
    return ImageError::kBadConfig;
  }
  what = nullptr;
  return ImageError::kOk;
}

}  // namespace

ImageError configure_image(const ImageConfig& cfg, const char** what) noexcept {
  const char* fault = nullptr;
  ImageError e = check_tiles(cfg, fault);
  if (e == ImageError::kOk) {
    e = check_values(cfg, fault);
  }
  if (e == ImageError::kOk) {
    detail::g_image = cfg;
  }
  if (what != nullptr) {
    *what = fault;
  }
  return e;
}

const ImageConfig& image_config() noexcept { return detail::g_image; }

fdir::TransitError tile_map_transits(const Deployment& d, const udn::FaultMap& map, std::uint64_t powered,
                                     std::uint64_t spares, std::uint32_t votes, fdir::TransitPlan& plan,
                                     std::uint64_t& subjects_out) noexcept {
  subjects_out = spares | fdir::under_observed(map, powered, votes);
  const std::uint64_t probers = powered & ~(std::uint64_t{1} << boot_tile(d, Role::kVisionCoordinator)) &
                                ~(std::uint64_t{1} << boot_tile(d, Role::kFilter));
  return fdir::plan_transits(map, probers, subjects_out, plan);
}

const char* role_name(Role r) noexcept { return role_decl(r).name; }

char role_code(Role r) noexcept { return role_decl(r).code; }

const Deployment* find_deployment(const char* name) noexcept {
  if (name == nullptr) {
    return nullptr;
  }
  for (const Deployment* d : kDeployments) {
    if (std::string_view(d->chip) == std::string_view(name)) {
      return d;
    }
  }
  return nullptr;
}

void wire_image(ImageConfig& cfg, const Deployment& d) noexcept {
  cfg.deployment = &d;
  for (const Wire& w : kWiring) {
    w.set(cfg) = boot_tile(d, w.to, w.index);
  }
  for (std::uint32_t slot = 0; slot < udn::kRoleSlots; ++slot) {
    cfg.endpoint.roles.tile[slot] = slot_boot_tile(d, slot);
    cfg.tile_health.slot_spare[slot] = bsp::kNoTile;
  }
  for (const Placement& p : d.placements) {
    if (p.slot < udn::kRoleSlots) {
      cfg.tile_health.slot_spare[p.slot] = p.backup;
    }
  }
  cfg.agent.watcher_slot = kSlotIo;  // the watcher is the I/O role (kWiring's agent.watcher_tile)
  // Reports, boot reports and the watching follow the TRN supervisor's tile where its watcher moves it.
  cfg.agent.supervisor_slot = kSlotTrnSupervisor;
  cfg.endpoint.report_slot = kSlotTrnSupervisor;
  cfg.agent.standby = backup_tile(d, Role::kTrnSupervisor);
  cfg.tile_health.own_slot = kSlotTrnSupervisor;
}

void tile_map_vision_tiles(const Deployment& d, VisionCoordConfig& cfg, std::uint64_t exclude_mask) noexcept {
  cfg.vision_count = 0;
  for (std::uint32_t t = 0; t < d.tiles() && cfg.vision_count < kMaxVisionTiles; ++t) {
    if (tile_role(d, t) == Role::kVision && ((exclude_mask >> t) & 1ULL) == 0ULL) {
      cfg.vision_tiles[cfg.vision_count] = static_cast<bsp::TileId>(t);
      ++cfg.vision_count;
    }
  }
}

Role slot_role(std::uint32_t slot) noexcept {
  if (slot == kSlotVisionPool) {
    return Role::kVision;
  }
  if (slot == kNoSlot) {
    return Role::kSpare;
  }
  for (const Placement& p : detail::g_image.deployment->placements) {
    if (p.slot == slot) {
      return p.role;
    }
  }
  return Role::kSpare;
}

bsp::TileId slot_boot_tile(const Deployment& d, std::uint32_t slot) noexcept {
  if (slot == kNoSlot) {
    return bsp::kNoTile;
  }
  for (const Placement& p : d.placements) {
    if (p.slot == slot) {
      return p.tile;
    }
  }
  return bsp::kNoTile;
}

bsp::TileId slot_tile_now(std::uint32_t slot) noexcept {
  if (slot >= udn::kRoleSlots) {
    return bsp::kNoTile;
  }
  // The newest move any open endpoint holds (the most holders among equals): the supervisor's own
  // directory starts again from the boot one when its tile is reset, while the others keep theirs.
  const Deployment& dep = *detail::g_image.deployment;
  const std::uint32_t tiles = dep.tiles();
  std::array<bsp::TileId, kMapTiles> tile{};
  std::array<std::uint32_t, kMapTiles> version{};
  for (bsp::TileId e = 0; e < tiles; ++e) {
    const udn::RoleDirectory d = udn::endpoint_roles_of(e);
    tile[e] = d.tile[slot];
    version[e] = d.version[slot];
  }
  bsp::TileId best = bsp::kNoTile;
  std::uint32_t best_version = 0U;
  std::uint32_t best_holders = 0U;
  for (bsp::TileId e = 0; e < tiles; ++e) {
    if (tile[e] == bsp::kNoTile) {
      continue;
    }
    std::uint32_t holders = 0U;
    for (bsp::TileId o = 0; o < tiles; ++o) {
      holders += tile[o] == tile[e] && version[o] == version[e] ? 1U : 0U;
    }
    if (best == bsp::kNoTile || version[e] > best_version || (version[e] == best_version && holders > best_holders)) {
      best = tile[e];
      best_version = version[e];
      best_holders = holders;
    }
  }
  return best == bsp::kNoTile ? slot_boot_tile(dep, slot) : best;
}

void spare_boot_entry(bsp::TileId tile) noexcept {
  const k::TaskTable table = role_table(slot_role(fdir::boot_slot(tile)));
  if (table.empty()) {
    return;  // nothing assigned: the tile idles
  }
  (void)k::start(table, bsp::tick_cycles());
}

}  // namespace trn::tasks
