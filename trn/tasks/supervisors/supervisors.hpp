/**
 * @file supervisors.hpp
 * @brief The TRN supervisor tree on the fdir framework (fdir/supervisor.hpp): the TRN supervisor
 *        at the top (mission phases, ground policies, the escalations of its children), the
 *        filter supervisor (simplex or TMR) and the vision supervisor (capacity, image rate).
 *
 *   TRN supervisor (tile 0, beside the health tasks)
 *     |-- policy: reliability, power  --> filter supervisor (its own tile)
 *     |                                     commands the filter through the I/O tile's
 *     |                                     IMU stream (filter_tmr / filter_simplex),
 *     |                                     judges it from the filter's status (every 10 jobs)
 *     |-- policy: capacity (image rate) --> vision supervisor (its own tile)
 *                                           judges the healthy vision tiles the coordinator
 *                                           reports each frame; sets its image rate
 *
 * A phase's policies go down at its start; a telecommand (reliability_high,
 * ...) changes one at any time. A child that runs out of alternatives
 * escalates; the TRN supervisor then tries its own (reliability: accept the
 * simplex filter, reported; capacity: half the image rate) and, with none
 * left, reports safe mode to the vehicle (safe_mode). Faults a child handles
 * (a vision tile lost while enough stay healthy, a replica outvoted and
 * re-seeded) never reach the top. Every decision is an event.
 */
#pragma once

#include "bsp_tile64/api/memory.hpp"
#include "bsp_tile64/api/port.hpp"
#include "fdir/supervisor.hpp"

#include <array>
#include <cstddef>
#include <cstdint>

namespace trn::tasks {

/** Nodes of the tree (the events' subject). */
/** Ticks between two passes of a supervisor's loop. */
inline constexpr std::uint32_t kSupPeriodTicks = 10U;
/** Status reports (100 ms apart) the filter supervisor ignores after a command: TMR takes 3 jobs to establish, a stop 2. */
inline constexpr std::uint32_t kFilterSettle = 3U;
/**
 * Every this many ticks the TRN supervisor hands each child again the
 * policies it holds for it (kMsgPolicyHeld): a child restarted from its image
 * (which starts with no policy, or its default) takes them within this
 * period; a child that holds a policy (the same, or the ground's) changes nothing.
 */
inline constexpr std::uint32_t kPolicyRefreshTicks = 1000U;

inline constexpr std::uint8_t kNodeTrn = 0U;
inline constexpr std::uint8_t kNodeVision = 1U;
inline constexpr std::uint8_t kNodeFilter = 2U;

/** Alternatives (ids in sup_apply events; docs/FDIR.md has the table). */
enum Alternative : std::uint8_t {
  kAltDelegate = 1,       ///< hand the policy down to the child that owns it
  kAltSimplex = 2,        ///< the filter as one task
  kAltTmr = 3,            ///< the filter in TMR on its replicas
  kAltTmrReseed = 4,      ///< TMR started again from a fresh seed (simplex, then TMR)
  kAltFullRate = 5,       ///< every frame, on the healthy vision tiles
  kAltHalfRate = 6,       ///< every other frame: twice the time per frame for fewer tiles
  kAltAcceptSimplex = 7,  ///< the top lowers reliability to normal and reports it
  kAltReplicasOn = 8,     ///< the filter's replicas powered (idle while simplex)
  kAltReplicasParked = 9, ///< the replicas switched off while the filter is simplex, woken before TMR
};

inline constexpr std::uint32_t kMaxPhases = 8U;

/** One mission phase as the TRN supervisor holds it. */
struct PhaseSpec {
  std::uint32_t start_tick = 0U;  ///< mission tick it begins at (1 ms ticks)
  std::uint8_t reliability = fdir::kReliabilityNormal;
  std::uint8_t power = fdir::kPowerFull;
};

struct SupervisorsConfig {
  std::array<PhaseSpec, kMaxPhases> phases{};
  std::uint32_t phase_count = 0U;         ///< 0: no phase table (policies only by telecommand)
  bsp::TileId trn_supervisor_tile = bsp::kNoTile;    ///< the TRN supervisor's tile (escalations go there)
  bsp::TileId filter_supervisor_tile = bsp::kNoTile;  ///< boot tile of the filter supervisor (kNoTile: no tree)
  bsp::TileId vision_supervisor_tile = bsp::kNoTile;  ///< boot tile of the vision supervisor
  bsp::TileId io_tile = bsp::kNoTile;     ///< where the filter supervisor's commands enter the filter's stream
  bsp::TileId coordinator_tile = bsp::kNoTile;
  std::uint32_t vision_min_full = 30U;    ///< healthy vision tiles the full image rate needs
  std::uint32_t vision_min_half = 15U;    ///< ... and half the rate
  std::array<bsp::TileId, 3> replica_tiles{bsp::kNoTile, bsp::kNoTile, bsp::kNoTile};  ///< boot tiles of the replicas
  bsp::TileId health_tile = bsp::kNoTile; ///< the tile-health supervisor: switches tiles off and on
  /** Ticks before a phase that needs the replicas (reliability high) that the top asks for them powered. */
  std::uint32_t wake_lead_ticks = 1000U;
};

/** What each node did (host: summary.json, through kSupervisorStatsRecord). */
struct SupervisorStats {
  std::uint32_t policies = 0U;     ///< policies taken (phases, telecommands, the parent)
  std::uint32_t applied = 0U;      ///< alternatives applied
  std::uint32_t escalations = 0U;  ///< escalations sent up
  std::uint32_t phase = 0U;        ///< TRN: the phase now (index)
  std::uint32_t safe_mode = 0U;    ///< TRN: safe mode reports
  std::uint32_t commands = 0U;     ///< filter: commands sent to the filter
  std::uint32_t statuses = 0U;     ///< filter / vision: status reports judged
  std::uint32_t rate_div = 1U;     ///< vision: 1 every frame, 2 every other
  std::uint32_t parks = 0U;        ///< filter: replicas switched off at its request
  std::uint32_t wakes = 0U;        ///< filter: replicas switched on again
};

/** A node's counters are emulated state through and through (bsp::ControlLayout). */
inline constexpr std::array kSupervisorStatsFields{
    BSP_CONTROL_STATE(SupervisorStats, policies), BSP_CONTROL_STATE(SupervisorStats, applied),
    BSP_CONTROL_STATE(SupervisorStats, escalations), BSP_CONTROL_STATE(SupervisorStats, phase),
    BSP_CONTROL_STATE(SupervisorStats, safe_mode), BSP_CONTROL_STATE(SupervisorStats, commands),
    BSP_CONTROL_STATE(SupervisorStats, statuses), BSP_CONTROL_STATE(SupervisorStats, rate_div),
    BSP_CONTROL_STATE(SupervisorStats, parks), BSP_CONTROL_STATE(SupervisorStats, wakes),
};
inline constexpr bsp::ControlLayout kSupervisorStatsLayout{kSupervisorStatsFields, sizeof(SupervisorStats),
                                                          alignof(SupervisorStats)};
static_assert(bsp::control_layout_ok(kSupervisorStatsLayout), "every member of SupervisorStats");
/**
 * A node's counters: a record in the RAM of the tile the node runs on (one
 * node per tile), carved at task start (the host reads it by this name).
 */
inline constexpr bsp::RamRecord<SupervisorStats> kSupervisorStatsRecord{"sup_stats", &kSupervisorStatsLayout};

/** Task entries (arg: const SupervisorsConfig*). */
void trn_supervisor_main(void* arg) noexcept;
void filter_supervisor_main(void* arg) noexcept;
void vision_supervisor_main(void* arg) noexcept;

/**
 * Names of the nodes' state carves in their tiles' RAM (every node's, the TRN
 * supervisor's own, the filter supervisor's own) and their layouts (what an
 * upset of them does). [host]
 */
inline constexpr const char* kSupNodeCarve = "sup_node";
inline constexpr const char* kSupTrnCarve = "sup_trn";
inline constexpr const char* kSupFilterCarve = "sup_filter";
/** Carve of a supervisor's settings (its SupervisorsConfig, copied from the image, under a CRC-32C). */
inline constexpr const char* kSupSettingsCarve = "sup_settings";
const bsp::ControlLayout& sup_node_state_layout() noexcept;
const bsp::ControlLayout& sup_trn_state_layout() noexcept;
const bsp::ControlLayout& sup_filter_state_layout() noexcept;

/** The node specs of the tree (the plans of docs/FDIR.md). */
const fdir::SupervisorSpec& supervisor_spec(std::uint8_t node) noexcept;

}  // namespace trn::tasks
