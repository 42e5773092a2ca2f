/**
 * @file filter_task.cpp
 * @brief The 100 Hz navigation filter job: IMU, match batches, bounded updates, solution out.
 */
#include "trn/tasks/filter/filter_task.hpp"
#include "trn/events.hpp"

#include "bsp_tile64/api/memory.hpp"
#include "fdir/assert.hpp"
#include "fdir/event_log.hpp"
#include "kernel/kernel.hpp"
#include "fdir/tmr.hpp"
#include "trn/tasks/filter/filter_checkpoint.hpp"
#include "trn/filter/filter_core.hpp"
#include "trn/tasks/filter/filter_tmr.hpp"
#include "trn/tasks/io/imu_ring.hpp"
#include "trn/tasks/messages.hpp"
#include "udn/crc32c.hpp"
#include "udn/endpoint.hpp"

#include <algorithm>
#include <array>
#include <span>

namespace trn::tasks {
namespace {

/** What the voter does with the records it fills. */
enum class Mode : std::uint8_t {
  kSimplex,   ///< runs them itself
  kStarting,  ///< runs them itself and compares the replicas, seeded from its state, until they agree
  kTmr,       ///< the replicas run them; the voter votes and delivers
  kStopping,  ///< as kTmr, until a replica's state after the stop job is there to go on from alone
};

/** Outputs kept per replica (and the voter's own while starting), by job. */
constexpr std::uint32_t kOutRing = 8U;
/**
 * Job j takes the IMU samples up to seq j - kImuLagJobs: sample s is read at
 * (s + 1) x 10 ms, so the newest one a job takes was read a whole period before
 * the job's release. What arrived sooner waits (held) for its job: which samples
 * a job takes does not depend on the network's timing.
 */
constexpr std::uint32_t kImuLagJobs = 2U;
/** Early samples held for their job at most (one or two in flight). */
constexpr std::uint32_t kImuHeld = 8U;
/** Causes of tmr_simplex (fdir/event_ids.hpp). */
constexpr std::uint32_t kTmrStopCommand = 0U;
constexpr std::uint32_t kTmrStopNotEstablished = 2U;
constexpr std::uint32_t kTmrStopRestart = 3U;
constexpr std::uint32_t kTmrStopNoMajority = ev::kTmrSimplexNoMajority;
/**
 * Votes without a majority in a row after which the replicas' states are taken to have parted and
 * the voter goes on alone from the last checkpoint the vote confirmed (one alone is a lost output).
 */
constexpr std::uint32_t kNoMajorityToFallBack = 2U;
/** Jobs a voter catching up after a restart votes at most in one of its own. */
constexpr std::uint32_t kVotesPerJob = 4U;
/** Voted words: the packed solution and the state digest. */
constexpr std::uint32_t kVotedWords = kNavWords + 1U;

struct TaskState {
  FilterCore core;
  const FilterTaskConfig* cfg;
  FilterTaskStats* stats;    ///< the core's counters (its record in tile RAM)
  FilterOutput* output;      ///< the latest solution delivered (its record in tile RAM)
  JobRecord record;          ///< the job being filled
  CheckpointArea* ckpt;      ///< nullptr: no checkpoints (disabled, or no DDR)
  const ImuRing* ring;       ///< the I/O tile's record; nullptr until it exists
  bool have_imu;             ///< last_imu is valid (the voter's cursor: samples put into records)
  std::uint32_t last_imu;    ///< seq of the last sample put into a record
  bool catching_up;          ///< samples to replay from the record before the live ones
  std::uint32_t ckpt_seq;    ///< number of the last checkpoint written or resumed from
  std::uint32_t ckpt_slot;   ///< checkpoint slot it is in (the next write goes to the other)
  std::uint32_t since_ckpt;  ///< jobs since it
  std::uint32_t job;         ///< this job's number
  std::array<bsp::ImuSample, kImuHeld> held;  ///< samples that came before their job, in order
  std::uint32_t held_count;
  bool cmd_held;             ///< a telecommand waits for the sample it came after
  std::array<std::uint32_t, std::size_t{kHeldMatches} * kMatchWords> mheld;  ///< packed matches waiting for their job, in order
  std::array<std::uint32_t, kHeldMatches> mheld_job;            ///< the job each waits for
  std::uint32_t mheld_count;
  std::uint32_t mheld_changes;  ///< +1 whenever the held matches change (written to DDR when they did)
  std::array<std::uint32_t, kCommandWords> cmd;
  // ---- TMR
  Mode mode;
  TmrArea* tmr;
  std::uint32_t command;     ///< a telecommand taken this job (0: none)
  std::uint32_t next_deliver;  ///< the job whose solution is delivered next
  bool delivered_any;
  std::uint32_t start_job;
  fdir::TmrGroup group;
  std::array<std::array<fdir::TmrRecord, kOutRing>, kReplicas> out;  ///< replicas' outputs by job
  std::array<std::uint32_t, kOutRing> out_bad;  ///< per ring place, bit per replica: its output there fails its CRC
  std::array<fdir::TmrRecord, kOutRing> own;  ///< the voter's own outputs while starting
  std::uint32_t hello_mask;  ///< replicas that asked for a seed since the last one
  std::uint32_t refused_mask;  ///< those of them that dropped their state because their own checks refused it
  std::array<std::uint32_t, kReplicas> seeded_differ;  ///< outputs of a replica not voting that differed from the vote, in a row
  std::uint32_t seed_asked;  ///< jobs since a seed was asked (0: none pending)
  bool resume_tmr;           ///< restarted while in TMR: start it again once caught up
  std::uint32_t last_winner; ///< a replica that agreed with the last vote
  std::uint32_t no_majority_mask;  ///< replicas that differed in a vote without a majority and have not voted since
  std::uint32_t no_majority_run;   ///< votes without a majority in a row
  std::array<VotedCheckpoint, 2> voted_ckpt;  ///< the last two checkpoints whose state digest the vote agreed on
  std::uint32_t stop_job;    ///< stopping: the job after whose record a replica saves its state for the voter
  bool stop_voted;           ///< stopping: that job was voted, stop_digest is its state digest
  std::uint32_t stop_digest;
  bool stop_again;           ///< stopping: no good state came; ask again before the next record
  std::uint32_t next_vote;   ///< the job voted next
  std::uint32_t held_saved;  ///< mheld_changes when the held matches were last written to DDR
  bool held_written;         ///< the held matches were written to DDR since the task started
  bool rejoin;               ///< restarted while voting: writes the records of its outage first
  std::uint32_t rebuild_from;  ///< the first of them
  std::uint32_t lenient_until; ///< until this job a vote waits for every voting replica's output
  std::uint32_t rolled_back_to;  ///< the checkpoint the last plausibility failure went back to (0: none)
  bool recovery_asked;           ///< refused again after going back: the tile asked to be restarted
  fdir::InnovationMonitor innov; ///< the simplex filter's innovation monitor (watch_innovations())
  bool widened;                  ///< its last verdict failed and the covariance was widened
  std::uint32_t state_seal;      ///< CRC-32C of the EKF's state at the end of the last job (seal_state())
  std::uint32_t seal_for;        ///< the job that checks it (+1 of the one that took it; 0: none)
};

/** A sample held for its job is emulated state through and through (bsp::ControlLayout). */
constexpr std::array kImuSampleFields{BSP_CONTROL_STATE(bsp::ImuSample, seq), BSP_CONTROL_STATE(bsp::ImuSample, status),
                                      BSP_CONTROL_STATE(bsp::ImuSample, t_s),
                                      BSP_CONTROL_STATE(bsp::ImuSample, dtheta_rad),
                                      BSP_CONTROL_STATE(bsp::ImuSample, dv_mps)};
constexpr bsp::ControlLayout kImuSampleLayout{kImuSampleFields, sizeof(bsp::ImuSample), alignof(bsp::ImuSample)};
static_assert(bsp::control_layout_ok(kImuSampleLayout), "every member of ImuSample");

/**
 * What an upset of the task's own state does (bsp::ControlLayout): its pointers (the core's, the
 * configuration, its records in tile RAM, its DDR areas) are host state; everything else is the
 * tile's own and is flipped for real. Every count it indexes by is bounded where it is taken
 * (held_count, mheld_count), a mode with no TMR area runs simplex, and check_task_state() reports a
 * value no valid state holds (kAssertFilterTaskBad).
 */
constexpr std::array kTaskStateFields{
    BSP_CONTROL_NESTED(TaskState, core, kFilterCoreLayout),
    BSP_CONTROL_HOST(TaskState, cfg),
    BSP_CONTROL_HOST(TaskState, stats),
    BSP_CONTROL_HOST(TaskState, output),
    BSP_CONTROL_NESTED(TaskState, record, kJobRecordLayout),
    BSP_CONTROL_HOST(TaskState, ckpt),
    BSP_CONTROL_HOST(TaskState, ring),
    BSP_CONTROL_STATE(TaskState, have_imu),
    BSP_CONTROL_STATE(TaskState, last_imu),
    BSP_CONTROL_STATE(TaskState, catching_up),
    BSP_CONTROL_STATE(TaskState, ckpt_seq),
    BSP_CONTROL_STATE(TaskState, ckpt_slot),
    BSP_CONTROL_STATE(TaskState, since_ckpt),
    BSP_CONTROL_STATE(TaskState, job),
    BSP_CONTROL_NESTED(TaskState, held, kImuSampleLayout),
    BSP_CONTROL_STATE(TaskState, held_count),
    BSP_CONTROL_STATE(TaskState, cmd_held),
    BSP_CONTROL_STATE(TaskState, mheld),
    BSP_CONTROL_STATE(TaskState, mheld_job),
    BSP_CONTROL_STATE(TaskState, mheld_count),
    BSP_CONTROL_STATE(TaskState, mheld_changes),
    BSP_CONTROL_STATE(TaskState, cmd),
    BSP_CONTROL_STATE(TaskState, mode),
    BSP_CONTROL_HOST(TaskState, tmr),
    BSP_CONTROL_STATE(TaskState, command),
    BSP_CONTROL_STATE(TaskState, next_deliver),
    BSP_CONTROL_STATE(TaskState, delivered_any),
    BSP_CONTROL_STATE(TaskState, start_job),
    BSP_CONTROL_NESTED(TaskState, group, fdir::TmrGroupLayout::kLayout),
    BSP_CONTROL_NESTED(TaskState, out, fdir::kTmrRecordLayout),
    BSP_CONTROL_STATE(TaskState, out_bad),
    BSP_CONTROL_NESTED(TaskState, own, fdir::kTmrRecordLayout),
    BSP_CONTROL_STATE(TaskState, hello_mask),
    BSP_CONTROL_STATE(TaskState, refused_mask),
    BSP_CONTROL_STATE(TaskState, seeded_differ),
    BSP_CONTROL_STATE(TaskState, seed_asked),
    BSP_CONTROL_STATE(TaskState, resume_tmr),
    BSP_CONTROL_STATE(TaskState, last_winner),
    BSP_CONTROL_STATE(TaskState, no_majority_mask),
    BSP_CONTROL_STATE(TaskState, no_majority_run),
    BSP_CONTROL_NESTED(TaskState, voted_ckpt, kVotedCheckpointLayout),
    BSP_CONTROL_STATE(TaskState, stop_job),
    BSP_CONTROL_STATE(TaskState, stop_voted),
    BSP_CONTROL_STATE(TaskState, stop_digest),
    BSP_CONTROL_STATE(TaskState, stop_again),
    BSP_CONTROL_STATE(TaskState, next_vote),
    BSP_CONTROL_STATE(TaskState, held_saved),
    BSP_CONTROL_STATE(TaskState, held_written),
    BSP_CONTROL_STATE(TaskState, rejoin),
    BSP_CONTROL_STATE(TaskState, rebuild_from),
    BSP_CONTROL_STATE(TaskState, lenient_until),
    BSP_CONTROL_STATE(TaskState, rolled_back_to),
    BSP_CONTROL_STATE(TaskState, recovery_asked),
    BSP_CONTROL_NESTED(TaskState, innov, fdir::kInnovationMonitorLayout),
    BSP_CONTROL_STATE(TaskState, widened),
    BSP_CONTROL_STATE(TaskState, state_seal),
    BSP_CONTROL_STATE(TaskState, seal_for),
};
constexpr bsp::ControlLayout kTaskStateLayout{kTaskStateFields, sizeof(TaskState), alignof(TaskState)};
static_assert(bsp::control_layout_ok(kTaskStateLayout), "every member of the task's state, pointers as host state");

// ------------------------------------------------------------------ the voter: inputs into a record

void add_sample(TaskState& st, const bsp::ImuSample& s) noexcept {
  if (record_add_imu(st.record, s)) {
    st.have_imu = true;
    st.last_imu = s.seq;
  }
}

/**
 * Puts from the DDR record the samples after the last one up to (not
 * including) @p until into the job's record, at most @p budget of them.
 * @return false if the budget ran out first. Samples the record lost are skipped and reported.
 */
bool replay(TaskState& st, std::uint32_t until, std::uint32_t& budget) noexcept {
  if (st.ring == nullptr) {
    st.ring = imu_ring();
  }
  for (std::uint32_t n = 0; n < kMaxReplayPerJob + 1U && st.last_imu + 1U < until; ++n) {
    if (budget == 0U) {
      return false;
    }
    bsp::ImuSample s{};
    const RingRead rr = st.ring == nullptr ? RingRead::kNotYet : imu_ring_get(*st.ring, st.last_imu + 1U, s);
    if (rr == RingRead::kNotYet) {
      return true;  // nothing newer recorded yet
    }
    if (rr == RingRead::kGone) {
      const std::uint32_t oldest = imu_ring_oldest(*st.ring);
      const std::uint32_t first = oldest > st.last_imu + 1U ? oldest : until;
      const std::uint32_t missing = first - (st.last_imu + 1U);
      st.stats->imu_lost += missing;
      trn::report(ev::kImuGap, st.last_imu + 1U, 0U, missing);
      st.last_imu = first - 1U;
      continue;
    }
    add_sample(st, s);
    ++st.stats->imu_replayed;
    --budget;
  }
  return st.last_imu + 1U >= until;
}

/** After a resume: replays the record until it has nothing newer (bounded per job). */
void catch_up(TaskState& st) noexcept {
  if (!st.catching_up) {
    return;
  }
  std::uint32_t budget = kMaxReplayPerJob;
  // Up to what is due at this job, not whatever the I/O tile has recorded by now.
  const std::uint32_t recorded = st.ring != nullptr ? st.ring->written : 0U;
  const std::uint32_t due_end = st.job >= kImuLagJobs ? st.job - kImuLagJobs + 1U : 0U;
  const std::uint32_t newest = recorded < due_end ? recorded : due_end;
  if (replay(st, newest > st.last_imu + 1U ? newest : st.last_imu + 1U, budget) && budget > 0U) {
    st.catching_up = false;
  }
}

/** True if sample @p seq belongs to this job (or an earlier one). */
bool imu_due(const TaskState& st, std::uint32_t seq) noexcept { return seq + kImuLagJobs <= st.job; }

/** A telecommand in the IMU stream: held until the job that takes the sample sent before it. */
void hold_command(TaskState& st, const Command& c) noexcept {
  (void)fdir::msg::encode(kCommandMsg, c, st.cmd);  // held as its words: they travel with the filter's frozen state
  st.cmd_held = true;  // a second one before the first is taken replaces it (one a second in flight)
}

void take_command(TaskState& st) noexcept {
  const std::uint32_t after = st.cmd[4];
  if (!st.cmd_held || (after != kNoImuYet && !imu_due(st, after))) {
    return;
  }
  st.cmd_held = false;
  ++st.stats->commands;
  st.command = st.cmd[2];
  trn::report(ev::kCommandTaken, st.cmd[2], st.cmd[1], st.job);
}

/** Puts a due sample into the record: duplicates skipped, a gap first replayed from the DDR record. */
void take_sample(TaskState& st, const bsp::ImuSample& s, std::uint32_t& budget) noexcept {
  if (st.have_imu && s.seq <= st.last_imu) {
    ++st.stats->imu_duplicates;  // replayed before it arrived
    return;
  }
  if (st.have_imu && s.seq > st.last_imu + 1U && st.cfg->checkpoint_every != 0U && !replay(st, s.seq, budget)) {
    st.catching_up = true;  // the rest of the gap (and this sample) come from the record next jobs
    return;
  }
  if (st.have_imu && s.seq <= st.last_imu) {
    ++st.stats->imu_duplicates;
    return;
  }
  add_sample(st, s);
}

/** The held samples that are due now, in order. */
void take_held(TaskState& st, std::uint32_t& budget) noexcept {
  const std::uint32_t count = std::min(st.held_count, kImuHeld);  // an upset may have left it larger
  std::uint32_t n = 0;
  for (; n < count && imu_due(st, st.held[n].seq); ++n) {
    take_sample(st, st.held[n], budget);
  }
  for (std::uint32_t i = n; i < count; ++i) {
    st.held[i - n] = st.held[i];
  }
  st.held_count = count - n;
}

/** What a handler of kChanImu acts on: the filter task's state and the job's replay budget. */
struct ImuInbox {
  TaskState& st;
  std::uint32_t& budget;
};

/** A telecommand in the IMU stream: held until the job that takes the sample sent before it. */
void take_command_msg(ImuInbox& in, const Command& c) noexcept { hold_command(in.st, c); }

/** A sample: into the record if it is due and none waits before it, else held for its job. */
void take_imu_msg(ImuInbox& in, const bsp::ImuSample& s) noexcept {
  TaskState& st = in.st;
  if (st.held_count == 0U && imu_due(st, s.seq)) {
    take_sample(st, s, in.budget);
  } else if (st.held_count < kImuHeld) {
    st.held[st.held_count] = s;
    ++st.held_count;
  } else {
    ++st.stats->imu_rejected;  // more early samples than a healthy stream sends: dropped, replayed from DDR
  }
}

/** The tagged kinds the filter takes on kChanImu; the untagged words there are IMU samples. */
constexpr std::array<fdir::msg::Handler<ImuInbox>, 1> kImuChannelHandlers{{
    fdir::msg::on<kCommandMsg, &take_command_msg, ImuInbox>(),
}};
constexpr fdir::msg::Handler<ImuInbox> kImuSampleHandler = fdir::msg::on<kImuMsg, &take_imu_msg, ImuInbox>();
static_assert(fdir::msg::handlers_fit(kImuChannelHandlers, kChanImu, role_bit(Role::kFilter)) &&
                  fdir::msg::untagged_fits(kImuSampleHandler, kChanImu, role_bit(Role::kFilter)),
              "the filter's handlers on kChanImu are kinds declared for it there");

/**
 * Puts the due samples (held ones, then up to kMaxImuPerJob waiting on
 * kChanImu) into the record, filling gaps from the DDR record; holds early
 * ones; takes a telecommand once the sample before it is in.
 */
void consume_imu(TaskState& st) noexcept {
  udn::FtMessage msg{};
  std::uint32_t budget = kMaxReplayPerJob;
  take_held(st, budget);
  ImuInbox in{st, budget};
  for (std::uint32_t n = 0; n < kMaxImuPerJob; ++n) {
    if (udn::endpoint_receive(kChanImu, msg) != udn::FtError::kOk) {
      break;
    }
    const std::span<const std::uint32_t> w(msg.data.data(), msg.data_words);
    if (fdir::msg::dispatch(kImuChannelHandlers, kImuSampleHandler, w, in) != fdir::msg::Dispatch::kTaken) {
      ++st.stats->imu_rejected;  // a telecommand or a sample its decoder refused
    }
  }
  // A due sample the network has not brought (lost, or sent to the tile a role left) comes from the
  // I/O tile's record: which samples a job takes does not depend on the network's timing.
  if (st.have_imu && st.cfg->checkpoint_every != 0U && st.job >= kImuLagJobs) {
    (void)replay(st, st.job - kImuLagJobs + 1U, budget);
  }
  take_command(st);
}

/** Moves the held matches whose job has come into the record, in order, as many as it takes. */
void take_held_matches(TaskState& st, bsp::Work& work) noexcept {
  st.mheld_count = std::min(st.mheld_count, kHeldMatches);  // an upset may have left it larger
  std::uint32_t n = 0;
  for (; n < st.mheld_count && st.mheld_job[n] <= st.job; ++n) {
    const std::span<const std::uint32_t, kMatchWords> m(st.mheld.data() + static_cast<std::size_t>(n) * kMatchWords,
                                                        kMatchWords);
    if (!record_add_match(st.record, m)) {
      break;  // the record is full: the rest next job
    }
  }
  for (std::uint32_t i = n; i < st.mheld_count; ++i) {
    for (std::uint32_t k = 0; k < kMatchWords; ++k) {
      st.mheld[static_cast<std::size_t>(i - n) * kMatchWords + k] = st.mheld[static_cast<std::size_t>(i) * kMatchWords + k];
    }
    st.mheld_job[i - n] = st.mheld_job[i];
  }
  work.mem_words += 2ULL * kMatchWords * st.mheld_count;
  st.mheld_count -= n;
  if (n != 0U) {
    ++st.mheld_changes;
  }
}

/** A match for job @p job: into the record if its job has come and none waits before it, else held. */
void take_match(TaskState& st, std::span<const std::uint32_t, kMatchWords> m, std::uint32_t job) noexcept {
  if (job <= st.job && st.mheld_count == 0U && record_add_match(st.record, m)) {
    return;
  }
  if (st.mheld_count >= kHeldMatches) {
    ++st.stats->matches_dropped;  // more than a frame waiting: only a broken sender does that
    return;
  }
  for (std::uint32_t k = 0; k < kMatchWords; ++k) {
    st.mheld[static_cast<std::size_t>(st.mheld_count) * kMatchWords + k] = m[k];
  }
  st.mheld_job[st.mheld_count] = job;
  ++st.mheld_count;
  ++st.mheld_changes;
}

/**
 * Puts into the record the held matches due now, then those of the parts
 * waiting on kChanMatches (a part says which job takes it; earlier ones wait).
 */
void consume_parts(TaskState& st) noexcept {
  udn::FtMessage msg{};
  bsp::Work work{};
  take_held_matches(st, work);
  for (std::uint32_t p = 0; p < kMaxPartsPerJob; ++p) {
    if (udn::endpoint_receive(kChanMatches, msg) != udn::FtError::kOk) {
      break;  // empty, or the node is not open yet
    }
    ++st.stats->parts_received;
    work.int_ops += 8ULL + 2ULL * msg.data_words;
    const std::span<const std::uint32_t> words(msg.data.data(), msg.data_words);
    MatchPart part{};
    // Checked against the seal the coordinator took as it made the part, before anything of it is read.
    if (!result_sealed(words) || !fdir::msg::decode(kMatchesMsg, words, part)) {
      ++st.stats->parts_bad;
      const std::uint32_t lost = msg.data_words > kMatchHeaderWords ? (msg.data_words - kMatchHeaderWords) / kMatchWords : 0U;
      trn::report(ev::kResultSealBroken, msg.source, ev::kSealBatchPart, msg.data_words > 1U ? msg.data[1] : 0U, lost);
      continue;
    }
    for (std::uint32_t i = 0; i < part.n; ++i) {
      const std::size_t at = kMatchHeaderWords + static_cast<std::size_t>(i) * kMatchWords;
      take_match(st, std::span<const std::uint32_t, kMatchWords>(msg.data.data() + at, kMatchWords), part.apply_job);
      ++st.stats->matches_received;
    }
    work.mem_words += 2ULL * msg.data_words;  // read from the node, written into the record
  }
  bsp::consume(work);
}

// ------------------------------------------------------------------ the voter: outputs

/**
 * Publishes and sends the solution of job @p job if it is the next one due; never twice, never back.
 * @p seal is the CRC-32C of @p words taken where they were computed (the job's own encoding, or the
 * vote): the copy that leaves is checked against it, and made again from @p words if it changed.
 */
void deliver(TaskState& st, std::uint32_t job, std::span<const std::uint32_t, kNavWords> words, std::uint32_t seal) noexcept {
  if (st.delivered_any && job < st.next_deliver) {
    return;  // delivered already
  }
  if (st.delivered_any && job > st.next_deliver) {
    st.stats->outputs_skipped += job - st.next_deliver;
  }
  std::array<std::uint32_t, kNavWords> w{};
  std::copy(words.begin(), words.end(), w.begin());
  // The solution as sent is what a fault may corrupt on its way out (every bit of it is delivered).
  (void)bsp::publish_filter(kNavChannel, w.data(), sizeof w);
  bsp::consume(bsp::Work{8ULL * kNavWords, 0U, 0U, 0U, kNavWords});
  if (udn::crc32c_words(w) != seal) {
    ++st.stats->outputs_resealed;
    trn::report(ev::kResultSealBroken, bsp::current_tile(), ev::kSealSolution, job, 0U);
    std::copy(words.begin(), words.end(), w.begin());
  }
  st.output->latest = fdir::msg::read(kNavMsg, w);
  st.output->delivered = true;
  const std::array<std::uint32_t, 1> j{job};
  st.stats->output_crc = udn::crc32c_words_continue(udn::crc32c_words_continue(st.stats->output_crc, j), w);
  ++st.stats->outputs_delivered;
  st.stats->last_delivered_job = job;
  if ((job + 1U) % kOutputMarkJobs == 0U) {
    st.stats->mark_job = job;
    st.stats->mark_crc = st.stats->output_crc;
  }
  st.delivered_any = true;
  st.next_deliver = job + 1U;
  bsp::consume(bsp::Work{2ULL * kNavWords, 0U, 0U, 0U, kNavWords});
  if (st.cfg->coordinator_tile == bsp::kNoTile) {
    return;
  }
  const bsp::TileId sink = udn::endpoint_role_tile(kSlotCoordinator, st.cfg->coordinator_tile);
  if (udn::endpoint_send(sink, kChanNav, w, 0U) == udn::FtError::kOk) {
    ++st.stats->nav_sent;
  } else {
    ++st.stats->nav_send_failed;
  }
}

bool resume_from_checkpoint(TaskState& st, std::uint32_t not_seq, std::span<const VotedCheckpoint> voted = {}) noexcept;

/**
 * The tile asks to be restarted (assertion @p id), once: its health agent stops the watchdog's
 * kicks, and the restarted task resumes from its last good checkpoint with everything else built
 * afresh.
 */
void ask_restart(TaskState& st, std::uint32_t id) noexcept {
  if (!st.recovery_asked) {
    st.recovery_asked = true;
    fdir::assert_failed(id, __LINE__);
  }
}

/**
 * Back to the last checkpoint after a failed job. When it is the one the last failure went back to
 * (or there is none), what is wrong is not in the state a checkpoint holds: ask_restart(@p id).
 */
void go_back(TaskState& st, std::uint32_t id) noexcept {
  if (resume_from_checkpoint(st, st.rolled_back_to)) {
    st.rolled_back_to = st.ckpt_seq;
    ++st.stats->rollbacks;
  } else {
    ask_restart(st, id);
  }
}

/** What a failed window adds to the covariance's diagonal (FilterTaskConfig::widen_*). */
filter::Vec15 widen_variances(const FilterTaskConfig& cfg) noexcept {
  filter::Vec15 var = filter::Vec15::Zero();
  const double p = static_cast<double>(cfg.widen_pos_m);
  const double v = 0.01 * static_cast<double>(cfg.widen_vel_cmps);
  const double th = 0.001 * static_cast<double>(cfg.widen_att_mrad);
  var.segment<3>(filter::kIdxP).setConstant(p * p);
  var.segment<3>(filter::kIdxV).setConstant(v * v);
  var.segment<3>(filter::kIdxTh).setConstant(th * th);
  return var;
}

/**
 * The innovation monitor after a simplex job whose state passed its check
 * (fdir/innovation_monitor.hpp): the job's measurements that reached the gate
 * (@p rep) go into its window. A failed window is reported
 * (filter_innovations_bad) and the covariance widened, so that the matches
 * are weighed again and pull the state back (the window starts again); when
 * the next full window fails too, widening did not help and the tile asks to
 * be restarted (kAssertFilterInnovations).
 */
void watch_innovations(TaskState& st, const filter::UpdateReport& rep, std::uint32_t job) noexcept {
  bsp::Work work{};
  fdir::InnovationWindow win{};
  const fdir::InnovationVerdict v =
      fdir::innovation_add(st.innov, st.cfg->innovation, st.cfg->filter.gate_chi2, rep.accepted + rep.rejected_gate,
                           rep.rejected_gate, rep.nis_sum, win, work);
  bsp::consume(work);
  if (v == fdir::InnovationVerdict::kNone) {
    return;
  }
  FilterTaskStats& s = *st.stats;
  ++s.innovation_windows;
  const std::uint32_t rej_permille = win.n != 0U ? static_cast<std::uint32_t>(
                                                       (1000ULL * win.rejected) / win.n) : 0U;
  s.max_window_nis_milli = win.mean_nis_milli > s.max_window_nis_milli ? win.mean_nis_milli : s.max_window_nis_milli;
  s.max_window_reject_permille = rej_permille > s.max_window_reject_permille ? rej_permille : s.max_window_reject_permille;
  if (v == fdir::InnovationVerdict::kConsistent) {
    st.widened = false;
    return;
  }
  ++s.innovations_bad;
  fdir::innovation_clear(st.innov);
  const std::uint32_t cause = (v == fdir::InnovationVerdict::kRejectedHigh ? 1U : 2U) + (st.widened ? 2U : 0U);
  const std::uint32_t n16 = win.n < 0xFFFFU ? win.n : 0xFFFFU;
  const std::uint32_t r16 = win.rejected < n16 ? win.rejected : n16;
  trn::report(ev::kFilterInnovationsBad, job, cause, n16 | (r16 << 16U), win.mean_nis_milli);
  if (st.widened) {
    ask_restart(st, kAssertFilterInnovations);
    return;
  }
  st.widened = true;
  st.core.ekf->widen(widen_variances(*st.cfg));
  bsp::consume(st.core.ekf->take_work());
}

/**
 * Simplex: runs record @p rec and checks the state after it against the one
 * before. False when it failed: nothing is delivered, and the task goes back
 * to its last checkpoint (once per checkpoint: a checkpoint that fails again
 * is not gone back to twice).
 */
bool run_checked(TaskState& st, const JobRecord& rec) noexcept {
  bsp::Work work{};
  const filter::StateBefore before = filter::state_before(st.core.ekf->state(), work);
  const filter::UpdateReport rep = core_run(st.core, rec);
  // The settings first: an upset there explains a state that fails, and going back to a checkpoint
  // with them still wrong would fail again. Checked after the job, so a job that passes ran with
  // them whole from its start (an upset stays until they are rebuilt).
  const std::uint32_t changed = core_settings_changed(st.core, work);
  if (changed != 0U) {
    const bool rebuilt = core_reload_settings(st.core, work);
    bsp::consume(work);
    ++st.stats->settings_rebuilt;
    trn::report(ev::kFilterSettingsBad, record_job(rec), changed, rebuilt ? 1U : 0U);
    // Every state since the upset was computed with them: back to the last checkpoint. Changed
    // again before the next one (a stuck bit, say), or not rebuilt: the tile asks for its restart.
    if (!rebuilt) {
      ask_restart(st, kAssertFilterSettingsChanged);
    } else if (st.ckpt != nullptr) {
      go_back(st, kAssertFilterSettingsChanged);
    }
    return false;
  }
  const filter::StateCheckResult r = filter::check_state(before, st.core.ekf->state(), st.cfg->envelope, work);
  bsp::consume(work);
  if (r.what == filter::StateCheck::kOk) {
    watch_innovations(st, rep, record_job(rec));
    return true;
  }
  ++st.stats->states_rejected;
  trn::report(ev::kFilterStateBad, record_job(rec), static_cast<std::uint32_t>(r.what),
              filter::state_check_field(r.value, r.what), filter::state_check_field(r.limit, r.what));
  go_back(st, kAssertFilterStateRefused);
  return false;
}

/**
 * The voter's own solution of record @p rec, as words (and kept while starting, to compare).
 * @return false when its state was refused (simplex): nothing delivered.
 */
bool run_own(TaskState& st, const JobRecord& rec) noexcept {
  if (st.mode == Mode::kSimplex) {
    if (!run_checked(st, rec)) {
      return false;
    }
  } else {
    core_run(st.core, rec);
  }
  std::array<std::uint32_t, kNavWords> w{};
  (void)fdir::msg::encode(kNavMsg, core_output(st.core), w);
  const std::uint32_t seal = udn::crc32c_words(w);  // where the solution is computed
  bsp::consume(bsp::Work{8ULL * kNavWords, 0U, 0U, 0U, kNavWords});
  if (st.mode == Mode::kStarting) {
    fdir::TmrRecord& r = st.own[st.job % kOutRing];
    r.job = record_job(rec);
    r.words = kVotedWords;
    for (std::uint32_t i = 0; i < kNavWords; ++i) {
      r.w[i] = w[i];
    }
    bsp::Work work{};
    r.w[kNavWords] = core_digest(st.core, work);
    bsp::consume(work);
  }
  deliver(st, record_job(rec), w, seal);
  return true;
}

/** Every checkpoint_every jobs (not while catching up): the whole state to DDR. */
void checkpoint(TaskState& st) noexcept {
  if (st.ckpt == nullptr || st.catching_up || !st.core.have_imu ||
      ++st.since_ckpt < st.cfg->checkpoint_every) {
    return;
  }
  st.since_ckpt = 0U;
  bsp::Work work{};
  st.ckpt_slot = 1U - st.ckpt_slot;
  // Numbered by job, so that a replica's later checkpoint is the newer one.
  st.ckpt_seq = st.job / st.cfg->checkpoint_every + 1U;
  checkpoint_write(*st.ckpt, st.core.ekf->state(), st.core.last_imu, st.ckpt_seq, st.ckpt_slot, work);
  bsp::consume(work);
  ++st.stats->checkpoints;
}

bool rejoin(TaskState& st, std::uint32_t job) noexcept;

/**
 * The core, then the task's own state and its output record, in the running tile's RAM (the state
 * after the core's carves: they keep the places they had before it lived in tile RAM).
 * @return the state, value-initialised but for the core and its pointers; nullptr for a bad
 *         configuration or a region too short.
 */
[[gnu::noinline]] TaskState* carve_task_state(const FilterTaskConfig& cfg) noexcept {
  if (cfg.matches_per_job == 0U || cfg.matches_per_job > kMaxMatchesPerFrame || !fdir::innovation_config_ok(cfg.innovation)) {
    return nullptr;
  }
  const bsp::Region ram{bsp::current_tile()};
  FilterCore core{};
  if (!core_set_up(core, cfg, ram)) {
    return nullptr;
  }
  bsp::MemError err = bsp::MemError::kOk;
  TaskState* const st = bsp::carve_record(ram, bsp::RamRecord<TaskState>{kFilterTaskCarve, &kTaskStateLayout}, &err);
  FilterOutput* const out = st != nullptr ? bsp::carve_record(ram, kFilterOutputRecord, &err) : nullptr;
  if (out == nullptr) {
    return nullptr;
  }
  st->core = core;
  st->cfg = &cfg;
  st->stats = core.stats;
  st->output = out;
  return st;
}

// Never inlined: Clang once inlined it into filter_task_main when its checkpoint read held a whole
// FilterState (about 18 KiB) on the stack, and the loop's frame kept those bytes for the whole flight
// (the 32 KiB stack overflowed into the next task's saved context when the filter went TMR). The state
// now stays in the block reader's static scratch; the attribute keeps set-up out of the loop's frame.
[[gnu::noinline]] bool set_up(TaskState& st, const FilterTaskConfig& cfg) noexcept {
  st.tmr = cfg.replica_tiles[0] != bsp::kNoTile ? tmr_area() : nullptr;
  if (st.tmr != nullptr && st.tmr->control.mode != 0U) {
    const auto job = static_cast<std::uint32_t>(bsp::now() / (std::uint64_t{kFilterPeriodTicks} * bsp::tick_cycles()));
    if (rejoin(st, job)) {
      return st.core.ekf->init(cfg.initial) == filter::FilterStatus::kOk;  // it votes: its own filter waits
    }
    // Not voting when it stopped, or out too long: simplex (the replicas go idle) until it has
    // caught up from its checkpoint, then the TMR starts again from its state.
    st.tmr->control.mode = 0U;
    st.resume_tmr = true;
    trn::report(ev::kTmrSimplex, job, kTmrStopRestart);
  }
  st.ckpt = cfg.checkpoint_every != 0U ? checkpoint_area() : nullptr;
  st.ring = cfg.checkpoint_every != 0U ? imu_ring() : nullptr;
  // A checkpoint left by an earlier start (a reset, or the tile this role moved from).
  if (resume_from_checkpoint(st, 0U)) {
    st.stats->resumed_from = st.ckpt_seq;
    return true;
  }
  return st.core.ekf->init(cfg.initial) == filter::FilterStatus::kOk;
}

/**
 * The newest good checkpoint into the filter, the IMU samples since it to be
 * replayed from the I/O tile's record (kFilterResumed). Its state stays in the
 * reader's scratch, restored before any call that may switch tiles.
 * @return false when there is none, or it is checkpoint @p not_seq (nothing changed; 0: any will do).
 * With @p voted not empty, only a checkpoint the TMR vote confirmed will do.
 */
bool resume_from_checkpoint(TaskState& st, std::uint32_t not_seq, std::span<const VotedCheckpoint> voted) noexcept {
  if (st.ckpt == nullptr) {
    return false;
  }
  bsp::Work work{};
  const CheckpointRead r = checkpoint_read(*st.ckpt, work, voted);
  const bool restored = r.found && (not_seq == 0U || r.seq != not_seq) &&
                        st.core.ekf->restore(*r.state) == filter::FilterStatus::kOk;
  bsp::consume(work);
  if (r.bad != 0U) {
    trn::report(ev::kCheckpointBad, r.bad_slot, 0U, r.bad);
  }
  if (!restored) {
    return false;
  }
  st.core.have_imu = true;
  st.core.last_imu = r.imu_seq;
  st.have_imu = true;
  st.last_imu = r.imu_seq;
  st.catching_up = true;
  st.ckpt_seq = r.seq;
  st.ckpt_slot = r.slot;
  st.since_ckpt = 0U;
  const std::uint32_t recorded = st.ring != nullptr ? st.ring->written : 0U;
  trn::report(ev::kFilterResumed, r.seq, 0U, recorded > r.imu_seq + 1U ? recorded - r.imu_seq - 1U : 0U,
               r.imu_seq);
  return true;
}

// ------------------------------------------------------------------ the voter: TMR

bsp::TileId replica_tile(const TaskState& st, std::uint32_t i) noexcept {
  return udn::endpoint_role_tile(kSlotReplica0 + i, st.cfg->replica_tiles[i]);
}

/** What a handler of the replicas' messages acts on: the filter task's state and the words received. */
struct ReplicaInbox {
  TaskState& st;
  std::span<const std::uint32_t> words;
};

void take_hello(ReplicaInbox& in, const ReplicaHello& hello) noexcept {
  in.st.hello_mask |= 1U << hello.replica;
  if (hello.refused != 0U) {
    in.st.refused_mask |= 1U << hello.replica;
  }
}

/**
 * Keeps replica @p i's output of job @p job (its solution's words @p nav, any bits, and its state
 * digest), and whether the words still match @p out_crc, the CRC the replica took where it computed
 * them: an output that fails it is voted as different and never wins (fdir::tmr_vote's bad_mask).
 */
void keep_output(TaskState& st, std::uint32_t i, std::uint32_t job, std::span<const std::uint32_t, kNavWords> nav,
                 std::uint32_t digest, std::uint32_t out_crc) noexcept {
  fdir::TmrRecord& r = st.out[i][job % kOutRing];
  r.job = job;
  r.words = kVotedWords;
  std::copy(nav.begin(), nav.end(), r.w.begin());
  r.w[kNavWords] = digest;
  const std::uint32_t bit = 1U << i;
  std::uint32_t& bad = st.out_bad[job % kOutRing];
  bad = udn::crc32c_words(nav) == out_crc ? (bad & ~bit) : (bad | bit);
  bsp::consume(bsp::Work{8ULL * kNavWords, 0U, 0U, 0U, 2ULL * kNavWords});
}

/** A replica's output as it came. */
void take_replica_out(ReplicaInbox& in, const ReplicaOut& out) noexcept {
  keep_output(in.st, out.replica, out.job,
              std::span<const std::uint32_t, kNavWords>(in.words.data() + kReplicaOutHeaderWords, kNavWords),
              out.digest, out.out_crc);
}

/** A replica's output its replica kept in DDR (the CRC after the voted words). */
void keep_kept_output(TaskState& st, std::uint32_t i, const fdir::TmrRecord& kept) noexcept {
  keep_output(st, i, kept.job, std::span<const std::uint32_t, kNavWords>(kept.w.data(), kNavWords), kept.w[kNavWords],
              kept.w[kNavWords + 1U]);
}

/** The kinds the filter takes on kChanNav; anything else there is dropped. */
constexpr std::array<fdir::msg::Handler<ReplicaInbox>, 2> kReplicaHandlers{{
    fdir::msg::on<kReplicaHelloMsg, &take_hello, ReplicaInbox>(),
    fdir::msg::on<kReplicaOutMsg, &take_replica_out, ReplicaInbox>(),
}};
static_assert(fdir::msg::handlers_fit(kReplicaHandlers, kChanNav, role_bit(Role::kFilter)),
              "the voter's handlers are kinds declared for the filter on kChanNav");

/** Takes the replicas' outputs and hellos waiting on kChanNav. */
void drain_replicas(TaskState& st) noexcept {
  udn::FtMessage m{};
  for (std::uint32_t n = 0; n < 4U * kReplicas && udn::endpoint_receive(kChanNav, m) == udn::FtError::kOk; ++n) {
    ReplicaInbox in{st, std::span<const std::uint32_t>(m.data.data(), m.data_words)};
    (void)fdir::msg::dispatch(kReplicaHandlers, in.words, in);
  }
}

const fdir::TmrRecord* output_of(const TaskState& st, std::uint32_t i, std::uint32_t job) noexcept {
  const fdir::TmrRecord& r = st.out[i][job % kOutRing];
  return (r.words == kVotedWords && r.job == job) ? &r : nullptr;
}

/** Replica @p i's output of job @p job, if it is here and passed its CRC (nullptr otherwise). */
const fdir::TmrRecord* good_output_of(const TaskState& st, std::uint32_t i, std::uint32_t job) noexcept {
  return (st.out_bad[job % kOutRing] & (1U << i)) == 0U ? output_of(st, i, job) : nullptr;
}

/** True if every voting replica's output for job @p job is here. */
bool all_present(const TaskState& st, std::uint32_t job) noexcept {
  for (std::uint32_t i = 0; i < kReplicas; ++i) {
    if ((st.group.active_mask() & (1U << i)) != 0U && output_of(st, i, job) == nullptr) {
      return false;
    }
  }
  return true;
}

/** Switch to TMR after this job: the voter's state is the replicas' seed. */
void start_tmr(TaskState& st) noexcept {
  if (st.tmr == nullptr || st.mode != Mode::kSimplex) {
    return;
  }
  TmrControl& c = st.tmr->control;
  ++c.epoch;
  c.mode = 1U;
  c.seed_by = kNoReplica;
  c.ckpt_by = kNoReplica;
  bsp::Work work{};
  tmr_write_seed(*st.tmr, st.core, st.job, fdir::kTmrAllReplicas, work);
  bsp::consume(work);
  (void)st.group.configure(st.cfg->tmr);
  st.mode = Mode::kStarting;
  st.start_job = st.job;
  st.hello_mask = 0U;
  st.refused_mask = 0U;
  st.seeded_differ = {};
  st.seed_asked = 0U;
  st.no_majority_mask = 0U;
  st.no_majority_run = 0U;
  st.voted_ckpt = {};
  trn::report(ev::kTmrStarting, st.job, c.epoch);
}

/** Back to simplex (the voter runs its own state): replicas go idle. */
void stop_tmr(TaskState& st, std::uint32_t reason) noexcept {
  st.tmr->control.mode = 0U;
  st.mode = Mode::kSimplex;
  trn::report(ev::kTmrSimplex, st.job, reason);
}

/** While starting: a replica whose output equals the voter's own joins; all three: TMR runs. */
void compare_starting(TaskState& st, std::uint32_t v) noexcept {
  const fdir::TmrRecord& own = st.own[v % kOutRing];
  if (own.job != v || own.words != kVotedWords) {
    return;
  }
  for (std::uint32_t i = 0; i < kReplicas; ++i) {
    const fdir::TmrRecord* r = good_output_of(st, i, v);
    if (r != nullptr && fdir::tmr_same(*r, own) && (st.group.active_mask() & (1U << i)) == 0U) {
      st.group.admit(i);
    }
  }
  if (st.group.active_count() == kReplicas) {
    st.mode = Mode::kTmr;
    st.next_vote = v + 1U;  // delivered already, by the voter's own filter
    st.tmr->control.ckpt_by = 0U;
    trn::report(ev::kTmrEstablished, v, st.tmr->control.epoch, st.job - st.start_job);
  } else if (st.job - st.start_job > kStartJobs) {
    stop_tmr(st, kTmrStopNotEstablished);
  }
}

/** Reports what the vote says of each replica; excludes past the thresholds. */
void account_vote(TaskState& st, const fdir::TmrVote& v, std::uint32_t job) noexcept {
  std::array<std::uint32_t, kReplicas> before{};
  for (std::uint32_t i = 0; i < kReplicas; ++i) {
    before[i] = st.group.count(i).disagree_in_row;
  }
  const std::uint32_t active = st.group.active_mask();
  const std::uint32_t out = st.group.account(v);
  for (std::uint32_t i = 0; i < kReplicas; ++i) {
    const std::uint32_t bit = 1U << i;
    if ((active & bit) == 0U) {
      continue;
    }
    if (((v.differ_mask | v.missing_mask) & bit) != 0U) {
      ++st.stats->tmr_outvoted;
      const bool bad = (st.out_bad[job % kOutRing] & bit) != 0U && output_of(st, i, job) != nullptr;
      const bool refused = (v.missing_mask & bit) != 0U && (st.refused_mask & bit) != 0U;
      trn::report(ev::kTmrOutvoted, replica_tile(st, i), job, i,
                  bad ? 3U : refused ? 4U : (v.differ_mask & bit) != 0U ? 1U : 2U);
    } else if (before[i] != 0U || (st.no_majority_mask & bit) != 0U) {
      trn::report(ev::kTmrAgrees, replica_tile(st, i), job, i, before[i]);
    }
    st.no_majority_mask &= ~bit;
    if ((out & bit) != 0U) {
      ++st.stats->tmr_exclusions;
      ++st.tmr->control.gen[i];  // it drops its state and waits for a seed
      trn::report(ev::kTmrExcluded, replica_tile(st, i), job, i, st.group.active_count());
    }
  }
}

/**
 * A replica not voting whose output equals the vote is readmitted (it loaded a seed). One that sends
 * outputs (it is seeded) but differs from the vote kOutRing times in a row has a wrong state again
 * (hit after its seed): it is outvoted and made to drop its state, to ask for another seed. Before,
 * it ran on with that state, never readmitted, and the group stayed two for the rest of the descent.
 */
void readmit(TaskState& st, const fdir::TmrRecord& voted, std::uint32_t job) noexcept {
  for (std::uint32_t i = 0; i < kReplicas; ++i) {
    if ((st.group.active_mask() & (1U << i)) != 0U || output_of(st, i, job) == nullptr) {
      continue;
    }
    const fdir::TmrRecord* r = good_output_of(st, i, job);
    if (r != nullptr && fdir::tmr_same(*r, voted)) {
      st.group.admit(i);
      ++st.stats->tmr_resyncs;
      st.hello_mask &= ~(1U << i);
      st.refused_mask &= ~(1U << i);
      st.seeded_differ[i] = 0U;
      trn::report(ev::kTmrResynced, replica_tile(st, i), job, i, st.group.active_count());
    } else if (++st.seeded_differ[i] >= kOutRing) {
      st.seeded_differ[i] = 0U;
      ++st.stats->tmr_outvoted;
      ++st.tmr->control.gen[i];  // it drops its state and waits for a seed
      trn::report(ev::kTmrOutvoted, replica_tile(st, i), job, i, 1U);
    }
  }
}

/**
 * The replicas' states have parted (kNoMajorityToFallBack votes without a majority): the voter goes
 * on alone from the newest checkpoint whose state digest the vote agreed on, the IMU samples since
 * replayed from the I/O tile's record, and reports it (tmr_fallback); the filter supervisor chooses
 * TMR again (seeded from this state) or simplex. Without such a checkpoint it keeps voting.
 */
void fall_back(TaskState& st, std::uint32_t v) noexcept {
  if (st.cfg->checkpoint_every == 0U) {
    return;
  }
  if (st.ckpt == nullptr) {
    st.ckpt = checkpoint_area();
  }
  if (!resume_from_checkpoint(st, 0U, st.voted_ckpt)) {
    return;
  }
  // The matches its core held were for the state it had when TMR started: gone with it.
  core_drop_matches(st.core);
  st.rolled_back_to = 0U;
  stop_tmr(st, kTmrStopNoMajority);
  trn::report(ev::kTmrFallback, v, st.no_majority_run, st.ckpt_seq, (st.ckpt_seq - 1U) * st.cfg->checkpoint_every);
  st.no_majority_run = 0U;
}

/** A voted job that a replica checkpointed: its number and the voted digest, kept for fall_back(). */
void note_voted_checkpoint(TaskState& st, std::uint32_t v, std::uint32_t digest) noexcept {
  const std::uint32_t every = st.cfg->checkpoint_every;
  if (every != 0U && v % every == 0U) {
    st.voted_ckpt[(v / every) % 2U] = VotedCheckpoint{v / every + 1U, digest};
  }
}

/** Votes job @p v; delivers the voted solution; counts, excludes, readmits. */
void vote(TaskState& st, std::uint32_t v) noexcept {
  std::array<const fdir::TmrRecord*, kReplicas> recs{};
  for (std::uint32_t i = 0; i < kReplicas; ++i) {
    recs[i] = output_of(st, i, v);
  }
  const fdir::TmrVote res = fdir::tmr_vote(recs, st.group.active_mask(), st.out_bad[v % kOutRing]);
  bsp::consume(bsp::Work{4ULL * kVotedWords * kReplicas, 0U, 0U, 0U, std::uint64_t{kVotedWords} * kReplicas});
  if (res.verdict == fdir::TmrVerdict::kNoMajority) {
    ++st.stats->tmr_no_majority;
    st.no_majority_mask |= res.differ_mask;
    // The replicas' tiles go with the masks: the suspects of a vote that could not name one.
    std::uint32_t tiles = 0U;
    for (std::uint32_t i = 0; i < kReplicas; ++i) {
      tiles |= (replica_tile(st, i) & 0xFFU) << (8U * (i + 1U));
    }
    trn::report(ev::kTmrNoMajority, v, st.group.active_mask(), res.differ_mask,
                 (res.missing_mask & 0xFFU) | tiles);
    if (++st.no_majority_run >= kNoMajorityToFallBack) {
      fall_back(st, v);
    }
    return;
  }
  st.no_majority_run = 0U;
  account_vote(st, res, v);
  const fdir::TmrRecord& voted = *recs[res.winner];
  readmit(st, voted, v);
  ++st.stats->tmr_jobs;
  // The voted words passed the CRC their replica took where it computed them (keep_output): sealed here.
  const std::span<const std::uint32_t, kNavWords> voted_words(voted.w.data(), kNavWords);
  bsp::consume(bsp::Work{8ULL * kNavWords, 0U, 0U, 0U, kNavWords});
  deliver(st, v, voted_words, udn::crc32c_words(voted_words));
  note_voted_checkpoint(st, v, voted.w[kNavWords]);
  st.last_winner = res.winner;
  if (st.mode == Mode::kStopping && v == st.stop_job) {
    st.stop_voted = true;
    st.stop_digest = voted.w[kNavWords];
  }
  if (st.mode == Mode::kStopping) {
    return;  // the seed area is the voter's until it is simplex again
  }
  // A replica that asked for a seed (rebooted, or excluded) gets one from the voted state.
  const std::uint32_t waiting = st.hello_mask & ~st.group.active_mask();
  TmrControl& c = st.tmr->control;
  if (waiting != 0U && (st.seed_asked == 0U || st.seed_asked > kOutRing)) {
    c.seed_for = waiting;
    c.seed_job = st.job;  // the record written this job: the winner saves its state after it
    c.seed_by = res.winner;
    st.seed_asked = 1U;
    st.hello_mask = 0U;
  } else if (st.seed_asked != 0U) {
    ++st.seed_asked;
  }
  if (c.ckpt_by >= kReplicas || (st.group.active_mask() & (1U << c.ckpt_by)) == 0U) {
    c.ckpt_by = res.winner;
  }
}

/**
 * Back to simplex, on command: the replica that agreed with the last vote
 * saves its state after this job's record for the voter (asked before the
 * record is written, so the replica that runs it sees the request).
 */
void begin_stop(TaskState& st) noexcept {
  TmrControl& c = st.tmr->control;
  c.seed_for = kVoterBit;
  c.seed_job = st.job;
  c.seed_by = st.last_winner;
  st.stop_job = st.job;
  st.stop_voted = false;
  st.stop_again = false;
  st.mode = Mode::kStopping;
}

/**
 * Once the stop job is voted: loads the replica's state after it if its
 * digest is the voted one, runs the records written since (in the DDR ring)
 * and delivers their solutions, and is simplex from this job on: no job
 * missed, none twice. Without a good state in time it asks again.
 */
void finish_stop(TaskState& st, std::uint32_t voted_job) noexcept {
  if (voted_job < st.stop_job) {
    return;
  }
  const TmrSeed& seed = st.tmr->seed;
  const bool good = st.stop_voted && seed.job == st.stop_job && (seed.for_mask & kVoterBit) != 0U &&
                    seed.epoch == st.tmr->control.epoch && tmr_seed_ok(seed) && seed.digest == st.stop_digest;
  bsp::Work work{};
  if (!good || !core_load(st.core, seed.image, work)) {
    bsp::consume(work);
    st.stop_again = st.job - st.stop_job >= kOutRing;
    return;
  }
  bsp::consume(work);
  // The records after the stop job, this one last: the voter's own state catches up with the stream.
  for (std::uint32_t j = st.stop_job + 1U; j < st.job && j - st.stop_job < kJobRingLen; ++j) {
    const JobRecord& rec = st.tmr->ring[j % kJobRingLen];
    bsp::Work rw{};
    const bool ok = record_ok(rec, j, rw);
    bsp::consume(rw);
    if (!ok) {
      st.stop_again = true;  // overwritten or damaged: the state cannot be brought up to date
      return;
    }
    run_own(st, rec);
  }
  run_own(st, st.record);
  stop_tmr(st, kTmrStopCommand);
}

/** The voter's place in the stream @p f, as a restarted voter takes it back (rejoin). */
void take_place(TaskState& st, const TmrVoter& f) noexcept {
  st.mode = Mode::kTmr;
  st.next_vote = f.next_vote;
  st.next_deliver = f.next_deliver;
  st.delivered_any = f.delivered_any != 0U;
  st.stats->outputs_delivered = f.outputs_delivered;
  st.stats->outputs_skipped = f.outputs_skipped;
  st.stats->output_crc = f.output_crc;
  st.stats->last_delivered_job = f.last_delivered_job;
  st.stats->mark_job = f.mark_job;
  st.stats->mark_crc = f.mark_crc;
  st.have_imu = f.have_imu != 0U;
  st.last_imu = f.last_imu;
  st.cmd_held = f.cmd_held != 0U;
  st.cmd = f.cmd;
  st.last_winner = f.last_winner;
  st.no_majority_mask = 0U;
  st.voted_ckpt = f.voted_ckpt;
  (void)st.group.configure(st.cfg->tmr);
  for (std::uint32_t i = 0; i < kReplicas; ++i) {
    if ((f.active_mask & (1U << i)) != 0U) {
      st.group.admit(i);
    }
  }
}

/**
 * A voter restarted (reset, or its role moved) while it voted: takes its
 * place in the stream from DDR, the outputs the replicas kept for the jobs it
 * had not voted, and the matches it held; the records of the jobs it missed
 * are written at its first job (rebuild). False if it was not voting, the
 * place is damaged or of another group, or it was out too long.
 */
bool rejoin(TaskState& st, std::uint32_t job) noexcept {
  TmrArea& a = *st.tmr;
  const TmrVoter& f = a.voter;
  bsp::Work work{};
  const bool ok = tmr_voter_ok(f) && f.voting == 1U && f.epoch == a.control.epoch && a.held.serial == f.held_serial &&
                  tmr_held_ok(a.held, work) && job > f.record_job && job - f.record_job <= kMaxRejoinGap;
  bsp::consume(work);
  if (!ok) {
    return false;
  }
  take_place(st, f);
  st.mheld_count = a.held.count;
  for (std::uint32_t m = 0; m < a.held.count; ++m) {
    st.mheld_job[m] = a.held.job[m];
  }
  std::copy_n(a.held.words.begin(), std::size_t{a.held.count} * kMatchWords, st.mheld.begin());
  // The outputs the replicas sent the voter that stopped, for the jobs it had not voted yet.
  for (std::uint32_t i = 0; i < kReplicas; ++i) {
    for (std::uint32_t j = f.next_vote; j <= f.record_job && j - f.next_vote < kHeldOutputs; ++j) {
      const fdir::TmrRecord& kept = a.outputs[i][j % kHeldOutputs];
      if (kept.job == j && kept.words == kVotedWords) {
        keep_kept_output(st, i, kept);
      }
    }
  }
  // Read: the place, the held matches, the kept outputs.
  const std::uint64_t read = sizeof(TmrVoter) / sizeof(std::uint32_t) +
                             std::uint64_t{a.held.count} * (kMatchWords + 1U) +
                             std::uint64_t{kReplicas} * kHeldOutputs * (kVotedWords + 2U);
  bsp::consume(bsp::Work{0U, 0U, 0U, 0U, read});
  st.ring = imu_ring();
  st.catching_up = true;
  st.rejoin = true;
  st.rebuild_from = f.record_job + 1U;
  // The replicas run two records a release: they gain one a release on the records of the outage.
  st.lenient_until = job + (job - f.record_job) + kVoteLag + 4U;
  trn::report(ev::kTmrVoterResumed, job, a.control.epoch, f.next_deliver, job - f.record_job - 1U);
  return true;
}

/** After a rejoin, at the first job: the records of the jobs missed, from the I/O tile's DDR record and the held matches. */
void rebuild(TaskState& st) noexcept {
  if (!st.rejoin) {
    return;
  }
  st.rejoin = false;
  const std::uint32_t now_job = st.job;
  for (std::uint32_t j = st.rebuild_from; j < now_job && now_job - j <= kMaxRejoinGap; ++j) {
    st.job = j;
    record_begin(st.record, j);
    std::uint32_t budget = kMaxReplayPerJob;
    if (st.have_imu && j >= kImuLagJobs) {
      (void)replay(st, j - kImuLagJobs + 1U, budget);
    }
    take_command(st);
    bsp::Work work{};
    take_held_matches(st, work);
    record_seal(st.record, work);
    st.tmr->ring[j % kJobRingLen] = st.record;
    work.mem_words += kRecordWords;
    bsp::consume(work);
  }
  st.job = now_job;
}

/** After each job in TMR: the voter's place in the stream to DDR (and the held matches, if they changed). */
void persist_voter(TaskState& st) noexcept {
  TmrArea& a = *st.tmr;
  bsp::Work work{};
  if (!st.held_written || st.held_saved != st.mheld_changes) {
    TmrHeldMatches& h = a.held;
    h.crc = ~h.crc;  // torn while written: refused
    h.serial = h.serial + 1U == 0U ? 1U : h.serial + 1U;
    st.mheld_count = std::min(st.mheld_count, kHeldMatches);
    h.count = st.mheld_count;
    for (std::uint32_t m = 0; m < st.mheld_count; ++m) {
      h.job[m] = st.mheld_job[m];
    }
    std::copy_n(st.mheld.begin(), std::size_t{st.mheld_count} * kMatchWords, h.words.begin());
    work.mem_words += std::uint64_t{st.mheld_count} * (kMatchWords + 1U);
    tmr_held_seal(h, work);
    st.held_saved = st.mheld_changes;
    st.held_written = true;
  }
  TmrVoter& f = a.voter;
  f.crc = ~f.crc;
  f.serial = f.serial + 1U == 0U ? 1U : f.serial + 1U;
  f.epoch = a.control.epoch;
  f.voting = st.mode == Mode::kTmr ? 1U : 0U;
  f.record_job = st.job;
  f.next_vote = st.next_vote;
  f.next_deliver = st.next_deliver;
  f.delivered_any = st.delivered_any ? 1U : 0U;
  f.outputs_delivered = st.stats->outputs_delivered;
  f.outputs_skipped = st.stats->outputs_skipped;
  f.output_crc = st.stats->output_crc;
  f.last_delivered_job = st.stats->last_delivered_job;
  f.mark_job = st.stats->mark_job;
  f.mark_crc = st.stats->mark_crc;
  f.have_imu = st.have_imu ? 1U : 0U;
  f.last_imu = st.last_imu;
  f.cmd_held = st.cmd_held ? 1U : 0U;
  f.cmd = st.cmd;
  f.active_mask = st.group.active_mask();
  f.last_winner = st.last_winner;
  f.held_serial = a.held.serial;
  f.voted_ckpt = st.voted_ckpt;
  tmr_voter_seal(f);
  work.mem_words += sizeof(TmrVoter) / sizeof(std::uint32_t);
  work.int_ops += 4ULL * sizeof(TmrVoter) / sizeof(std::uint32_t);
  bsp::consume(work);
}

/**
 * The outputs of job @p job that did not come over the network (sent to a
 * voter that stopped, or before the role's move was known) but that their
 * replica kept in DDR.
 */
void fill_from_ddr(TaskState& st, std::uint32_t job) noexcept {
  std::uint64_t words = 0U;
  for (std::uint32_t i = 0; i < kReplicas; ++i) {
    const fdir::TmrRecord& kept = st.tmr->outputs[i][job % kHeldOutputs];
    if ((st.group.active_mask() & (1U << i)) != 0U && output_of(st, i, job) == nullptr && kept.job == job &&
        kept.words == kVotedWords) {
      keep_kept_output(st, i, kept);
      words += kVotedWords + 3U;
    }
  }
  bsp::consume(bsp::Work{0U, 0U, 0U, 0U, 2U + words});
}

/**
 * The votes of this job: normally job - kVoteLag alone; a voter that is
 * behind (after a restart) votes up to kVotesPerJob older jobs first, and
 * until lenient_until waits for every voting replica's output rather than
 * count one as missing (the replicas are running the records of its outage).
 */
void vote_due(TaskState& st, std::uint32_t v) noexcept {
  if (st.next_vote + kOutRing / 2U < v) {
    st.next_vote = v - kOutRing / 2U;  // older outputs are gone: those jobs are never delivered
  }
  for (std::uint32_t n = 0; n < kVotesPerJob && st.next_vote <= v && st.mode != Mode::kSimplex; ++n) {
    const std::uint32_t d = st.next_vote;
    fill_from_ddr(st, d);
    if (st.job < st.lenient_until && !all_present(st, d)) {
      return;
    }
    vote(st, d);
    st.next_vote = d + 1U;
  }
}

/** One job of the voter in TMR or starting TMR: the record to the ring, then the vote kVoteLag jobs back. */
/**
 * The voter's thresholds (its TMR group's, in this tile's RAM) against the image's, every TMR
 * job: changed, they are set again (the replicas voted on and their counts kept) and reported
 * (tile_settings_bad). Its EKF's settings are checked when it runs simplex again.
 */
void check_voter_settings(TaskState& st) noexcept {
  const fdir::TmrGroupConfig& held = st.group.config();
  const fdir::TmrGroupConfig& image = st.cfg->tmr;
  bsp::consume(bsp::Work{4U, 0U, 0U, 0U, 4U});
  if (held.disagree_to_exclude == image.disagree_to_exclude && held.miss_to_exclude == image.miss_to_exclude) {
    return;
  }
  (void)st.group.set_thresholds(image);  // the image's were accepted at set-up
  ++st.stats->settings_rebuilt;
  trn::report(ev::kTileSettingsBad, st.job, ev::kSettingsOfVoter, ev::kSettingsAtStart, 0U);
}

void tmr_job(TaskState& st) noexcept {
  check_voter_settings(st);
  drain_replicas(st);
  const std::uint32_t v = st.job >= kVoteLag ? st.job - kVoteLag : 0U;
  if (st.mode == Mode::kTmr || st.mode == Mode::kStopping) {
    vote_due(st, v);
  }
  // The control block is written before the record it names, so a replica that sees the record sees it.
  bsp::Work work{};
  record_seal(st.record, work);
  st.tmr->ring[st.job % kJobRingLen] = st.record;
  work.mem_words += kRecordWords;
  bsp::consume(work);
  if (st.mode == Mode::kStarting) {
    run_own(st, st.record);
    compare_starting(st, v);
  } else if (st.mode == Mode::kStopping) {
    finish_stop(st, v);
  }
  if (st.mode != Mode::kSimplex) {
    persist_voter(st);
  }
}

/** The voter's status for the filter supervisor: its mode, the voters and the faults counted. */
void send_status(const TaskState& st) noexcept {
  if (st.cfg->filter_supervisor_tile == bsp::kNoTile || st.job % kFilterStatusJobs != 0U) {
    return;
  }
  const std::uint32_t mode = st.mode == Mode::kSimplex    ? kFilterModeSimplex
                             : st.mode == Mode::kStarting ? kFilterModeStarting
                             : st.mode == Mode::kTmr      ? kFilterModeTmr
                                                            : kFilterModeStopping;
  std::array<std::uint32_t, kFilterStatusWords> w{};
  (void)fdir::msg::encode(kFilterStatusMsg,
                          FilterStatus{st.job, mode, st.group.active_mask(), st.stats->tmr_no_majority,
                                       st.stats->outputs_skipped},
                          w);
  // A lost status is a missing verdict: the supervisor judges the next one.
  (void)udn::endpoint_send(udn::endpoint_role_tile(kSlotFilterSupervisor, st.cfg->filter_supervisor_tile), kChanControl, w, 0U);
}

/**
 * The EKF's state at the end of the job, sealed for the next one (check_state_seal()): between
 * the two nothing of the filter runs, so a change is an upset of the tile's RAM.
 */
void seal_state(TaskState& st) noexcept {
  bsp::Work work{};
  st.state_seal = st.core.ekf->state_crc(work);
  st.seal_for = st.job + 1U;
  bsp::consume(work);
}

/**
 * The simplex filter's state against the seal the last job took: changed, it is reported
 * (filter_state_changed) and the filter goes back to its last checkpoint, as after a refused state
 * (go_back(): the same checkpoint twice, and the tile asks to be restarted). In TMR the voter's own
 * filter is not used; a replica's state is the vote's.
 */
void check_state_seal(TaskState& st) noexcept {
  if (st.mode != Mode::kSimplex || st.seal_for != st.job || st.job == 0U) {
    return;
  }
  bsp::Work work{};
  const bool intact = st.core.ekf->state_crc(work) == st.state_seal;
  bsp::consume(work);
  st.seal_for = 0U;
  if (intact) {
    return;
  }
  ++st.stats->states_changed;
  trn::report(ev::kFilterStateChanged, st.job - 1U, 0U);
  go_back(st, kAssertFilterStateRefused);
}

/**
 * The task's counts and mode as an upset may have left them: a value no valid state holds is
 * bounded (a count to its array, a mode to simplex) and the tile asks to be restarted
 * (kAssertFilterTaskBad). Each use bounds them too: an upset can land after this check.
 */
void check_task_state(TaskState& st) noexcept {
  const bool counts_ok = st.held_count <= kImuHeld && st.mheld_count <= kHeldMatches;
  const bool mode_ok = st.mode == Mode::kSimplex ||
                       (st.tmr != nullptr && static_cast<std::uint8_t>(st.mode) <= static_cast<std::uint8_t>(Mode::kStopping));
  if (counts_ok && mode_ok) {
    return;
  }
  st.held_count = std::min(st.held_count, kImuHeld);
  st.mheld_count = std::min(st.mheld_count, kHeldMatches);
  if (!mode_ok) {
    st.mode = Mode::kSimplex;
  }
  ask_restart(st, kAssertFilterTaskBad);
}

}  // namespace

void filter_task_main(void* arg) noexcept {
  const auto* cfg = static_cast<const FilterTaskConfig*>(arg);
  TaskState* const state = cfg != nullptr ? carve_task_state(*cfg) : nullptr;
  if (state == nullptr || !set_up(*state, *cfg)) {
    return;
  }
  TaskState& st = *state;
  st.job = static_cast<std::uint32_t>(bsp::now() / (std::uint64_t{kFilterPeriodTicks} * bsp::tick_cycles()));
  st.stats->started_job = st.job;
  for (;;) {  // one pass per 10 ms release
    const bsp::Cycles start = bsp::now();
    if (st.tmr != nullptr) {
      st.tmr->voter_phase = static_cast<std::uint32_t>((start / bsp::tick_cycles()) % kFilterPeriodTicks) + 1U;
    }
    st.command = 0U;
    check_task_state(st);
    check_state_seal(st);
    rebuild(st);
    record_begin(st.record, st.job);
    catch_up(st);
    consume_imu(st);
    consume_parts(st);
    if (st.mode == Mode::kSimplex || st.tmr == nullptr) {
      if (run_own(st, st.record)) {
        checkpoint(st);  // only a state that passed its check is kept
      }
      if (st.command == kCmdFilterTmr || (st.resume_tmr && !st.catching_up)) {
        st.resume_tmr = false;
        start_tmr(st);
      }
    } else {
      if ((st.command == kCmdFilterSimplex && st.mode == Mode::kTmr) ||
          (st.mode == Mode::kStopping && st.stop_again)) {
        begin_stop(st);
      }
      tmr_job(st);
      if (st.command == kCmdFilterSimplex && st.mode == Mode::kStarting) {
        stop_tmr(st, kTmrStopCommand);
      }
    }
    send_status(st);
    seal_state(st);
    ++st.stats->jobs;
    ++st.job;
    st.stats->last_job_cycles = bsp::now() - start;
    if (st.stats->last_job_cycles > st.stats->max_job_cycles) {
      st.stats->max_job_cycles = st.stats->last_job_cycles;
    }
    k::checkin();
    (void)k::wait_period();
  }
}

const bsp::ControlLayout& filter_task_layout() noexcept { return kTaskStateLayout; }

}  // namespace trn::tasks
