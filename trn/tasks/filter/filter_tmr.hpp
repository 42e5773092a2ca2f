/**
 * @file filter_tmr.hpp
 * @brief TMR of the navigation filter: the shared areas of the group in DDR and the replica task.
 *
 * The filter role's tile (the voter: alone, it runs the filter itself) takes the inputs off the network and
 * writes each job's record (trn/filter/filter_core.hpp) into a ring in DDR.
 * Three replicas, each on its own tile, run the same records from the same
 * state and send the voter, per job, their packed solution and the digest of
 * their whole state (kMsgReplicaOut on kChanNav). The voter votes them 2 of 3
 * bit for bit (fdir/tmr.hpp), kVoteLag jobs after the record, and delivers
 * the voted solution in place of its own.
 *
 * The control block (written by the voter only) says whether the group runs,
 * which replica saves its state after which job (a seed, for a replica that
 * re-synchronises or for the switch back), and which replicas must drop their
 * state (a generation per replica, raised at each exclusion). A seed is the
 * core's whole state after a job, with its digest and a CRC over its header;
 * a replica loads the newest seed meant for it and runs on from the record
 * after it. A replica that is not seeded, or lost its place in the ring,
 * says so to the voter (kMsgReplicaHello) every kHelloEvery releases. A
 * replica whose EKF settings in RAM changed (their CRC after each job:
 * core_settings_changed) reports it (kFilterSettingsBad), builds them again,
 * sends nothing for that job and drops its state, to be re-seeded.
 *
 * The voter's place in the stream is in DDR too, so that a voter restarted
 * (reset, or its role moved to a spare) goes on where it stopped: after each
 * job it votes, the voter writes its place (TmrVoter: the last record written,
 * the next job to deliver, the delivered stream's CRC, its input cursor and
 * the telecommand it holds) and, when they changed, the matches it holds for
 * later jobs (TmrHeldMatches). Each replica also keeps its last outputs in DDR
 * (TmrArea::outputs), as sent: the outputs the voter held when it failed are
 * voted by the next one. The replicas wait (state kept) for records while the
 * voter is down; the new voter writes the records of the outage from the I/O
 * tile's IMU record and the held matches, and votes every job, late but once.
 */
#pragma once

#include "fdir/tmr.hpp"
#include "trn/filter/filter_core.hpp"
#include "trn/tasks/filter/filter_checkpoint.hpp"

#include <array>
#include <cstdint>

namespace trn::tasks {

/** Records the ring holds (320 ms of jobs: a replica may run this far behind). */
inline constexpr std::uint32_t kJobRingLen = 32U;
/** The voter votes job j while it writes the record of job j + kVoteLag. */
inline constexpr std::uint32_t kVoteLag = 2U;
/** The voter's bit in a seed's for_mask (the replicas' are 0 .. kReplicas - 1, messages.hpp). */
inline constexpr std::uint32_t kVoterBit = 1U << kReplicas;
/** Releases (10 ms) between two hellos of a replica waiting for a seed. */
inline constexpr std::uint32_t kHelloEvery = 2U;
/**
 * Records a replica runs per release (10 ms) at most: one normally, two when
 * it catches up after a seed (a job with matches costs about 4 ms).
 */
inline constexpr std::uint32_t kReplicaJobsPerRelease = 2U;
inline constexpr std::uint32_t kNoReplica = 0xFFFF'FFFFU;

struct TmrControl {
  std::uint32_t mode = 0U;        ///< 1 while the group runs (0: the voter is simplex; replicas idle)
  std::uint32_t epoch = 0U;       ///< +1 per switch to TMR: a seed of another epoch is never loaded
  std::uint32_t seed_by = kNoReplica;  ///< replica to save its state after job seed_job
  std::uint32_t seed_job = 0U;
  std::uint32_t seed_for = 0U;    ///< who that seed is for (bit per replica, kVoterBit)
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

/** Replica outputs kept in DDR per replica, by job. */
inline constexpr std::uint32_t kHeldOutputs = 8U;
/** Matches the voter holds for later jobs at most (one frame's). */
inline constexpr std::uint32_t kHeldMatches = kMaxMatchesPerFrame;
/**
 * Jobs a restarted voter may have missed and still go on voting (the records
 * of the outage must fit the ring with the ones the replicas have not run).
 */
inline constexpr std::uint32_t kMaxRejoinGap = kJobRingLen - 8U;

/** The voter's place in the stream after a job it voted (written by the voter only). */
struct TmrVoter {
  std::uint32_t serial = 0U;        ///< +1 per write (0: never written)
  std::uint32_t epoch = 0U;         ///< of the group it voted in
  std::uint32_t voting = 0U;        ///< 1 if it voted (TMR established, not stopping)
  std::uint32_t record_job = 0U;    ///< the last record written to the ring
  std::uint32_t next_vote = 0U;     ///< the job it votes next
  std::uint32_t next_deliver = 0U;  ///< the job whose solution is delivered next
  std::uint32_t delivered_any = 0U;
  std::uint32_t outputs_delivered = 0U;
  std::uint32_t outputs_skipped = 0U;
  std::uint32_t output_crc = 0U;
  std::uint32_t last_delivered_job = 0U;
  std::uint32_t mark_job = 0U;
  std::uint32_t mark_crc = 0U;
  std::uint32_t have_imu = 0U;      ///< the input cursor: last_imu is the last sample put into a record
  std::uint32_t last_imu = 0U;
  std::uint32_t cmd_held = 0U;      ///< a telecommand waiting for its sample
  std::array<std::uint32_t, kCommandWords> cmd{};
  std::uint32_t active_mask = 0U;   ///< replicas voting
  std::uint32_t last_winner = 0U;
  std::uint32_t held_serial = 0U;   ///< the TmrHeldMatches serial that goes with this place
  /// The last two checkpoints whose state digest the vote agreed on: what a voter restarted in TMR
  /// can fall back to when the replicas part (without them, nothing until its next voted checkpoint).
  std::array<VotedCheckpoint, 2> voted_ckpt{};
  std::uint32_t crc = 0U;           ///< CRC-32C of the words above
};

/** The matches the voter holds for later jobs, in order (written when they change). */
struct TmrHeldMatches {
  std::uint32_t serial = 0U;
  std::uint32_t count = 0U;
  std::array<std::uint32_t, kHeldMatches> job{};
  std::array<std::uint32_t, std::size_t{kHeldMatches} * kMatchWords> words{};
  std::uint32_t crc = 0U;           ///< CRC-32C of serial, count and the held jobs and words
};

struct TmrArea {
  TmrControl control{};
  /**
   * The voter's release phase: its job's start in board ticks modulo the
   * period, plus 1 (0: not written yet). A replica that starts late (woken,
   * reset) aligns its releases to it.
   */
  std::uint32_t voter_phase = 0U;
  TmrSeed seed{};
  std::array<JobRecord, kJobRingLen> ring{};
  TmrVoter voter{};
  TmrHeldMatches held{};
  /** Each replica's outputs by job (job % kHeldOutputs), as sent; words 0 if none. */
  std::array<std::array<fdir::TmrRecord, kHeldOutputs>, kReplicas> outputs{};
};

/** The group's area in DDR (carved on first use, found again after); nullptr if DDR is full. [task] */
TmrArea* tmr_area() noexcept;

/** Writes a seed: the state of @p c after job @p job, for @p for_mask; charges @p work. */
void tmr_write_seed(TmrArea& a, FilterCore& c, std::uint32_t job, std::uint32_t for_mask, bsp::Work& work) noexcept;

/** Seals @p f (its CRC) / true if its CRC checks. */
void tmr_voter_seal(TmrVoter& f) noexcept;
bool tmr_voter_ok(const TmrVoter& f) noexcept;
/** Seals @p h / true if its CRC checks; both charge @p work. */
void tmr_held_seal(TmrHeldMatches& h, bsp::Work& work) noexcept;
bool tmr_held_ok(const TmrHeldMatches& h, bsp::Work& work) noexcept;

/** True if the seed's header CRC checks. */
bool tmr_seed_ok(const TmrSeed& s) noexcept;

/** Which replica @p tile runs now (the role directory, boot tiles as fallback); kNoReplica if none. */
std::uint32_t replica_index(const FilterTaskConfig& cfg, bsp::TileId tile) noexcept;

/** Replica task entry (arg: const FilterTaskConfig*, the filter's). Never returns unless set-up fails. */
void filter_replica_main(void* arg) noexcept;

/** Name of a replica's state carve in its tile's RAM, and its layout (what an upset of it does). [host] */
inline constexpr const char* kReplicaCarve = "replica";
const bsp::ControlLayout& replica_state_layout() noexcept;

}  // namespace trn::tasks
