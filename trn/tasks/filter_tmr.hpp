/**
 * @file filter_tmr.hpp
 * @brief TMR of the navigation filter: the shared areas of the group in DDR and the replica task.
 *
 * The filter role's tile (the "front") takes the inputs off the network and
 * writes each job's record (trn/tasks/filter_core.hpp) into a ring in DDR.
 * Three replicas, each on its own tile, run the same records from the same
 * state and send the front, per job, their packed solution and the digest of
 * their whole state (kMsgReplicaOut on kChanNav). The front votes them 2 of 3
 * bit for bit (fdir/tmr.hpp), kVoteLag jobs after the record, and delivers
 * the voted solution in place of its own.
 *
 * The control block (written by the front only) says whether the group runs,
 * which replica saves its state after which job (a seed, for a replica that
 * re-synchronises or for the switch back), and which replicas must drop their
 * state (a generation per replica, raised at each exclusion). A seed is the
 * core's whole state after a job, with its digest and a CRC over its header;
 * a replica loads the newest seed meant for it and runs on from the record
 * after it. A replica that is not seeded, or lost its place in the ring,
 * says so to the front (kMsgReplicaHello) every kHelloEvery releases.
 */
#pragma once

#include "trn/tasks/filter_core.hpp"

#include <array>
#include <cstdint>

namespace trn::tasks {

/** Records the ring holds (320 ms of jobs: a replica may run this far behind). */
inline constexpr std::uint32_t kJobRingLen = 32U;
/** The front votes job j while it writes the record of job j + kVoteLag. */
inline constexpr std::uint32_t kVoteLag = 2U;
/** The replica count, and the front's bit in a seed's for_mask. */
inline constexpr std::uint32_t kReplicas = 3U;
inline constexpr std::uint32_t kFrontBit = 1U << kReplicas;
/** Releases (10 ms) between two hellos of a replica waiting for a seed. */
inline constexpr std::uint32_t kHelloEvery = 2U;
/**
 * Records a replica runs per release (10 ms) at most: one normally, two when
 * it catches up after a seed (a job with matches costs about 4 ms).
 */
inline constexpr std::uint32_t kReplicaJobsPerRelease = 2U;
/** Output sent per job: [0] kMsgReplicaOut [1] replica [2] job [3] state digest [4..] packed solution. */
inline constexpr std::uint32_t kReplicaOutWords = 4U + kNavWords;
/** [0] kMsgReplicaHello [1] replica [2] epoch it saw. */
inline constexpr std::uint32_t kReplicaHelloWords = 3U;
inline constexpr std::uint32_t kNoReplica = 0xFFFF'FFFFU;

struct TmrControl {
  std::uint32_t mode = 0U;        ///< 1 while the group runs (0: the front is simplex; replicas idle)
  std::uint32_t epoch = 0U;       ///< +1 per switch to TMR: a seed of another epoch is never loaded
  std::uint32_t seed_by = kNoReplica;  ///< replica to save its state after job seed_job
  std::uint32_t seed_job = 0U;
  std::uint32_t seed_for = 0U;    ///< who that seed is for (bit per replica, kFrontBit)
  std::uint32_t ckpt_by = kNoReplica;  ///< replica that writes the filter's DDR checkpoints
  std::array<std::uint32_t, kReplicas> gen{};  ///< raised when a replica is excluded: it drops its state
};

struct TmrSeed {
  std::uint32_t serial = 0U;      ///< +1 per seed written (0: none yet)
  std::uint32_t job = 0U;         ///< the state after this job
  std::uint32_t for_mask = 0U;
  std::uint32_t epoch = 0U;
  std::uint32_t digest = 0U;      ///< core digest of the state
  std::array<std::uint32_t, kReplicas> gen{};  ///< the generations it was made for
  std::uint32_t crc = 0U;         ///< CRC-32C of the words above
  CoreImage image{};
};

struct TmrArea {
  TmrControl control{};
  TmrSeed seed{};
  std::array<JobRecord, kJobRingLen> ring{};
};

/** The group's area in DDR (carved on first use, found again after); nullptr if DDR is full. [task] */
TmrArea* tmr_area() noexcept;

/** Writes a seed: the state of @p c after job @p job, for @p for_mask; charges @p work. */
void tmr_write_seed(TmrArea& a, FilterCore& c, std::uint32_t job, std::uint32_t for_mask, bsp::Work& work) noexcept;

/** True if the seed's header CRC checks. */
bool tmr_seed_ok(const TmrSeed& s) noexcept;

/** Which replica @p tile runs now (the role directory, boot tiles as fallback); kNoReplica if none. */
std::uint32_t replica_index(const FilterTaskConfig& cfg, bsp::TileId tile) noexcept;

/** Replica task entry (arg: const FilterTaskConfig*, the filter's). Never returns unless set-up fails. */
void filter_replica_main(void* arg) noexcept;

/** Counters of the replica on @p tile. [host] */
FilterTaskStats replica_stats(bsp::TileId tile) noexcept;

}  // namespace trn::tasks
