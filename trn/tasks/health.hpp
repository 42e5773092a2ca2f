/**
 * @file health.hpp
 * @brief Network health: every tile probes its mesh neighbours; the TRN supervisor tile votes
 *        the suspects and, when two neighbours agree, marks the switch failed in the fault map.
 *
 * Probing runs inside each tile's comm service (comm.hpp) every
 * kProbePeriodTicks: a neighbour that misses kProbeMissThreshold rounds is
 * reported to the health tile (kMsgSuspect on kChanControl). One report is
 * never enough: a tile that lost its own links would accuse all its
 * neighbours. The health task declares a switch failed once kVotesToFail
 * distinct neighbours report it, records it in the mission's fault map
 * (comm_set_fault_map: every node rebuilds its routes at its next tick, so
 * traffic goes around the failed switch through intermediate tiles), and logs
 * both steps. Reports about tiles that are switched off on purpose (spares)
 * are expected, as an off tile answers no ping, and are ignored.
 */
#pragma once

#include "bsp_tile64/port.hpp"
#include "kernel/task_table.hpp"

#include <array>
#include <cstdint>

namespace trn::tasks {

inline constexpr std::uint32_t kProbePeriodTicks = 10U;
inline constexpr std::uint32_t kProbeMissThreshold = 3U;
inline constexpr std::uint32_t kVotesToFail = 2U;
/** First word of a suspect report: [0] kMsgSuspect [1] reporter [2] suspect. */
inline constexpr std::uint32_t kMsgSuspect = 0x53555331U;  // "SUS1"
inline constexpr std::uint32_t kSuspectWords = 3U;

struct HealthConfig {
  std::uint32_t reserved = 0;  ///< the off-by-design tiles come from health_set_tile()
};

enum class HealthEventKind : std::uint8_t {
  kReport,        ///< a neighbour reported a suspect switch
  kSwitchFailed,  ///< enough neighbours agree: the switch is marked failed in the fault map
};

struct HealthEvent {
  bsp::Cycles cycle = 0;
  HealthEventKind kind = HealthEventKind::kReport;
  bsp::TileId suspect = bsp::kNoTile;
  bsp::TileId reporter = bsp::kNoTile;  ///< kReport: who; kSwitchFailed: the deciding vote
  std::uint32_t votes = 0;
  std::uint32_t map_version = 0;        ///< kSwitchFailed: fault-map version published
};

inline constexpr std::uint32_t kHealthEventCapacity = 64U;

/** Health task entry (arg: const HealthConfig*). */
void health_task_main(void* arg) noexcept;

/**
 * Tile the suspect reports go to and the tiles switched off by design (spares):
 * set by the image before boot (kNoTile: probing off). Off tiles are neither
 * probed (an off tile answers no ping, and pings would pile up in its queues
 * until they block the sender) nor voted on.
 */
void health_set_tile(bsp::TileId tile, std::uint64_t off_by_design) noexcept;
bsp::TileId health_tile() noexcept;
std::uint64_t health_off_tiles() noexcept;

/** Events written so far by the health task. [host] */
std::uint32_t health_event_count() noexcept;
/** Event @p i; false if overwritten or not written. [host] */
bool health_event(std::uint32_t i, HealthEvent* out) noexcept;

}  // namespace trn::tasks
