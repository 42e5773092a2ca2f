/**
 * @file roles.hpp
 * @brief The task tables of the tile roles that exist today: one constexpr table per role.
 *
 * The image (and integration tests) fill the role configurations before the
 * board boots, register each powered tile's table with k::set_task_table(),
 * and the kernel starts every tile from it. The mission's full tile map builds
 * on these tables.
 */
#pragma once

#include "kernel/task_table.hpp"
#include "udn/endpoint.hpp"
#include "trn/tasks/filter_task.hpp"
#include "trn/tasks/io_task.hpp"

namespace trn::tasks {

/** Configuration of every tile's messaging endpoint (boot map, probes, report tile, event sink); set before boot. */
extern udn::EndpointConfig g_endpoint_config;
/** The endpoint service every TRN tile runs first in its table. */
inline constexpr k::TaskSpec kCommTask = udn::endpoint_task_spec(&g_endpoint_config);

/** Configuration read by the I/O role's task; set before boot. */
extern IoTaskConfig g_io_role_config;
/** Configuration read by the filter role's task; set before boot. */
extern FilterTaskConfig g_filter_role_config;

/** I/O tile: the device driver, most urgent on its tile. */
inline constexpr k::TaskSpec kIoRole[] = {
    {"io", &io_task_main, &g_io_role_config, 1, 0, 0, 32U * 1024U, k::Policy::kPreemptive},
};

/**
 * Filter tile: the fault-tolerant messaging service (match batches in, solutions
 * out) and the navigation filter, 100 Hz (10 ticks of 1 ms), deadline one period.
 * The IMU still comes over the raw UDN from the I/O tile.
 */
inline constexpr k::TaskSpec kFilterRole[] = {
    kCommTask,
    {"filter", &filter_task_main, &g_filter_role_config, 2, 10, 10, 32U * 1024U, k::Policy::kPreemptive},
};

static_assert(k::check_table(kIoRole) == k::TableError::kOk);
static_assert(k::check_table(kFilterRole) == k::TableError::kOk);

}  // namespace trn::tasks
