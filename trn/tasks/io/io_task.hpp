/**
 * @file io_task.hpp
 * @brief The I/O tile's device driver task: forwards IMU samples to the filter tile.
 */
#pragma once

#include "bsp_tile64/api/memory.hpp"
#include "bsp_tile64/api/port.hpp"

#include <array>
#include <cstddef>
#include <cstdint>

namespace trn::tasks {

/** Longest wait for a device interrupt between two check-ins with the health agent (ticks). */
inline constexpr std::uint32_t kIdleCheckinTicks = 20U;
/** Ticks a frame notice may wait for the network. */
inline constexpr std::uint32_t kNoticeTicks = 20U;

struct IoTaskConfig {
  bsp::TileId filter_tile = bsp::kNoTile;
  bsp::TileId coordinator_tile = bsp::kNoTile;  ///< frame notices go here (kNoTile: frames are not forwarded)
  /** The TRN supervisor: policy telecommands (codes from kCmdFirstPolicy) go here (kNoTile: they are dropped). */
  bsp::TileId trn_supervisor_tile = bsp::kNoTile;
  /** The filter supervisor (slot kSlotFilterSupervisor): told of a ground filter_tmr / filter_simplex, which it takes as its policy (kNoTile: nobody). */
  bsp::TileId filter_supervisor_tile = bsp::kNoTile;
};

struct IoTaskStats {
  std::uint32_t imu_forwarded;
  std::uint32_t send_failures;  ///< the network refused past the timeout
  std::uint32_t frames_forwarded;
  std::uint32_t frame_send_failures;
  std::uint32_t sup_commands;     ///< supervisor commands put into the filter's stream
  std::uint32_t policies;         ///< policy telecommands handed to the TRN supervisor
};

/** The I/O task's counters are emulated state through and through (bsp::ControlLayout). */
inline constexpr std::array kIoTaskStatsFields{
    BSP_CONTROL_STATE(IoTaskStats, imu_forwarded),       BSP_CONTROL_STATE(IoTaskStats, send_failures),
    BSP_CONTROL_STATE(IoTaskStats, frames_forwarded),    BSP_CONTROL_STATE(IoTaskStats, frame_send_failures),
    BSP_CONTROL_STATE(IoTaskStats, sup_commands),        BSP_CONTROL_STATE(IoTaskStats, policies),
};
inline constexpr bsp::ControlLayout kIoTaskStatsLayout{kIoTaskStatsFields, sizeof(IoTaskStats), alignof(IoTaskStats)};
static_assert(bsp::control_layout_ok(kIoTaskStatsLayout), "every member of IoTaskStats");
/** The I/O task's counters: a record in its tile's RAM, carved at task start (the host reads it by this name). */
inline constexpr bsp::RamRecord<IoTaskStats> kIoTaskStatsRecord{"io_stats", &kIoTaskStatsLayout};

/** Name of the I/O task's own state carve in its tile's RAM (the device semaphore), and its layout (what an upset of it does). [host] */
inline constexpr const char* kIoStateCarve = "io_state";
const bsp::ControlLayout& io_state_layout() noexcept;

/**
 * Task entry (arg: const IoTaskConfig*): activates the UDN, takes Irq::kDevice
 * through a kernel hook, and sends every IMU sample to the filter tile as it
 * arrives (raw UDN: a 100 Hz stream whose next sample supersedes a lost one),
 * and a notice of every frame to the vision coordinator (fault-tolerant UDN,
 * kChanControl; the I/O role then lists kCommTask). Counts in its record
 * (kIoTaskStatsRecord). Runs forever.
 */
void io_task_main(void* arg) noexcept;

}  // namespace trn::tasks
