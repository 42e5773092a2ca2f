/**
 * @file endpoint.hpp
 * @brief A tile's fault-tolerant messaging endpoint: its node and fault map in tile RAM, the
 *        service task that polls it when packets arrive and probes the neighbours, and send and
 *        receive for the tile's tasks.
 *
 * Every tile that talks over the fault-tolerant UDN runs the endpoint service
 * task (endpoint_task_spec: highest priority) from its task table, with one
 * EndpointConfig set by the image before boot. The service is event-driven:
 * it polls the node when the tile's UDN interrupt says a packet arrived, at
 * each tick with a probe or a transit ping, and every tick while the node has
 * packets in flight or owes an answer; otherwise it sleeps (at most
 * kCommMaxSleepTicks), and so does a tickless tile with nothing else to do. The endpoint's
 * state (FtNode, the tile's copy of the fault map, the probe) is carved in the
 * tile's RAM at the service's start, so an upset can hit it and a restart
 * starts it afresh from the boot map. The tile's tasks share it, so every node
 * operation runs with interrupts masked.
 *
 * Fault map by message: a newer map arrives on kFtChanMap (from the health
 * tile, or from a neighbour) and the service rebuilds the routes from it. A
 * tile that missed an update catches up through the probes: PING and PONG carry
 * the sender's map version, and a tile that hears an older version from a
 * neighbour sends that neighbour its own map (once per version).
 *
 * Roles, not tiles: a message to a role (the filter, the coordinator) goes
 * through the role directory, the paper's destination index over the cores
 * that run: slot -> tile. Every tile starts from config.roles; a supervisor
 * that moves a role to a spare sends each tile a role move (kMsgRoleMove on
 * kFtChanMap) and the service applies the newest move of each slot, so
 * senders follow a move without knowing tile numbers.
 *
 * Reports: the probe's suspects go to config.health_tile on kFtChanFdir
 * (kMsgSuspect), and so do the transit probes' targets lost or back
 * (kMsgTransit), each by its route and, as a copy, through a twin whose way
 * shares no switch and no link with it (route_twin_via): one failed switch
 * or link cannot keep them from the health tile. Events (corrections,
 * resends, suspects, maps applied) go to config.sink. The endpoint never
 * includes the layers above it.
 */
#pragma once

#include "bsp_tile64/api/port.hpp"
#include "kernel/task_table.hpp"
#include "udn/ft_link.hpp"
#include "udn/route.hpp"

#include <array>
#include <cstdint>
#include <span>

namespace udn {

/** Role slots of the directory (logical destinations the image names). */
inline constexpr std::uint32_t kRoleSlots = 9U;

/** Where each role slot runs. kNoTile: the slot is not used. */
struct RoleDirectory {
  std::array<bsp::TileId, kRoleSlots> tile = [] {
    std::array<bsp::TileId, kRoleSlots> t{};
    t.fill(bsp::kNoTile);
    return t;
  }();
  std::array<std::uint32_t, kRoleSlots> version{};  ///< moves of each slot so far
};

struct EndpointConfig {
  FtConfig ft{10U, 8U};  ///< detours re-injected by two tiles take several ticks per leg
  std::uint32_t packets_per_tick = 16U;
  FaultMap boot_map{};                  ///< the map every tile starts from (cols 0: all clear on the network's grid)
  bsp::TileId health_tile = bsp::kNoTile; ///< suspect reports go here (kNoTile: no probing)
  /**
   * The role slot of the tile reports go to (kRoleSlots or more: none):
   * where the directory has that role, reports follow it; health_tile is its
   * tile until the directory says otherwise.
   */
  std::uint32_t report_slot = 0xFFFF'FFFFU;
  std::uint64_t not_probed = 0U;        ///< tiles off by design (spares): they answer no ping
  std::uint32_t probe_period_ticks = 10U;
  std::uint32_t probe_miss_threshold = 3U;
  /**
   * Transit probes: bit b of transit_targets[t] makes tile t ping tile b
   * straight once per probe period, testing the switches between them (at
   * most kMaxTransitTargets per tile and probe_period_ticks - 1; planned by
   * fdir/transit.hpp). Each transit has its own tick of the period.
   */
  std::array<std::uint64_t, kRouteMaxTiles> transit_targets{};
  FtEventSink sink{};
  RoleDirectory roles{};  ///< the boot directory: where each role slot starts
};

/** Transit targets one tile pings at most. */
inline constexpr std::uint32_t kMaxTransitTargets = 4U;

/*
 * Message layouts. Each message has a pack_ that writes it and an unpack_
 * that reads received words: unpack_ returns false, with its output left as
 * it was, unless the words are exactly that message with every field in the
 * range documented here (endpoint_messages.cpp; tests/fuzz/flight_msg_fuzz.cpp
 * checks both directions).
 */

/** Suspect report (kFtChanFdir): [0] kMsgSuspect [1] reporter [2] suspect, two different tiles below kRouteMaxTiles. */
inline constexpr std::uint32_t kMsgSuspect = 0x53555331U;  // "SUS1"
inline constexpr std::uint32_t kSuspectWords = 3U;
struct SuspectReport {
  bsp::TileId reporter = 0U;
  bsp::TileId suspect = 0U;
};
void pack_suspect(const SuspectReport& r, std::span<std::uint32_t, kSuspectWords> w) noexcept;
[[nodiscard]] bool unpack_suspect(std::span<const std::uint32_t> w, SuspectReport& out) noexcept;

/**
 * Transit report (kFtChanFdir): [0] kMsgTransit [1] prober [2] target (tiles
 * below kRouteMaxTiles) [3] 1 lost, 0 answers again.
 */
inline constexpr std::uint32_t kMsgTransit = 0x54524E31U;  // "TRN1"
inline constexpr std::uint32_t kTransitWords = 4U;
struct TransitReport {
  bsp::TileId prober = 0U;
  bsp::TileId target = 0U;
  bool lost = false;
};
void pack_transit(const TransitReport& r, std::span<std::uint32_t, kTransitWords> w) noexcept;
[[nodiscard]] bool unpack_transit(std::span<const std::uint32_t> w, TransitReport& out) noexcept;

/**
 * Fault map (kFtChanMap), kFaultMapWords words:
 *   [0] kMsgFaultMap [1] version [2] cols [3] rows [4..5] failed tiles [6..7] no-forward tiles
 *   [8..23] failed links, four tiles per word (tile 4i + k in bits 8k .. 8k + 7 of word 8 + i).
 */
inline constexpr std::uint32_t kMsgFaultMap = 0x464D4150U;  // "FMAP"
inline constexpr std::uint32_t kFaultMapWords = 8U + kRouteMaxTiles / 4U;

void pack_fault_map(const FaultMap& map, std::span<std::uint32_t, kFaultMapWords> w) noexcept;
/** @return false if @p w is not a fault map message of a grid of at most kRouteMaxTiles tiles. */
[[nodiscard]] bool unpack_fault_map(std::span<const std::uint32_t> w, FaultMap& map) noexcept;

/**
 * Role move (kFtChanMap): [0] kMsgRoleMove [1] slot (below kRoleSlots) [2] tile
 * (below kRouteMaxTiles) [3] the slot's version after the move (not 0: the boot directory's).
 */
inline constexpr std::uint32_t kMsgRoleMove = 0x524F4C45U;  // "ROLE"
inline constexpr std::uint32_t kRoleMoveWords = 4U;
struct RoleMove {
  std::uint32_t slot = 0U;
  bsp::TileId tile = 0U;
  std::uint32_t version = 0U;
};
void pack_role_move(const RoleMove& m, std::span<std::uint32_t, kRoleMoveWords> w) noexcept;
[[nodiscard]] bool unpack_role_move(std::span<const std::uint32_t> w, RoleMove& out) noexcept;

/**
 * Parked tiles (kFtChanMap): [0] kMsgParked [1..2] the tiles switched off by
 * the power policy, low word first [3] serial (newer wins). A parked tile is
 * off by design like a spare: not pinged, not a transit target; its switch
 * still routes. A tile that leaves the set is probed again from scratch.
 */
inline constexpr std::uint32_t kMsgParked = 0x50524B31U;  // "PRK1"
inline constexpr std::uint32_t kParkedWords = 4U;
struct ParkedSet {
  std::uint64_t tiles = 0U;  ///< bit per tile
  std::uint32_t serial = 0U; ///< not 0: the boot state's
};
void pack_parked(const ParkedSet& p, std::span<std::uint32_t, kParkedWords> w) noexcept;
[[nodiscard]] bool unpack_parked(std::span<const std::uint32_t> w, ParkedSet& out) noexcept;

/** Applies a parked set on this tile's endpoint (what a kMsgParked message does). [task] @return false if older or closed. */
bool endpoint_set_parked(std::uint64_t parked, std::uint32_t serial) noexcept;

/** Service task entry (arg: const EndpointConfig*): opens the node, then serves it every tick. */
void endpoint_task_main(void* arg) noexcept;

/** The service's check-in budget with the tile's health agent (it checks in at every pass). */
inline constexpr std::uint32_t kCommWatchTicks = 20U;

/** The service's longest sleep: half its check-in budget. */
inline constexpr std::uint32_t kCommMaxSleepTicks = kCommWatchTicks / 2U;

/**
 * Probe rounds between two sendings of a suspicion or a lost transit that
 * still holds. The health tile's votes live in its RAM: a reset of that tile
 * (its watchdog, its watcher) starts them afresh, and a report sent once
 * before it would never count again. The health tile takes a repeated report
 * as nothing new.
 */
inline constexpr std::uint32_t kReReportRounds = 20U;

/** The service task's table entry for @p cfg (priority 0, event-driven, preemptive). */
constexpr k::TaskSpec endpoint_task_spec(EndpointConfig* cfg) noexcept {
  return k::TaskSpec{"comm", &endpoint_task_main, cfg, 0, 0, 0, 16U * 1024U, k::Policy::kPreemptive, kCommWatchTicks};
}

/** True once the current tile's endpoint is open. [task] */
bool endpoint_ready() noexcept;

/** Waits (sleeping a tick at a time) up to @p max_ticks for the current tile's endpoint. [task] */
bool endpoint_wait_ready(std::uint32_t max_ticks) noexcept;

/**
 * Sends @p words reliably to @p dest on @p channel from the current tile,
 * retrying each tick while the window or the network is full, for at most
 * @p max_ticks ticks (0: one attempt, never a wait).
 * @return kOk, or the last error (kUnreachable at once).
 */
[[nodiscard]] FtError endpoint_send(bsp::TileId dest, std::uint32_t channel, std::span<const std::uint32_t> words,
                                    std::uint32_t max_ticks) noexcept;

/** Pops the current tile's oldest message on @p channel. @return kOk or kEmpty (kBadArgs when closed). */
[[nodiscard]] FtError endpoint_receive(std::uint32_t channel, FtMessage& out) noexcept;

/**
 * Sleeps the calling task until a message is delivered on @p channel, at most
 * @p max_ticks ticks; returns at once if one is waiting. A wake-up says only
 * "look again": endpoint_receive() tells what is there. [task]
 * @return false if the endpoint is closed or the channel is not a task's.
 */
bool endpoint_wait(std::uint32_t channel, std::uint32_t max_ticks) noexcept;

/**
 * Installs @p map on the current tile if it is newer than the tile's copy (the
 * health tile applies its own decisions this way). @return kOk, or kBadArgs
 * when the endpoint is closed or the map does not fit the grid. [task]
 */
[[nodiscard]] FtError endpoint_install_map(const FaultMap& map) noexcept;

/**
 * The tile the current tile's directory names for @p slot; @p fallback when the
 * slot is out of range or unused, or the endpoint is closed. [task]
 */
[[nodiscard]] bsp::TileId endpoint_role_tile(std::uint32_t slot, bsp::TileId fallback) noexcept;

/**
 * Applies a move of @p slot to @p tile with @p version on the current tile if it
 * is newer than the tile's entry (the supervisor applies its own moves this
 * way). @return true if applied. [task]
 */
bool endpoint_move_role(std::uint32_t slot, bsp::TileId tile, std::uint32_t version) noexcept;

/** The current tile's copy of the role directory (empty when the endpoint is closed). [task] */
[[nodiscard]] RoleDirectory endpoint_roles() noexcept;

/** The role directory of @p tile's endpoint (empty when closed). [host] */
RoleDirectory endpoint_roles_of(bsp::TileId tile) noexcept;

/**
 * Whether the current tile hears nobody: it probes at least one neighbour or
 * transit target other than @p besides, and every one of them is reported
 * silent (a neighbour) or lost (a transit). A tile whose own switch failed
 * sees exactly this; a tile whose one probed neighbour hung still hears its
 * transits. @p besides leaves out the tile whose silence is in question (a
 * watcher beside the supervisor's tile must not take that tile's silence for
 * its own). False when the endpoint is closed or not probing. [task]
 */
[[nodiscard]] bool endpoint_cut_off(bsp::TileId besides = bsp::kNoTile) noexcept;

/** What the current tile's neighbour probe says of one tile (endpoint_hears). */
enum class Heard : std::uint8_t {
  kAnswers,    ///< its pings are answered (one lost in a row at most): its core runs, its switch routes
  kSilent,     ///< its last two pings or more went unanswered
  kNotProbed,  ///< not a neighbour this tile probes (off the grid, a spare, failed, or the endpoint closed)
};

/** Whether the current tile's probe hears neighbour @p tile (a second opinion on a silent tile). [task] */
[[nodiscard]] Heard endpoint_hears(bsp::TileId tile) noexcept;

/** The current tile's copy of the fault map (the boot map before the endpoint opens). [task] */
[[nodiscard]] FaultMap endpoint_fault_map() noexcept;

/** Name of the endpoint's carve in its tile's RAM, and the endpoint's layout (bsp::ControlLayout). [host] */
inline constexpr const char* kEndpointCarve = "endpoint";
const bsp::ControlLayout& endpoint_state_layout() noexcept;

/** The node of @p tile, or nullptr when it is not open. [host: statistics] */
const FtNode* endpoint_node(bsp::TileId tile) noexcept;

/** Fault-map version @p tile routes by (0 when closed). [host] */
std::uint32_t endpoint_map_version(bsp::TileId tile) noexcept;

}  // namespace udn
