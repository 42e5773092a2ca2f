/**
 * @file filter_task.hpp
 * @brief The navigation filter task: 100 Hz on its tile, IMU from the I/O tile, landmark match
 *        batches from the vision coordinator, a solution published and sent every period.
 *
 * A periodic kernel task (period 10 ticks of 1 ms) on a tile whose table also
 * runs the fault-tolerant messaging service (kCommTask). Each job:
 *  1. takes the IMU samples that arrived on kChanImu (fault-tolerant UDN,
 *     bounded per job) and propagates the EKF with each;
 *  2. takes the match-batch parts waiting on kChanMatches into a queue in tile
 *     RAM (two frames; on overflow the oldest frame's remainder is dropped);
 *  3. applies at most matches_per_job queued matches, each at its image time
 *     (the EKF's pose history: matches arrive 0.2-0.8 s after the image);
 *  4. publishes the solution (bsp::publish_filter, where silent-data-corruption
 *     faults hit it) and sends it to coordinator_tile on kChanNav without waiting.
 * The counted work is charged with the board's cost model. The EKF, the
 * queue, the task's own state (kFilterTaskCarve) and the latest solution
 * delivered (kFilterOutputRecord) live in the tile's RAM (carved at task
 * start), like any state a single-event upset could hit. How many matches a job applies depends only
 * on the queue, never on timing, so replicas fed the same parts stay in step.
 *
 * Restarts (trn/tasks/filter/filter_checkpoint.hpp): every checkpoint_every jobs the
 * whole state goes to DDR. A task that starts and finds a good checkpoint,
 * on whatever tile (after a reset, or as a spare that took the role over),
 * resumes from it (kFilterResumed) instead of the initial estimate, and
 * replays the IMU samples it missed from the I/O tile's DDR record
 * (trn/tasks/io/imu_ring.hpp), at most kMaxReplayPerJob per job, before the live
 * ones; a live sample already replayed is skipped, and a gap in the live
 * stream is filled from the record too. Samples the record no longer holds
 * are reported (kImuGap).
 *
 * Plausibility (trn/filter/state_check.hpp): running alone (simplex), the
 * task checks the state after every job against the one before it and the
 * vehicle's envelope. A state that fails is not delivered
 * (kFilterStateBad); the task goes back to its last checkpoint and replays
 * the IMU samples since from the record, as after a restart (kFilterResumed).
 * Refused again from that checkpoint (what is wrong is outside the state a
 * checkpoint holds), it asks for its tile's restart (kAssertFilterStateRefused:
 * the health agent stops kicking the watchdog). In TMR the vote does this work.
 *
 * Settings: running alone, the task also checks after every job that the
 * EKF's settings in RAM (configuration, camera, process noise: written at
 * set-up, never by a job, not in a checkpoint) still have the CRC-32C they
 * had when built. Changed (an upset), the job's solution is not delivered
 * (kFilterSettingsBad), the settings are built again from the task's
 * configuration in the image, and the task goes back to its last checkpoint
 * (kFilterResumed): the states since the upset were computed with them.
 * Changed again before a newer checkpoint, the tile asks for its restart
 * (kAssertFilterSettingsChanged).
 */
#pragma once

#include "bsp_tile64/api/camera_model.hpp"
#include "bsp_tile64/api/memory.hpp"
#include "bsp_tile64/api/port.hpp"
#include "fdir/innovation_monitor.hpp"
#include "fdir/tmr.hpp"
#include "trn/filter/ekf.hpp"
#include "trn/filter/filter_config.hpp"
#include "trn/filter/nav_output.hpp"
#include "trn/filter/nav_state.hpp"
#include "trn/filter/state_check.hpp"
#include "trn/match.hpp"

#include <array>
#include <cstddef>
#include <cstdint>

namespace trn::tasks {

/** Publication channel of the navigation solution (bsp::publish_filter). */
inline constexpr std::uint32_t kNavChannel = 1;
/** IMU samples one job consumes at most (more wait for the next job). */
inline constexpr std::uint32_t kMaxImuPerJob = 4;
/** Matches the queue holds: two full frames. */
inline constexpr std::uint32_t kMatchQueueLen = 2U * kMaxMatchesPerFrame;
/** Match-batch parts one job takes at most (the messaging layer queues 8 per channel). */
inline constexpr std::uint32_t kMaxPartsPerJob = 16;
/** Matches applied per job by default: 15 x ~0.3 ms of TILE64 time keeps a job under half its period. */
inline constexpr std::uint32_t kDefaultMatchesPerJob = 15;
/** IMU samples one job replays at most from the I/O tile's DDR record when it is behind. */
inline constexpr std::uint32_t kMaxReplayPerJob = 20;
/** Jobs between two marks of the delivered stream's CRC (FilterTaskStats::mark_crc). */
inline constexpr std::uint32_t kOutputMarkJobs = 100;
/** Assertion id (fdir::assert_failed) of a state refused again after going back to a checkpoint: the tile asks to be restarted. */
inline constexpr std::uint32_t kAssertFilterStateRefused = 0x0605;
/** Assertion id of the EKF's settings changed again before a new checkpoint (or not rebuilt): the tile asks to be restarted. */
inline constexpr std::uint32_t kAssertFilterSettingsChanged = 0x0606;
/**
 * Assertion id of a count or mode in the task's own state that no valid state holds (an upset of
 * it): bounded for the jobs that remain, and the tile asks to be restarted.
 */
inline constexpr std::uint32_t kAssertFilterTaskBad = 0x0607;
/**
 * Assertion id of the filter's measurements still failing against its covariance after it was
 * widened (filter_innovations_bad twice in a row): the tile asks to be restarted.
 */
inline constexpr std::uint32_t kAssertFilterInnovations = 0x0608;
/** Jobs between two checkpoints by default (100 ms). */
inline constexpr std::uint32_t kDefaultCheckpointEvery = 10;
/** Jobs a switch to TMR may take before it is given up. */
inline constexpr std::uint32_t kStartJobs = 100U;

struct FilterTaskConfig {
  filter::FilterConfig filter{};
  bsp::CameraModel camera{};
  filter::InitialEstimate initial{};
  bsp::TileId coordinator_tile = bsp::kNoTile;  ///< tile sent the solution every job on kChanNav (kNoTile: none)
  std::uint32_t matches_per_job = kDefaultMatchesPerJob;  ///< 1..kMaxMatchesPerFrame
  std::uint32_t checkpoint_every = kDefaultCheckpointEvery;  ///< jobs between DDR checkpoints (0: none, no resume)
  /** Boot tiles of the TMR replicas (slots kSlotReplica0..): kNoTile for none (no TMR). */
  std::array<bsp::TileId, 3> replica_tiles{bsp::kNoTile, bsp::kNoTile, bsp::kNoTile};
  /** Boot tile of the filter supervisor (slot kSlotFilterSupervisor), sent a status every kFilterStatusJobs jobs (kNoTile: none). */
  bsp::TileId filter_supervisor_tile = bsp::kNoTile;
  /** When the voter excludes a replica (disagreements or missed jobs in a row). */
  fdir::TmrGroupConfig tmr{};
  /** What a plausible state is, checked after every simplex job (trn/filter/state_check.hpp). */
  filter::StateEnvelope envelope{};
  /** When the simplex filter's measurements disagree with its covariance (fdir/innovation_monitor.hpp). */
  fdir::InnovationMonitorConfig innovation{};
  /**
   * What a failed window adds to the covariance's diagonal (variances of these sigmas): position
   * (m), velocity (cm/s), attitude (mrad). The filter's own matches then bring it back.
   */
  std::uint32_t widen_pos_m = 10U;
  std::uint32_t widen_vel_cmps = 50U;
  std::uint32_t widen_att_mrad = 2U;
};

struct FilterTaskStats {
  std::uint32_t jobs;
  std::uint32_t imu_used;          ///< samples integrated
  std::uint32_t imu_rejected;      ///< bad length or invalid status
  std::uint32_t filter_errors;     ///< steps or updates that returned another error
  std::uint32_t parts_received;    ///< match-batch parts taken from kChanMatches
  std::uint32_t parts_bad;         ///< parts refused: wrong kind, count or length
  std::uint32_t matches_received;  ///< matches queued from good parts
  std::uint32_t matches_applied;   ///< accepted by the filter
  std::uint32_t coarse_applied;    ///< of those, coarse-stage matches
  std::uint32_t rejected_gate;     ///< refused by the filter's gate
  std::uint32_t rejected_stale;    ///< refused for their image time (history, future)
  std::uint32_t rejected_invalid;  ///< refused as invalid (geometry, sigma, time not finite)
  std::uint32_t matches_dropped;   ///< dropped from a full queue (the oldest frame's remainder)
  std::uint32_t queue_high_water;  ///< most matches queued at once
  std::uint32_t nav_sent;          ///< solutions handed to the messaging layer for coordinator_tile
  std::uint32_t nav_send_failed;   ///< refused (window full, no route, node not open)
  std::uint32_t imu_replayed;      ///< samples integrated from the I/O tile's DDR record (missed on the network)
  std::uint32_t imu_duplicates;    ///< live samples already integrated (replayed before they arrived)
  std::uint32_t imu_lost;          ///< samples neither received nor still in the record
  std::uint32_t checkpoints;       ///< checkpoints written
  std::uint32_t resumed_from;      ///< checkpoint the task started from (0: the initial estimate)
  bsp::Cycles max_job_cycles;      ///< longest job, from its start to the end of its sends
  bsp::Cycles last_job_cycles;
  std::uint32_t outputs_delivered; ///< solutions delivered (published and sent), in job order
  std::uint32_t outputs_skipped;   ///< jobs whose solution was never delivered (no majority, a gap)
  std::uint32_t outputs_resealed;  ///< solutions whose copy changed on its way out, made again (kResultSealBroken)
  std::uint32_t output_crc;        ///< CRC-32C over the delivered solutions' job numbers and words
  std::uint32_t last_delivered_job;
  std::uint32_t started_job;       ///< the job this task started at: every count here is since then (a restart clears them)
  std::uint32_t mark_job;          ///< the last delivered job j with (j + 1) % kOutputMarkJobs == 0
  std::uint32_t mark_crc;          ///< output_crc through it: two flights compare their streams up to a job
  std::uint32_t tmr_jobs;          ///< jobs whose delivered solution was voted
  std::uint32_t tmr_outvoted;      ///< replica outputs outvoted (different or missing)
  std::uint32_t tmr_no_majority;   ///< votes without a majority
  std::uint32_t tmr_exclusions;
  std::uint32_t tmr_resyncs;       ///< replicas readmitted after a seed
  std::uint32_t commands;          ///< telecommands taken
  std::uint32_t states_rejected;   ///< simplex jobs whose state failed the plausibility check (not delivered)
  std::uint32_t rollbacks;         ///< returns to the last checkpoint (a refused state, rebuilt settings)
  std::uint32_t settings_rebuilt;  ///< simplex jobs after which the EKF's settings had changed in RAM, and TMR jobs that found the voter's thresholds changed; rebuilt
  std::uint32_t states_changed;         ///< simplex jobs that found the EKF's state changed since the last one (filter_state_changed)
  std::uint32_t innovation_windows;     ///< windows the innovation monitor judged (simplex)
  std::uint32_t innovations_bad;        ///< of them, failed (filter_innovations_bad): the covariance widened
  std::uint32_t max_window_nis_milli;   ///< the largest mean clipped d2 of a judged window, thousandths
  std::uint32_t max_window_reject_permille;  ///< the largest rejected fraction of a judged window, thousandths
};

/** The filter's counters are emulated state through and through (bsp::ControlLayout). */
inline constexpr std::array kFilterTaskStatsFields{
    BSP_CONTROL_STATE(FilterTaskStats, jobs),
    BSP_CONTROL_STATE(FilterTaskStats, imu_used),
    BSP_CONTROL_STATE(FilterTaskStats, imu_rejected),
    BSP_CONTROL_STATE(FilterTaskStats, filter_errors),
    BSP_CONTROL_STATE(FilterTaskStats, parts_received),
    BSP_CONTROL_STATE(FilterTaskStats, parts_bad),
    BSP_CONTROL_STATE(FilterTaskStats, matches_received),
    BSP_CONTROL_STATE(FilterTaskStats, matches_applied),
    BSP_CONTROL_STATE(FilterTaskStats, coarse_applied),
    BSP_CONTROL_STATE(FilterTaskStats, rejected_gate),
    BSP_CONTROL_STATE(FilterTaskStats, rejected_stale),
    BSP_CONTROL_STATE(FilterTaskStats, rejected_invalid),
    BSP_CONTROL_STATE(FilterTaskStats, matches_dropped),
    BSP_CONTROL_STATE(FilterTaskStats, queue_high_water),
    BSP_CONTROL_STATE(FilterTaskStats, nav_sent),
    BSP_CONTROL_STATE(FilterTaskStats, nav_send_failed),
    BSP_CONTROL_STATE(FilterTaskStats, imu_replayed),
    BSP_CONTROL_STATE(FilterTaskStats, imu_duplicates),
    BSP_CONTROL_STATE(FilterTaskStats, imu_lost),
    BSP_CONTROL_STATE(FilterTaskStats, checkpoints),
    BSP_CONTROL_STATE(FilterTaskStats, resumed_from),
    BSP_CONTROL_STATE(FilterTaskStats, max_job_cycles),
    BSP_CONTROL_STATE(FilterTaskStats, last_job_cycles),
    BSP_CONTROL_STATE(FilterTaskStats, outputs_delivered),
    BSP_CONTROL_STATE(FilterTaskStats, outputs_skipped),
    BSP_CONTROL_STATE(FilterTaskStats, outputs_resealed),
    BSP_CONTROL_STATE(FilterTaskStats, output_crc),
    BSP_CONTROL_STATE(FilterTaskStats, last_delivered_job),
    BSP_CONTROL_STATE(FilterTaskStats, started_job),
    BSP_CONTROL_STATE(FilterTaskStats, mark_job),
    BSP_CONTROL_STATE(FilterTaskStats, mark_crc),
    BSP_CONTROL_STATE(FilterTaskStats, tmr_jobs),
    BSP_CONTROL_STATE(FilterTaskStats, tmr_outvoted),
    BSP_CONTROL_STATE(FilterTaskStats, tmr_no_majority),
    BSP_CONTROL_STATE(FilterTaskStats, tmr_exclusions),
    BSP_CONTROL_STATE(FilterTaskStats, tmr_resyncs),
    BSP_CONTROL_STATE(FilterTaskStats, commands),
    BSP_CONTROL_STATE(FilterTaskStats, states_rejected),
    BSP_CONTROL_STATE(FilterTaskStats, rollbacks),
    BSP_CONTROL_STATE(FilterTaskStats, settings_rebuilt),
    BSP_CONTROL_STATE(FilterTaskStats, states_changed),
    BSP_CONTROL_STATE(FilterTaskStats, innovation_windows),
    BSP_CONTROL_STATE(FilterTaskStats, innovations_bad),
    BSP_CONTROL_STATE(FilterTaskStats, max_window_nis_milli),
    BSP_CONTROL_STATE(FilterTaskStats, max_window_reject_permille),
};
inline constexpr bsp::ControlLayout kFilterTaskStatsLayout{kFilterTaskStatsFields, sizeof(FilterTaskStats),
                                                          alignof(FilterTaskStats)};
static_assert(bsp::control_layout_ok(kFilterTaskStatsLayout), "every member of FilterTaskStats");
/**
 * The counters of the filter task, or of a replica, on its tile: a record in
 * the tile's RAM, carved with the filter's core at task start (the host reads
 * it by this name).
 */
inline constexpr bsp::RamRecord<FilterTaskStats> kFilterTaskStatsRecord{"filter_stats", &kFilterTaskStatsLayout};

/** The latest solution the filter task delivered (published and sent), as it went out. */
struct FilterOutput {
  filter::NavOutput latest;
  bool delivered;  ///< false before the first
};
inline constexpr std::array kFilterOutputFields{
    BSP_CONTROL_NESTED(FilterOutput, latest, filter::kNavOutputLayout),
    BSP_CONTROL_STATE(FilterOutput, delivered),
};
inline constexpr bsp::ControlLayout kFilterOutputLayout{kFilterOutputFields, sizeof(FilterOutput),
                                                       alignof(FilterOutput)};
static_assert(bsp::control_layout_ok(kFilterOutputLayout), "every member of FilterOutput");
/**
 * The filter task's latest solution on its tile: a record in the tile's RAM,
 * carved after the task's own state at task start (the host reads it by this
 * name; a replica has none).
 */
inline constexpr bsp::RamRecord<FilterOutput> kFilterOutputRecord{"filter_output", &kFilterOutputLayout};

/** Task entry (arg: const FilterTaskConfig*). Never returns unless set-up fails (bad config included). */
void filter_task_main(void* arg) noexcept;

/**
 * Name of the filter task's own state carve in its tile's RAM (inputs held for their job, the TMR
 * vote's outputs and counts, the place in the stream), and its layout (what an upset of it does). [host]
 */
inline constexpr const char* kFilterTaskCarve = "filter_task";
const bsp::ControlLayout& filter_task_layout() noexcept;

}  // namespace trn::tasks
