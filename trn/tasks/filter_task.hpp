/**
 * @file filter_task.hpp
 * @brief The navigation filter task: 100 Hz on its tile, IMU from the I/O tile, a solution
 *        published every period.
 *
 * A periodic kernel task (period 10 ticks of 1 ms). Each job takes the IMU
 * samples that arrived over the UDN (tag kTagImu, bounded per job), steps the
 * EKF with each, charges the counted work with the board's cost model, and
 * publishes the navigation solution (the filter's output record, passed
 * through bsp::publish_filter so silent-data-corruption faults can hit it).
 * The EKF lives in the tile's RAM (carved at task start), like any state a
 * single-event upset could hit.
 */
#pragma once

#include "bsp_tile64/devices/camera_model.hpp"
#include "bsp_tile64/port.hpp"
#include "trn/filter/ekf.hpp"
#include "trn/filter/filter_config.hpp"
#include "trn/filter/nav_output.hpp"
#include "trn/filter/nav_state.hpp"

#include <cstdint>

namespace trn::tasks {

/** Publication channel of the navigation solution (bsp::publish_filter). */
inline constexpr std::uint32_t kNavChannel = 1;
/** IMU samples one job consumes at most (more wait for the next job). */
inline constexpr std::uint32_t kMaxImuPerJob = 4;

struct FilterTaskConfig {
  filter::FilterConfig filter{};
  bsp::CameraModel camera{};
  filter::InitialEstimate initial{};
};

struct FilterTaskStats {
  std::uint32_t jobs;
  std::uint32_t imu_used;        ///< samples integrated
  std::uint32_t imu_rejected;    ///< bad length or invalid status
  std::uint32_t filter_errors;   ///< steps that returned another error
  bsp::Cycles max_job_cycles;    ///< longest job, release to publication
  bsp::Cycles last_job_cycles;
};

/** Task entry (arg: const FilterTaskConfig*). Never returns unless set-up fails. */
void filter_task_main(void* arg) noexcept;

/** Counters of the filter task on @p tile. [host] */
FilterTaskStats filter_task_stats(bsp::TileId tile) noexcept;

/** The latest solution published by @p tile's filter; false before the first. [host] */
bool filter_task_output(bsp::TileId tile, filter::NavOutput* out) noexcept;

}  // namespace trn::tasks
