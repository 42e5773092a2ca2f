/**
 * @file vision_worker.hpp
 * @brief A vision tile: matches the landmarks of the work units the coordinator sends.
 *
 * Waits for units (kChanControl), matches each landmark (trn/vision/frame.hpp)
 * in the frame in shared DDR, charges the work, and answers with the matches
 * (kChanResult). At the coordinator's start it also relights the bands of the
 * coarse layer it is asked for (kMsgRelight) and answers when done; in a
 * coarse frame it computes the bands of the coarse surface it is sent
 * (kMsgCoarseBand) into its slot in DDR and answers with their digests.
 */
#pragma once

#include "bsp_tile64/api/camera_model.hpp"
#include "bsp_tile64/api/memory.hpp"
#include "bsp_tile64/api/port.hpp"

#include <array>
#include <cstddef>
#include <cstdint>

namespace trn::tasks {

struct VisionWorkerConfig {
  bsp::CameraModel camera{};
  double descent_sun_m[3] = {0.0, 0.0, 0.0};  ///< unit vector to the descent sun, map frame (mission knowledge)
  bsp::TileId coordinator_tile = bsp::kNoTile;
};

struct VisionWorkerStats {
  std::uint32_t units;
  std::uint32_t landmarks;
  std::uint32_t matches;
  std::uint32_t coarse_bands;  ///< bands of the coarse stage's surface computed (kMsgCoarseBand)
  std::uint32_t bad_units;
  std::uint32_t send_failed;
  std::uint32_t settings_rebuilt;  ///< checks that found its settings in RAM changed (built again, tile_settings_bad)
};

/** A vision task's counters are emulated state through and through (bsp::ControlLayout). */
inline constexpr std::array kVisionWorkerStatsFields{
    BSP_CONTROL_STATE(VisionWorkerStats, units),        BSP_CONTROL_STATE(VisionWorkerStats, landmarks),
    BSP_CONTROL_STATE(VisionWorkerStats, matches),      BSP_CONTROL_STATE(VisionWorkerStats, coarse_bands),
    BSP_CONTROL_STATE(VisionWorkerStats, bad_units),    BSP_CONTROL_STATE(VisionWorkerStats, send_failed),
    BSP_CONTROL_STATE(VisionWorkerStats, settings_rebuilt),
};
inline constexpr bsp::ControlLayout kVisionWorkerStatsLayout{kVisionWorkerStatsFields, sizeof(VisionWorkerStats),
                                                            alignof(VisionWorkerStats)};
static_assert(bsp::control_layout_ok(kVisionWorkerStatsLayout), "every member of VisionWorkerStats");
/** Name of the carve that holds a vision tile's settings (camera, sun) in its RAM (a plan's upset names it). */
inline constexpr const char* kWorkerSettingsCarve = "worker_settings";
/** A vision task's counters: a record in its tile's RAM, carved at task start (the host reads it by this name). */
inline constexpr bsp::RamRecord<VisionWorkerStats> kVisionWorkerStatsRecord{"worker_stats", &kVisionWorkerStatsLayout};

/** Vision tile entry (arg: const VisionWorkerConfig*). */
void vision_worker_main(void* arg) noexcept;

/** Name of a vision tile's task state carve, and its layout (bsp::ControlLayout: what an upset of it does). [host] */
inline constexpr const char* kVisionWorkerCarve = "vision_task";
const bsp::ControlLayout& vision_worker_state_layout() noexcept;

}  // namespace trn::tasks
