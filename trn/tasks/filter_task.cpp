/**
 * @file filter_task.cpp
 * @brief The 100 Hz navigation filter job: IMU, match batches, bounded updates, solution out.
 */
#include "trn/tasks/filter_task.hpp"

#include "bsp_tile64/memory.hpp"
#include "fdir/event_log.hpp"
#include "kernel/kernel.hpp"
#include "trn/tasks/filter_checkpoint.hpp"
#include "trn/tasks/imu_ring.hpp"
#include "trn/tasks/messages.hpp"
#include "udn/endpoint.hpp"

#include <array>
#include <new>
#include <span>

namespace trn::tasks {
namespace {

/** Matches waiting to be applied, oldest first (a ring). */
struct MatchQueue {
  std::uint32_t head;
  std::uint32_t count;
  std::array<Match, kMatchQueueLen> m;
};

struct Slot {
  filter::Ekf* ekf;
  MatchQueue* queue;
  const FilterTaskConfig* cfg;
  FilterTaskStats stats;
  filter::NavOutput latest;
  bool published;
  CheckpointArea* ckpt;      ///< nullptr: no checkpoints (disabled, or no DDR)
  const ImuRing* ring;       ///< the I/O tile's record; nullptr until it exists
  bool have_imu;             ///< last_imu is valid
  std::uint32_t last_imu;    ///< seq of the last sample integrated
  bool catching_up;          ///< samples to replay from the record before the live ones
  std::uint32_t ckpt_seq;    ///< number of the last checkpoint written or resumed from
  std::uint32_t ckpt_slot;   ///< slot it is in (the next write goes to the other)
  std::uint32_t since_ckpt;  ///< jobs since it
};

std::array<Slot, bsp::kMaxTiles> g_slots{};

/** Propagates with one sample and remembers it as the last integrated. */
void integrate(Slot& slot, const bsp::ImuSample& s) noexcept {
  filter::UpdateReport rep{};
  const filter::FilterStatus st = slot.ekf->step(filter::StepInput{&s, nullptr, 0}, rep);
  if (st == filter::FilterStatus::kOk) {
    ++slot.stats.imu_used;
  } else if (st == filter::FilterStatus::kImuInvalid) {
    ++slot.stats.imu_rejected;
  } else {
    ++slot.stats.filter_errors;
  }
  slot.have_imu = true;
  slot.last_imu = s.seq;
}

/**
 * Integrates from the DDR record the samples after the last one up to
 * (not including) @p until, at most @p budget of them. @return false if the
 * budget ran out first. Samples the record lost are skipped and reported.
 */
bool replay(Slot& slot, std::uint32_t until, std::uint32_t& budget) noexcept {
  if (slot.ring == nullptr) {
    slot.ring = imu_ring();
  }
  for (std::uint32_t n = 0; n < kMaxReplayPerJob + 1U && slot.last_imu + 1U < until; ++n) {
    if (budget == 0U) {
      return false;
    }
    bsp::ImuSample s{};
    const RingRead rr = slot.ring == nullptr ? RingRead::kNotYet : imu_ring_get(*slot.ring, slot.last_imu + 1U, s);
    if (rr == RingRead::kNotYet) {
      return true;  // nothing newer recorded yet
    }
    if (rr == RingRead::kGone) {
      const std::uint32_t oldest = imu_ring_oldest(*slot.ring);
      const std::uint32_t first = oldest > slot.last_imu + 1U ? oldest : until;
      const std::uint32_t missing = first - (slot.last_imu + 1U);
      slot.stats.imu_lost += missing;
      fdir::report(fdir::EventId::kImuGap, slot.last_imu + 1U, 0U, missing);
      slot.last_imu = first - 1U;
      continue;
    }
    integrate(slot, s);
    ++slot.stats.imu_replayed;
    --budget;
  }
  return slot.last_imu + 1U >= until;
}

/** After a resume: replays the record until it has nothing newer (bounded per job). */
void catch_up(Slot& slot) noexcept {
  if (!slot.catching_up) {
    return;
  }
  std::uint32_t budget = kMaxReplayPerJob;
  const std::uint32_t newest = slot.ring != nullptr ? slot.ring->written : 0U;
  if (replay(slot, newest > slot.last_imu + 1U ? newest : slot.last_imu + 1U, budget) && budget > 0U) {
    slot.catching_up = false;
  }
}

/** Integrates up to kMaxImuPerJob samples waiting on kChanImu (filling gaps from the record). */
void consume_imu(Slot& slot) noexcept {
  udn::FtMessage msg{};
  std::uint32_t budget = kMaxReplayPerJob;
  for (std::uint32_t n = 0; n < kMaxImuPerJob; ++n) {
    if (udn::endpoint_receive(kChanImu, msg) != udn::FtError::kOk) {
      return;
    }
    if (msg.data_words != kImuWords) {
      ++slot.stats.imu_rejected;
      continue;
    }
    const bsp::ImuSample s = unpack_imu(std::span<const std::uint32_t, kImuWords>{msg.data.data(), kImuWords});
    if (slot.have_imu && s.seq <= slot.last_imu) {
      ++slot.stats.imu_duplicates;  // replayed before it arrived
      continue;
    }
    if (slot.have_imu && s.seq > slot.last_imu + 1U && slot.cfg->checkpoint_every != 0U &&
        !replay(slot, s.seq, budget)) {
      slot.catching_up = true;  // the rest of the gap (and this sample) come from the record next jobs
      continue;
    }
    if (slot.have_imu && s.seq <= slot.last_imu) {
      ++slot.stats.imu_duplicates;
      continue;
    }
    integrate(slot, s);
  }
}

/** Every checkpoint_every jobs (not while catching up): the whole state to DDR. */
void checkpoint(Slot& slot) noexcept {
  if (slot.ckpt == nullptr || slot.catching_up || !slot.have_imu || ++slot.since_ckpt < slot.cfg->checkpoint_every) {
    return;
  }
  slot.since_ckpt = 0U;
  bsp::Work work{};
  slot.ckpt_slot = 1U - slot.ckpt_slot;
  checkpoint_write(*slot.ckpt, slot.ekf->state(), slot.last_imu, ++slot.ckpt_seq, slot.ckpt_slot, work);
  bsp::consume(work);
  ++slot.stats.checkpoints;
}

/** Drops what is left of the oldest frame in the queue. */
void drop_oldest_frame(MatchQueue& q, FilterTaskStats& st) noexcept {
  const std::uint32_t frame = q.m[q.head].frame;
  for (std::uint32_t i = 0; i < kMatchQueueLen && q.count > 0U && q.m[q.head].frame == frame; ++i) {
    q.head = (q.head + 1U) % kMatchQueueLen;
    --q.count;
    ++st.matches_dropped;
  }
}

/**
 * Queues @p m. A full queue first loses its oldest frame's remainder: fresher
 * images are worth more, and the oldest is the nearest to leaving the history.
 * A queue full of @p m's own frame (more than a frame can hold) drops @p m.
 */
void push(MatchQueue& q, const Match& m, FilterTaskStats& st) noexcept {
  // Each pass empties at least one slot, so one pass suffices; the bound is for the reader.
  for (std::uint32_t i = 0; i < kMatchQueueLen && q.count == kMatchQueueLen; ++i) {
    if (q.m[q.head].frame == m.frame) {
      ++st.matches_dropped;
      return;
    }
    drop_oldest_frame(q, st);
  }
  q.m[(q.head + q.count) % kMatchQueueLen] = m;
  ++q.count;
  st.queue_high_water = q.count > st.queue_high_water ? q.count : st.queue_high_water;
}

/** True if @p msg is a well-formed match-batch part whose matches all belong to its frame. */
bool part_ok(const udn::FtMessage& msg) noexcept {
  if (msg.data_words < kMatchHeaderWords || msg.data[0] != kMsgMatches) {
    return false;
  }
  const std::uint32_t n = msg.data[3];
  if (n == 0U || n > kMatchesPerPart || msg.data_words != kMatchHeaderWords + n * kMatchWords) {
    return false;
  }
  for (std::uint32_t i = 0; i < n; ++i) {
    // Word 21 of a packed match is its frame number (messages.hpp).
    if (msg.data[kMatchHeaderWords + i * kMatchWords + 21U] != msg.data[1]) {
      return false;
    }
  }
  return true;
}

/** Takes the match-batch parts waiting on kChanMatches into the queue. */
void consume_parts(Slot& slot) noexcept {
  udn::FtMessage msg{};
  bsp::Work work{};
  for (std::uint32_t p = 0; p < kMaxPartsPerJob; ++p) {
    if (udn::endpoint_receive(kChanMatches, msg) != udn::FtError::kOk) {
      break;  // empty, or the node is not open yet
    }
    ++slot.stats.parts_received;
    work.int_ops += 8ULL + 2ULL * msg.data_words;
    if (!part_ok(msg)) {
      ++slot.stats.parts_bad;
      continue;
    }
    const std::uint32_t n = msg.data[3];
    for (std::uint32_t i = 0; i < n; ++i) {
      const std::size_t at = kMatchHeaderWords + static_cast<std::size_t>(i) * kMatchWords;
      const std::span<const std::uint32_t, kMatchWords> w(msg.data.data() + at, kMatchWords);
      push(*slot.queue, unpack_match(w), slot.stats);
      ++slot.stats.matches_received;
    }
    work.mem_words += 2ULL * msg.data_words;  // read from the node, written into the queue
  }
  bsp::consume(work);
}

/** Applies at most matches_per_job queued matches (two calls when the ring wraps). */
void apply_matches(Slot& slot) noexcept {
  MatchQueue& q = *slot.queue;
  std::uint32_t budget = slot.cfg->matches_per_job;
  for (int pass = 0; pass < 2 && budget > 0U && q.count > 0U; ++pass) {
    const std::uint32_t contiguous = kMatchQueueLen - q.head;
    std::uint32_t n = budget < q.count ? budget : q.count;
    n = n < contiguous ? n : contiguous;
    filter::UpdateReport rep{};
    if (slot.ekf->update(&q.m[q.head], n, rep) != filter::FilterStatus::kOk) {
      ++slot.stats.filter_errors;
    }
    slot.stats.matches_applied += rep.accepted;
    slot.stats.coarse_applied += rep.coarse_accepted;
    slot.stats.rejected_gate += rep.rejected_gate;
    slot.stats.rejected_stale += rep.rejected_stale;
    slot.stats.rejected_invalid += rep.rejected_invalid;
    q.head = (q.head + n) % kMatchQueueLen;
    q.count -= n;
    budget -= n;
  }
}

void publish(Slot& slot) noexcept {
  filter::NavOutput out = filter::make_nav_output(slot.ekf->state(), slot.ekf->config());
  // The published value is what a fault may corrupt on its way out.
  (void)bsp::publish_filter(kNavChannel, &out, sizeof out);
  slot.latest = out;
  slot.published = true;
}

/** Sends the published solution to nav_sink; never waits (a full window counts as a failure). */
void send_nav(Slot& slot) noexcept {
  if (slot.cfg->nav_sink == bsp::kNoTile) {
    return;
  }
  std::array<std::uint32_t, kNavWords> w{};
  pack_nav(slot.latest, w);
  bsp::consume(bsp::Work{2ULL * kNavWords, 0U, 0U, 0U, kNavWords});
  const bsp::TileId sink = udn::endpoint_role_tile(kSlotCoordinator, slot.cfg->nav_sink);
  if (udn::endpoint_send(sink, kChanNav, w, 0U) == udn::FtError::kOk) {
    ++slot.stats.nav_sent;
  } else {
    ++slot.stats.nav_send_failed;
  }
}

bool set_up(Slot& slot, const FilterTaskConfig& cfg) noexcept {
  if (cfg.matches_per_job == 0U || cfg.matches_per_job > kMaxMatchesPerFrame) {
    return false;
  }
  slot.cfg = &cfg;
  bsp::MemError err = bsp::MemError::kOk;
  const bsp::Region ram{bsp::current_tile()};
  auto* ekf = bsp::carve_array<filter::Ekf>(ram, 1, "ekf", &err);
  if (err != bsp::MemError::kOk) {
    return false;
  }
  ::new (ekf) filter::Ekf{};
  slot.ekf = ekf;
  auto* queue = bsp::carve_array<MatchQueue>(ram, 1, "match queue", &err);
  if (err != bsp::MemError::kOk) {
    return false;
  }
  ::new (queue) MatchQueue{};
  slot.queue = queue;
  if (slot.ekf->configure(cfg.filter, cfg.camera) != filter::FilterStatus::kOk) {
    return false;
  }
  slot.ckpt = cfg.checkpoint_every != 0U ? checkpoint_area() : nullptr;
  slot.ring = cfg.checkpoint_every != 0U ? imu_ring() : nullptr;
  if (slot.ckpt != nullptr) {
    // A checkpoint left by an earlier start (a reset, or the tile this role moved from).
    filter::FilterState st{};
    bsp::Work work{};
    const CheckpointRead r = checkpoint_read(*slot.ckpt, st, work);
    bsp::consume(work);
    if (r.bad != 0U) {
      fdir::report(fdir::EventId::kCheckpointBad, r.bad_slot, 0U, r.bad);
    }
    if (r.found && slot.ekf->restore(st) == filter::FilterStatus::kOk) {
      slot.have_imu = true;
      slot.last_imu = r.imu_seq;
      slot.catching_up = true;
      slot.ckpt_seq = r.seq;
      slot.ckpt_slot = r.slot;
      slot.stats.resumed_from = r.seq;
      const std::uint32_t recorded = slot.ring != nullptr ? slot.ring->written : 0U;
      fdir::report(fdir::EventId::kFilterResumed, r.seq, 0U, recorded > r.imu_seq + 1U ? recorded - r.imu_seq - 1U : 0U,
                   r.imu_seq);
      return true;
    }
  }
  return slot.ekf->init(cfg.initial) == filter::FilterStatus::kOk;
}

}  // namespace

void filter_task_main(void* arg) noexcept {
  const bsp::TileId tile = bsp::current_tile();
  Slot& slot = g_slots[tile];
  slot = Slot{};
  const auto* cfg = static_cast<const FilterTaskConfig*>(arg);
  if (cfg == nullptr || !set_up(slot, *cfg)) {
    return;
  }
  for (;;) {  // one pass per 10 ms release
    const bsp::Cycles start = bsp::now();
    catch_up(slot);
    consume_imu(slot);
    bsp::consume(slot.ekf->take_work());
    consume_parts(slot);
    apply_matches(slot);
    bsp::consume(slot.ekf->take_work());
    publish(slot);
    send_nav(slot);
    checkpoint(slot);
    ++slot.stats.jobs;
    slot.stats.last_job_cycles = bsp::now() - start;
    if (slot.stats.last_job_cycles > slot.stats.max_job_cycles) {
      slot.stats.max_job_cycles = slot.stats.last_job_cycles;
    }
    k::checkin();
    (void)k::wait_period();
  }
}

FilterTaskStats filter_task_stats(bsp::TileId tile) noexcept {
  return tile < bsp::kMaxTiles ? g_slots[tile].stats : FilterTaskStats{};
}

bool filter_task_output(bsp::TileId tile, filter::NavOutput* out) noexcept {
  if (tile >= bsp::kMaxTiles || out == nullptr || !g_slots[tile].published) {
    return false;
  }
  *out = g_slots[tile].latest;
  return true;
}

}  // namespace trn::tasks
