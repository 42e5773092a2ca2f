/**
 * @file filter_tmr.cpp
 * @brief The TMR group's DDR areas and the replica task (see filter_tmr.hpp).
 */
#include "trn/tasks/filter/filter_tmr.hpp"
#include "trn/events.hpp"

#include "bsp_tile64/api/memory.hpp"
#include "fdir/event_log.hpp"
#include "kernel/kernel.hpp"
#include "trn/filter/state_check.hpp"
#include "trn/tasks/filter/filter_checkpoint.hpp"
#include "trn/tasks/vision/vision_shared.hpp"
#include "udn/crc32c.hpp"
#include "udn/endpoint.hpp"

#include <type_traits>

namespace trn::tasks {
namespace {

struct Replica {
  FilterCore core;           ///< its counters too (core.stats, the record in tile RAM)
  std::uint32_t index;
  bool seeded;
  std::uint32_t epoch;       ///< of the seed loaded
  std::uint32_t gen;         ///< own generation when it loaded
  std::uint32_t seed_serial; ///< last seed loaded
  std::uint32_t next_job;    ///< the record to run next
  std::uint32_t since_hello;
  std::uint32_t ckpt_slot;
};

/** What an upset of a replica's state does (bsp::ControlLayout): the core as laid out, the rest the tile's own. */
constexpr std::array kReplicaFields{
    BSP_CONTROL_NESTED(Replica, core, kFilterCoreLayout), BSP_CONTROL_STATE(Replica, index),
    BSP_CONTROL_STATE(Replica, seeded),                   BSP_CONTROL_STATE(Replica, epoch),
    BSP_CONTROL_STATE(Replica, gen),                      BSP_CONTROL_STATE(Replica, seed_serial),
    BSP_CONTROL_STATE(Replica, next_job),                 BSP_CONTROL_STATE(Replica, since_hello),
    BSP_CONTROL_STATE(Replica, ckpt_slot),
};
constexpr bsp::ControlLayout kReplicaLayout{kReplicaFields, sizeof(Replica), alignof(Replica)};
static_assert(bsp::control_layout_ok(kReplicaLayout), "every member of Replica, the core's pointers as host state");
static_assert(std::is_trivially_copyable_v<Replica>, "carved and value-initialised as a record (bsp::carve_record)");

std::uint32_t seed_header_crc(const TmrSeed& s) noexcept {
  const std::array<std::uint32_t, 8> h{s.serial, s.job, s.for_mask, s.epoch, s.digest, s.gen[0], s.gen[1], s.gen[2]};
  return udn::crc32c_words(h);
}

/** Asks the voter for a seed; @p refused: at once, because its own checks refused its state. */
void send_hello(const Replica& r, const TmrControl& ctl, bool refused = false) noexcept {
  std::array<std::uint32_t, kReplicaHelloWords> w{};
  (void)fdir::msg::encode(kReplicaHelloMsg, ReplicaHello{r.index, ctl.epoch, refused ? 1U : 0U}, w);
  (void)udn::endpoint_send(udn::endpoint_role_tile(kSlotFilter, bsp::kNoTile), kChanNav, w, 0U);
}

/** Loads the newest seed meant for this replica, if there is one. */
void try_seed(Replica& r, const TmrArea& a) noexcept {
  const TmrSeed& s = a.seed;
  const std::uint32_t bit = 1U << r.index;
  if (s.serial == 0U || s.serial == r.seed_serial || (s.for_mask & bit) == 0U || s.epoch != a.control.epoch ||
      s.gen[r.index] != a.control.gen[r.index] || !tmr_seed_ok(s)) {
    return;
  }
  bsp::Work work{};
  const bool ok = core_load(r.core, s.image, work);
  bsp::consume(work);
  r.seed_serial = s.serial;
  if (!ok) {
    return;
  }
  r.seeded = true;
  r.epoch = s.epoch;
  r.gen = s.gen[r.index];
  r.next_job = s.job + 1U;
}

/**
 * Sends the voter this job's output, its state digest and the CRC of the output taken here, where it
 * was computed (the voter votes no output that fails it: two corrupted alike cannot outvote the third),
 * and keeps them in DDR for a voter that restarts (the CRC after the voted words).
 */
void send_output(Replica& r, TmrArea& a, std::uint32_t job, std::uint32_t digest) noexcept {
  const filter::NavOutput nav = core_output(r.core);
  std::array<std::uint32_t, kNavWords> words{};
  (void)fdir::msg::encode(kNavMsg, nav, words);
  const std::uint32_t out_crc = udn::crc32c_words(words);
  std::array<std::uint32_t, kReplicaOutWords> w{};
  pack_replica_out(ReplicaOut{r.index, job, digest, out_crc}, nav, w);
  // The solution as sent is what a fault may corrupt on its way out (every bit of it is delivered).
  (void)bsp::publish_filter(kNavChannel, w.data() + kReplicaOutHeaderWords, std::size_t{kNavWords} * sizeof(std::uint32_t));
  fdir::TmrRecord& kept = a.outputs[r.index][job % kHeldOutputs];
  kept.words = 0U;  // torn while written: not an output
  kept.job = job;
  for (std::uint32_t i = 0; i < kNavWords; ++i) {
    kept.w[i] = w[kReplicaOutHeaderWords + i];
  }
  kept.w[kNavWords] = digest;
  kept.w[kNavWords + 1U] = out_crc;
  kept.words = kNavWords + 1U;
  bsp::consume(bsp::Work{8ULL * kNavWords, 0U, 0U, 0U, 2ULL * kNavWords + 4U});
  if (udn::endpoint_send(udn::endpoint_role_tile(kSlotFilter, bsp::kNoTile), kChanNav, w, 0U) ==
      udn::FtError::kOk) {
    ++r.core.stats->nav_sent;
  } else {
    ++r.core.stats->nav_send_failed;
  }
}

/**
 * What the control block asks of this replica after it ran @p job: a seed, a checkpoint (with
 * @p digest, the state digest its output for the job carries to the vote).
 */
void after_job(Replica& r, TmrArea& a, std::uint32_t job, std::uint32_t digest) noexcept {
  const TmrControl& ctl = a.control;
  bsp::Work work{};
  if (ctl.seed_by == r.index && ctl.seed_job == job) {
    tmr_write_seed(a, r.core, job, ctl.seed_for, work);
  }
  if (ctl.ckpt_by == r.index && r.core.cfg->checkpoint_every != 0U && job % r.core.cfg->checkpoint_every == 0U) {
    CheckpointArea* ck = checkpoint_area();
    if (ck != nullptr) {
      r.ckpt_slot = 1U - r.ckpt_slot;
      // Numbered by job, so a later checkpoint of any writer is the newer one.
      checkpoint_write(*ck, r.core.ekf->state(), r.core.last_imu, job / r.core.cfg->checkpoint_every + 1U,
                       r.ckpt_slot, work, digest);
      ++r.core.stats->checkpoints;
    }
  }
  bsp::consume(work);
}

/**
 * The checks of a replica's job, as the simplex filter's (run_checked): its settings in RAM, then its
 * state against the one before the job (@p before). False when one fails: the replica reports it and
 * drops its state (its output goes missing; the voter excludes and re-seeds it, as after a restart).
 *
 * Settings changed (an upset): this job's state was computed with them; they are built again from
 * the image. Before, they stayed wrong: re-seeded, the replica never agreed again, and a second such
 * replica left no majority. A state that fails the plausibility check is never sent: two replicas
 * corrupted alike cannot outvote the third with a state the simplex filter would have refused.
 */
bool job_ok(Replica& r, const filter::StateBefore& before) noexcept {
  bsp::Work work{};
  const std::uint32_t changed = core_settings_changed(r.core, work);
  if (changed != 0U) {
    const bool rebuilt = core_reload_settings(r.core, work);
    bsp::consume(work);
    ++r.core.stats->settings_rebuilt;
    trn::report(ev::kFilterSettingsBad, r.next_job, changed, rebuilt ? 1U : 0U);
    return false;
  }
  const filter::StateCheckResult c = filter::check_state(before, r.core.ekf->state(), r.core.cfg->envelope, work);
  bsp::consume(work);
  if (c.what == filter::StateCheck::kOk) {
    return true;
  }
  ++r.core.stats->states_rejected;
  trn::report(ev::kFilterStateBad, r.next_job, static_cast<std::uint32_t>(c.what),
              filter::state_check_field(c.value, c.what), filter::state_check_field(c.limit, c.what));
  return false;
}

/** Runs the records that are there, at most kReplicaJobsPerRelease; unseeds itself if one is gone or bad. */
void run_records(Replica& r, TmrArea& a) noexcept {
  for (std::uint32_t n = 0; n < kReplicaJobsPerRelease; ++n) {
    const JobRecord& rec = a.ring[r.next_job % kJobRingLen];
    const std::uint32_t job = record_job(rec);
    if (job < r.next_job) {
      return;  // not written yet
    }
    bsp::Work work{};
    const bool ok = record_ok(rec, r.next_job, work);
    bsp::consume(work);
    if (!ok) {
      r.seeded = false;  // overwritten before it ran (too far behind), or damaged: needs a seed
      return;
    }
    bsp::Work bw{};
    const filter::StateBefore before = filter::state_before(r.core.ekf->state(), bw);
    bsp::consume(bw);
    core_run(r.core, rec);
    if (!job_ok(r, before)) {
      r.seeded = false;
      // Said at once: the voter counts its missing outputs as refused, not as a silent replica.
      send_hello(r, a.control, true);
      r.since_hello = 0U;
      return;
    }
    bsp::Work dw{};
    const std::uint32_t digest = core_digest(r.core, dw);
    bsp::consume(dw);
    send_output(r, a, r.next_job, digest);
    after_job(r, a, r.next_job, digest);
    ++r.core.stats->jobs;
    ++r.next_job;
  }
}

}  // namespace

TmrArea* tmr_area() noexcept {
  void* p = ddr_carve_named("filter_tmr", sizeof(TmrArea), alignof(TmrArea));
  return static_cast<TmrArea*>(p);
}

bool tmr_seed_ok(const TmrSeed& s) noexcept { return s.crc == seed_header_crc(s); }

namespace {
std::uint32_t voter_crc(const TmrVoter& f) noexcept {
  std::array<std::uint32_t, 24U + kCommandWords> w{f.serial,           f.epoch,         f.voting,      f.record_job,
                                                   f.next_vote,        f.next_deliver,  f.delivered_any,
                                                   f.outputs_delivered, f.outputs_skipped, f.output_crc,
                                                   f.last_delivered_job, f.mark_job,    f.mark_crc,    f.have_imu,
                                                   f.last_imu,         f.cmd_held,      f.active_mask, f.last_winner,
                                                   f.held_serial,      0U,
                                                   f.voted_ckpt[0].seq, f.voted_ckpt[0].digest,
                                                   f.voted_ckpt[1].seq, f.voted_ckpt[1].digest};
  for (std::uint32_t i = 0; i < kCommandWords; ++i) {
    w[24U + i] = f.cmd[i];
  }
  return udn::crc32c_words(w);
}

std::uint32_t held_crc(const TmrHeldMatches& h, bsp::Work& work) noexcept {
  const std::array<std::uint32_t, 2> head{h.serial, h.count};
  const std::uint32_t n = h.count <= kHeldMatches ? h.count : kHeldMatches;
  std::uint32_t c = udn::crc32c_words(head);
  c = udn::crc32c_words_continue(c, std::span<const std::uint32_t>(h.job.data(), n));
  c = udn::crc32c_words_continue(c, std::span<const std::uint32_t>(h.words.data(), std::size_t{n} * kMatchWords));
  work.int_ops += 4ULL * (2U + n * (kMatchWords + 1U));
  work.mem_words += 2U + n * (kMatchWords + 1U);
  return c;
}
}  // namespace

void tmr_voter_seal(TmrVoter& f) noexcept { f.crc = voter_crc(f); }

bool tmr_voter_ok(const TmrVoter& f) noexcept { return f.serial != 0U && f.crc == voter_crc(f); }

void tmr_held_seal(TmrHeldMatches& h, bsp::Work& work) noexcept { h.crc = held_crc(h, work); }

bool tmr_held_ok(const TmrHeldMatches& h, bsp::Work& work) noexcept {
  return h.count <= kHeldMatches && h.crc == held_crc(h, work);
}

void tmr_write_seed(TmrArea& a, FilterCore& c, std::uint32_t job, std::uint32_t for_mask, bsp::Work& work) noexcept {
  TmrSeed& s = a.seed;
  s.crc = 0U;  // torn while written: refused
  core_save(c, s.image, work);
  s.digest = core_digest(c, work);
  s.job = job;
  s.for_mask = for_mask;
  s.epoch = a.control.epoch;
  s.gen = a.control.gen;
  ++s.serial;
  s.crc = seed_header_crc(s);
}

std::uint32_t replica_index(const FilterTaskConfig& cfg, bsp::TileId tile) noexcept {
  for (std::uint32_t i = 0; i < kReplicas; ++i) {
    if (cfg.replica_tiles[i] != bsp::kNoTile && udn::endpoint_role_tile(kSlotReplica0 + i, cfg.replica_tiles[i]) == tile) {
      return i;
    }
  }
  return kNoReplica;
}

void filter_replica_main(void* arg) noexcept {
  const bsp::TileId tile = bsp::current_tile();
  const auto* cfg = static_cast<const FilterTaskConfig*>(arg);
  TmrArea* const a = tmr_area();
  FilterCore core{};
  if (cfg == nullptr || a == nullptr || !core_set_up(core, *cfg, bsp::Region{tile})) {
    return;
  }
  // The state after the core's carves: they keep the places they had before it lived in tile RAM.
  bsp::MemError err = bsp::MemError::kOk;
  Replica* const state = bsp::carve_record(bsp::Region{tile}, bsp::RamRecord<Replica>{kReplicaCarve, &kReplicaLayout}, &err);
  if (state == nullptr) {
    return;
  }
  state->core = core;
  Replica& r = *state;
  // A replica started in flight (woken by the power policy, reset) is released with the voter's
  // jobs, as one booted with it: released a few ticks off, it found two records in some releases
  // and overran its deadline.
  if (a->voter_phase != 0U) {
    (void)k::align_period(a->voter_phase - 1U);
  }
  for (;;) {  // one pass per release
    k::checkin();
    r.index = replica_index(*cfg, tile);
    const TmrControl& ctl = a->control;
    if (r.index == kNoReplica || ctl.mode == 0U) {
      r.seeded = false;  // the group does not run: idle
    } else {
      if (r.seeded && (r.epoch != ctl.epoch || r.gen != ctl.gen[r.index])) {
        r.seeded = false;  // excluded by the voter, or a new group: drop the state
      }
      if (!r.seeded) {
        try_seed(r, *a);
      }
      if (r.seeded) {
        run_records(r, *a);
      }
      if (!r.seeded && ++r.since_hello >= kHelloEvery) {
        r.since_hello = 0U;
        send_hello(r, ctl);
      }
    }
    (void)k::wait_period();
  }
}

const bsp::ControlLayout& replica_state_layout() noexcept { return kReplicaLayout; }

}  // namespace trn::tasks
