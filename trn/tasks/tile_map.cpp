/**
 * @file tile_map.cpp
 * @brief Role names, role task tables and the configurations they point to.
 */
#include "trn/tasks/tile_map.hpp"

#include "trn/tasks/roles.hpp"

namespace trn::tasks {

VisionCoordConfig g_coord_config{};
VisionWorkerConfig g_vision_config{};
IoTaskConfig g_io_mission_config{};
fdir::NetHealthConfig g_net_health_config{};

const char* role_name(Role r) noexcept {
  switch (r) {
    case Role::kTrnSupervisor: return "trn_supervisor";
    case Role::kVisionCoordinator: return "vision_coordinator";
    case Role::kFilterSupervisor: return "filter_supervisor";
    case Role::kIo: return "io";
    case Role::kFilter: return "filter";
    case Role::kVision: return "vision";
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
    case Role::kVision: return 'v';
    case Role::kSpare: break;
  }
  return '.';
}

k::TaskTable role_table(Role r) noexcept {
  switch (r) {
    case Role::kIo: return kIoMissionRole;
    case Role::kFilter: return kFilterRole;
    case Role::kVisionCoordinator: return kCoordinatorRole;
    case Role::kVision: return kVisionRole;
    case Role::kTrnSupervisor: return kSupervisorRole;
    case Role::kFilterSupervisor:
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

}  // namespace trn::tasks
