/**
 * @file filter_core.hpp
 * @brief The filter job as a step function of a job record: what the simplex filter and each
 *        TMR replica run, so that the same records give the same outputs bit for bit.
 *
 * A job record holds the inputs of one 100 Hz job, as words: the IMU samples
 * to integrate, in order, and the matches to queue, in order (each as packed
 * on the network). The task that takes the inputs off the network (the
 * filter role's task, the voter) fills one per job; the simplex filter runs it at once, a
 * TMR replica runs the copy it reads from the shared job ring
 * (trn/tasks/filter/filter_tmr.hpp). A record carries its job number and a CRC-32C
 * of its words, so a torn or upset copy is refused rather than run.
 *
 * The core is the state a job changes: the EKF and the queue of matches not
 * yet applied. Its digest (CRC-32C of the state block and the queue's words)
 * is what TMR replicas vote on besides their output; save and load move it
 * whole (switch to TMR, a replica re-synchronised, back to simplex).
 */
#pragma once

#include "bsp_tile64/api/memory.hpp"
#include "bsp_tile64/api/work.hpp"
#include "trn/filter/ekf.hpp"
#include "trn/filter/state_block.hpp"
#include "trn/tasks/filter/filter_task.hpp"
#include "trn/tasks/messages.hpp"

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>

namespace trn::tasks {

/** IMU samples one record holds: the live ones of a job and a job's replay. */
inline constexpr std::uint32_t kRecordImuMax = kMaxImuPerJob + kMaxReplayPerJob;
/** Matches one record holds: a job's parts, full. */
inline constexpr std::uint32_t kRecordMatchMax = kMaxPartsPerJob * kMatchesPerPart;
/** [0] job [1] IMU samples [2] matches [3] CRC-32C of the words after the header. */
inline constexpr std::uint32_t kRecordHeaderWords = 4U;
inline constexpr std::uint32_t kRecordWords =
    kRecordHeaderWords + kRecordImuMax * kImuWords + kRecordMatchMax * kMatchWords;

struct JobRecord {
  std::array<std::uint32_t, kRecordWords> w{};
};
/** A record being filled is emulated state: its counts are bounded wherever they are taken (bsp::ControlLayout). */
inline constexpr std::array kJobRecordFields{BSP_CONTROL_STATE(JobRecord, w)};
inline constexpr bsp::ControlLayout kJobRecordLayout{kJobRecordFields, sizeof(JobRecord), alignof(JobRecord)};
static_assert(bsp::control_layout_ok(kJobRecordLayout), "every member of JobRecord");

/** Empties @p r for job @p job. */
void record_begin(JobRecord& r, std::uint32_t job) noexcept;
/** Appends a sample; false when the record holds kRecordImuMax already. */
bool record_add_imu(JobRecord& r, const bsp::ImuSample& s) noexcept;
/** Appends a packed match; false when the record holds kRecordMatchMax already. */
bool record_add_match(JobRecord& r, std::span<const std::uint32_t, kMatchWords> m) noexcept;
/** Seals the record (its CRC); charges @p work. */
void record_seal(JobRecord& r, bsp::Work& work) noexcept;
/** True if @p r is sealed, for job @p job, and its counts and CRC check; charges @p work. */
bool record_ok(const JobRecord& r, std::uint32_t job, bsp::Work& work) noexcept;
[[nodiscard]] inline std::uint32_t record_job(const JobRecord& r) noexcept { return r.w[0]; }
[[nodiscard]] inline std::uint32_t record_imu_count(const JobRecord& r) noexcept { return r.w[1]; }
[[nodiscard]] inline std::uint32_t record_match_count(const JobRecord& r) noexcept { return r.w[2]; }

/** Matches waiting to be applied, oldest first (a ring). */
struct MatchQueue {
  std::uint32_t head;
  std::uint32_t count;
  std::array<Match, kMatchQueueLen> m;
};

/** Words of a saved core: the queue (head, count, packed matches), then the last IMU sample integrated. */
inline constexpr std::uint32_t kQueueWords = 2U + kMatchQueueLen * kMatchWords + 2U;

struct FilterCore {
  filter::Ekf* ekf = nullptr;
  MatchQueue* queue = nullptr;
  filter::StateBlock* scratch = nullptr;  ///< for digests and saves
  const FilterTaskConfig* cfg = nullptr;
  FilterTaskStats* stats = nullptr;       ///< the owner's counters, its record in tile RAM (kFilterTaskStatsRecord)
  bool have_imu = false;
  std::uint32_t last_imu = 0U;            ///< seq of the last sample integrated
  /// CRC-32C of each part of the EKF's settings when they were (re)built (core_settings_changed()).
  std::array<std::uint32_t, 3> settings_crc{};
};

/**
 * What an upset of a core does (bsp::ControlLayout): its pointers are host
 * state; the cursor of the samples integrated and the settings' digests are
 * the tile's own.
 */
inline constexpr std::array kFilterCoreFields{
    BSP_CONTROL_HOST(FilterCore, ekf),      BSP_CONTROL_HOST(FilterCore, queue),
    BSP_CONTROL_HOST(FilterCore, scratch),  BSP_CONTROL_HOST(FilterCore, cfg),
    BSP_CONTROL_HOST(FilterCore, stats),    BSP_CONTROL_STATE(FilterCore, have_imu),
    BSP_CONTROL_STATE(FilterCore, last_imu), BSP_CONTROL_STATE(FilterCore, settings_crc),
};
inline constexpr bsp::ControlLayout kFilterCoreLayout{kFilterCoreFields, sizeof(FilterCore), alignof(FilterCore)};
static_assert(bsp::control_layout_ok(kFilterCoreLayout), "every member of FilterCore, pointers as host state");

/**
 * Carves the core in @p ram (the running tile's RAM), its counters' record
 * (kFilterTaskStatsRecord) last, and configures the EKF (not initialised).
 */
bool core_set_up(FilterCore& c, const FilterTaskConfig& cfg, bsp::Region ram) noexcept;

/**
 * Runs one job: integrates the record's samples, queues its matches, applies at most
 * matches_per_job. @return the job's matches that reached the gate: accepted, rejected_gate and
 * their clipped innovations (nis_sum); the other counts are left 0.
 */
filter::UpdateReport core_run(FilterCore& c, const JobRecord& r) noexcept;

/** The solution after the last job. */
filter::NavOutput core_output(const FilterCore& c) noexcept;

/** Drops the matches waiting in the queue (they were for a state the core no longer has). */
void core_drop_matches(FilterCore& c) noexcept;

/** CRC-32C of the whole state (state block, queue, last sample); charges @p work. */
std::uint32_t core_digest(FilterCore& c, bsp::Work& work) noexcept;

/** Name of the carve that holds a core's EKF (an upset aimed at the filter names it). */
inline constexpr const char* kEkfCarve = "ekf";
/**
 * Bytes of the EKF's settings at the start of its carve: its configuration,
 * camera and process noise are the Ekf's first members (tests check it).
 */
inline constexpr std::size_t kEkfSettingsBytes =
    sizeof(filter::FilterConfig) + sizeof(filter::CameraGeometry) + sizeof(filter::Vec15);

/** Parts of the EKF's settings, as bits of core_settings_changed()'s result. */
inline constexpr std::uint32_t kSettingsConfig = 1U;        ///< the filter's configuration
inline constexpr std::uint32_t kSettingsCamera = 2U;        ///< the camera's geometry
inline constexpr std::uint32_t kSettingsProcessNoise = 4U;  ///< the process noise derived from the configuration

/**
 * The parts of the EKF's settings in RAM whose CRC-32C is not what it was
 * when they were built: its configuration, its camera and the process noise
 * (368 bytes that no job writes and no checkpoint holds). 0: unchanged.
 * Charges @p work.
 */
std::uint32_t core_settings_changed(const FilterCore& c, bsp::Work& work) noexcept;

/**
 * Builds the EKF's settings again from the task's configuration (the image's
 * copy), keeping its state, and takes their digest anew; charges @p work.
 * False if the configuration is refused (it was accepted at set-up).
 */
bool core_reload_settings(FilterCore& c, bsp::Work& work) noexcept;

/** A saved core: its state block and its queue words. */
struct CoreImage {
  filter::StateBlock block{};
  std::array<std::uint32_t, kQueueWords> queue{};
};

/** Saves the whole state into @p out; charges @p work. */
void core_save(FilterCore& c, CoreImage& out, bsp::Work& work) noexcept;

/** Loads a saved state (checked: state block, queue counts); false leaves the core as it was. */
bool core_load(FilterCore& c, const CoreImage& in, bsp::Work& work) noexcept;

}  // namespace trn::tasks
