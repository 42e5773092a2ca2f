/**
 * @file comm.hpp
 * @brief A tile's fault-tolerant messaging endpoint: its FtNode, the service task that runs
 *        the listener every tick, and interrupt-safe send and receive for the tile's tasks.
 *
 * Every TRN tile that talks over the fault-tolerant UDN runs the comm service
 * task (kCommTask: highest priority, period one tick) from its task table.
 * The node lives in the tile's RAM (carved at the service's start, so a
 * single-event upset can hit it like any tile state) and is reached through a
 * per-tile pointer. The tile's tasks share it, so every node operation runs
 * with interrupts masked: the tick that would preempt a task in the middle of
 * ft_send() waits until the call returns.
 *
 * The fault map the nodes build their routes from is the mission's, in shared
 * memory: the image sets it before boot and the health task when it votes a
 * switch failed (comm_set_fault_map); a node takes a newer version at its next
 * service tick. The service also probes the tile's mesh neighbours
 * (health.hpp) and reports suspects to the health tile.
 */
#pragma once

#include "bsp_tile64/port.hpp"
#include "kernel/task_table.hpp"
#include "udn/ft_link.hpp"
#include "udn/route.hpp"

#include <cstdint>
#include <span>

namespace trn::tasks {

/** The fault-tolerant messaging settings every TRN tile uses. */
inline constexpr udn::FtConfig kCommFtConfig{10U, 8U};  // detours re-injected by two tiles take several ticks per leg
/** Packets the service handles per tick at most. */
inline constexpr std::uint32_t kCommPacketsPerTick = 16U;

/** Sets the mission's fault map (host before boot, or the health task); @return its new version. */
std::uint32_t comm_set_fault_map(const udn::FaultMap& map) noexcept;

/** A copy of the mission's current fault map (all clear before any was set). */
udn::FaultMap comm_fault_map() noexcept;

/** Service task entry: opens the tile's node, then polls it every period. Arg unused. */
void comm_task_main(void* arg) noexcept;

/** True once the current tile's node is open (tasks wait for it at their start). [task] */
bool comm_ready() noexcept;

/** Waits (sleeping a tick at a time) up to @p max_ticks for the current tile's node. [task] */
bool comm_wait_ready(std::uint32_t max_ticks) noexcept;

/**
 * Sends @p words reliably to @p dest on @p channel from the current tile,
 * retrying each tick while the window or the network is full, for at most
 * @p max_ticks ticks. @return kOk, or the last error (kUnreachable at once).
 */
udn::FtError comm_send(bsp::TileId dest, std::uint32_t channel, std::span<const std::uint32_t> words,
                       std::uint32_t max_ticks) noexcept;

/** Pops the current tile's oldest message on @p channel. @return kOk or kEmpty (kBadArgs when closed). */
udn::FtError comm_receive(std::uint32_t channel, udn::FtMessage& out) noexcept;

/** The node of @p tile, or nullptr when it is not open. [host: statistics and events] */
const udn::FtNode* comm_node(bsp::TileId tile) noexcept;

/** The comm service's task table entry (priority 0, period 1, preemptive). */
inline constexpr k::TaskSpec kCommTask{"comm", &comm_task_main, nullptr, 0, 1, 0, 16U * 1024U,
                                       k::Policy::kPreemptive};

}  // namespace trn::tasks
