/**
 * @file health_agent.hpp
 * @brief Core health, level 1: every tile's health agent, which kicks the tile's hardware
 *        watchdog while its watched tasks check in, reports the tile's boots and answers self-tests.
 *
 * Level 1, on every tile (health_agent_main, a periodic task): each watched
 * task (TaskSpec::watch_ticks > 0) checks in with k::checkin() within its
 * budget; the agent kicks the tile's hardware watchdog only while every
 * watched task is within budget. A task past its budget is written once as
 * kTaskOverdue and the kicks stop, so the hardware watchdog expires. At its
 * start the agent arms the watchdog and sends the supervisor a boot report
 * with the tile's reset cause (kMsgBooted on kFtChanHealth).
 *
 * The agent answers the supervisor's self-tests (fdir/tile_health.hpp) with
 * self_test_kernel over its resident pattern, and the agent of the tile named
 * watcher watches the supervisor's tile by its heartbeat (kMsgAlive). The
 * supervisor and the watcher are roles: each agent finds their tiles in the
 * role directory (supervisor_slot, watcher_slot), so both can move.
 */
#pragma once

#include "bsp_tile64/api/port.hpp"
#include "bsp_tile64/api/work.hpp"
#include "kernel/task_table.hpp"

#include <cstddef>
#include <cstdint>
#include <span>

namespace fdir {

/** Publication channel of a self-test digest (bsp::publish_filter: where corrupted outputs are injected). */
inline constexpr std::uint32_t kSelfTestChannel = 7U;

/** Bytes of the self-test's memory pattern each agent keeps in its tile's RAM (carve kSelfTestCarve). */
inline constexpr std::size_t kSelfTestPatternBytes = 4096U;
/** Name of the pattern's carve (a fault plan's `carve` aims an upset at it). */
inline constexpr const char* kSelfTestCarve = "self_test";

/** Writes the fixed self-test pattern (the same on every tile) into @p pattern. */
void self_test_pattern_fill(std::span<std::uint8_t> pattern) noexcept;

/**
 * The self-test kernel: from @p seed, a 6x6 double-precision matrix product
 * with accumulation (the filter's arithmetic), integer multiply-accumulates
 * over a pseudo-random byte image (the correlator's), and a weighted sum of
 * the tile's resident memory pattern @p pattern (kSelfTestPatternBytes, kept
 * in the tile's RAM between rounds: an upset there reaches the digest); the
 * digest is a CRC-32C of the results. Every healthy tile computes the same
 * digest for the same seed. Charges @p work.
 */
std::uint32_t self_test_kernel(std::uint32_t seed, std::span<const std::uint8_t> pattern, bsp::Work& work) noexcept;

/**
 * This tile's resident pattern, looked up in its RAM's carves (a reset
 * empties the RAM, and the agent carves it again); empty when none. [task]
 */
std::span<std::uint8_t> self_test_pattern(bsp::TileId self) noexcept;

/**
 * This tile's digest for @p seed, through its resident pattern, passed
 * through its publication channel (where a corrupted output is injected);
 * then the pattern is written anew (the scrub: a transient upset is gone by
 * the next round): the agent's answer, and the supervisor's own turn. [task]
 * @return false when the tile has no pattern.
 */
bool self_test_digest(bsp::TileId self, std::uint32_t seed, std::uint32_t& digest) noexcept;

struct HealthAgentConfig {
  bsp::TileId health_tile = bsp::kNoTile;  ///< tile of the tile-health supervisor (boot reports, watchdog monitor)
  /**
   * The supervisor's role slot in the role directory (kRoleSlots or more:
   * none): boot reports, self-test answers, the heartbeat and the watching
   * follow the role where it moves; @c health_tile is its tile until the
   * directory says otherwise.
   */
  std::uint32_t supervisor_slot = 0xFFFF'FFFFU;
  std::uint32_t watchdog_ticks = 20U;     ///< hardware watchdog timeout (>= 2 agent periods)
  bsp::TileId watcher_tile = bsp::kNoTile;     ///< tile whose agent watches the supervisor's tile (kNoTile: none)
  /**
   * The watcher's role slot in the role directory (udn::RoleDirectory;
   * kRoleSlots or more: none): where the role moves, the watching goes with
   * it; @c watcher_tile is its tile until the directory says otherwise.
   */
  std::uint32_t watcher_slot = 0xFFFF'FFFFU;
  /** A supervisor heartbeat missing this long is named and its tile reset (> watchdog_ticks + a boot). */
  std::uint32_t watcher_timeout_ticks = 40U;
  std::uint32_t max_watcher_resets = 3U;  ///< resets of the supervisor's tile by the watcher over the mission
  /**
   * The spare kept for the supervisor's role (kNoTile: none). A supervisor
   * still silent a whole timeout after the watcher's reset, to the tiles
   * beside it too, is no hang: the watcher switches its tile off and this
   * one on, with the supervisor's slot as its boot slot (kSupervisorMoved).
   */
  bsp::TileId standby = bsp::kNoTile;
};

/** Agent period: it looks at the check-ins and kicks every this many ticks. */
inline constexpr std::uint32_t kAgentPeriodTicks = 5U;

/** The health agent's task entry (arg: const HealthAgentConfig*). */
void health_agent_main(void* arg) noexcept;

/** The agent's task row for a role's table: just below the messaging service. */
constexpr k::TaskSpec health_agent_task_spec(HealthAgentConfig* cfg) noexcept {
  return k::TaskSpec{"health", &health_agent_main, cfg, 1, kAgentPeriodTicks, 0, 16U * 1024U,
                     k::Policy::kPreemptive, 0U};
}

}  // namespace fdir
