/**
 * @file io_task.hpp
 * @brief The I/O tile's device driver task: forwards IMU samples to the filter tile.
 */
#pragma once

#include "bsp_tile64/port.hpp"

#include <cstdint>

namespace trn::tasks {

struct IoTaskConfig {
  bsp::TileId filter_tile = bsp::kNoTile;
};

struct IoTaskStats {
  std::uint32_t imu_forwarded;
  std::uint32_t send_failures;  ///< the network refused past the timeout
};

/**
 * Task entry (arg: const IoTaskConfig*): activates the UDN, takes Irq::kDevice
 * through a kernel hook, and sends every IMU sample to the filter tile as it
 * arrives. Runs forever.
 */
void io_task_main(void* arg) noexcept;

/** Counters of the I/O task on the current board. [host] */
IoTaskStats io_task_stats() noexcept;

}  // namespace trn::tasks
