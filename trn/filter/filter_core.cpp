/**
 * @file filter_core.cpp
 * @brief Job records and the filter step that runs them (see filter_core.hpp).
 */
#include "trn/filter/filter_core.hpp"

#include "bsp_tile64/api/memory.hpp"
#include "trn/tasks/sdc_points.hpp"
#include "udn/crc32c.hpp"

#include <cstddef>
#include <new>
#include <span>

namespace trn::tasks {
namespace {

constexpr std::uint32_t kImuAt = kRecordHeaderWords;
constexpr std::uint32_t kMatchAt = kRecordHeaderWords + kRecordImuMax * kImuWords;

std::span<const std::uint32_t> record_body(const JobRecord& r) noexcept {
  return {r.w.data() + kRecordHeaderWords, kRecordWords - kRecordHeaderWords};
}

/** Propagates with one sample and remembers it as the last integrated. */
void integrate(FilterCore& c, const bsp::ImuSample& s) noexcept {
  filter::UpdateReport rep{};
  const filter::FilterStatus st = c.ekf->step(filter::StepInput{&s, nullptr, 0}, rep);
  if (st == filter::FilterStatus::kOk) {
    ++c.stats->imu_used;
  } else if (st == filter::FilterStatus::kImuInvalid) {
    ++c.stats->imu_rejected;
  } else {
    ++c.stats->filter_errors;
  }
  c.have_imu = true;
  c.last_imu = s.seq;
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

/**
 * How many of the @p available queued matches from @p head fit in @p budget
 * updates: a coarse match costs filter::kCoarseIterations (its iterated
 * update), and so does every match when @p loose (the filter's position is
 * loose, and it iterates them all); any other one. At least one when any is
 * available, so a budget smaller than a coarse match's cost still moves the
 * queue. Lowers @p budget.
 */
std::uint32_t matches_that_fit(const MatchQueue& q, std::uint32_t head, std::uint32_t available, bool loose,
                               std::uint32_t& budget) noexcept {
  std::uint32_t n = 0;
  while (n < available && budget > 0U) {
    const bool coarse = q.m[(head + n) % kMatchQueueLen].landmark == kCoarseLandmark;
    const std::uint32_t cost = coarse || loose ? filter::kCoarseIterations : 1U;
    if (cost > budget && n > 0U) {
      break;
    }
    budget -= cost < budget ? cost : budget;
    ++n;
  }
  return n;
}

/** Applies the queued matches that fit in matches_per_job updates (two calls when the ring wraps). */
void apply_matches(FilterCore& c, filter::UpdateReport& job) noexcept {
  MatchQueue& q = *c.queue;
  std::uint32_t budget = c.cfg->matches_per_job;
  for (int pass = 0; pass < 2 && budget > 0U && q.count > 0U; ++pass) {
    const std::uint32_t contiguous = kMatchQueueLen - q.head;
    // A loose position iterates every match (Ekf::update()): each counts as a coarse one.
    const std::uint32_t n =
        matches_that_fit(q, q.head, q.count < contiguous ? q.count : contiguous, c.ekf->position_loose(), budget);
    filter::UpdateReport rep{};
    if (c.ekf->update(&q.m[q.head], n, rep) != filter::FilterStatus::kOk) {
      ++c.stats->filter_errors;
    }
    c.stats->matches_applied += rep.accepted;
    c.stats->coarse_applied += rep.coarse_accepted;
    c.stats->rejected_gate += rep.rejected_gate;
    c.stats->rejected_stale += rep.rejected_stale;
    c.stats->rejected_invalid += rep.rejected_invalid;
    job.accepted += rep.accepted;
    job.rejected_gate += rep.rejected_gate;
    job.nis_sum += rep.nis_sum;
    q.head = (q.head + n) % kMatchQueueLen;
    q.count -= n;
  }
}

/**
 * The queue and the last sample as words: [0] head, [1] count, the queued
 * matches packed as on the network at their ring positions (the head matters:
 * apply_matches() splits a job's matches where the ring wraps, and the split
 * changes the result's bits), then have_imu and last_imu in the last two words.
 */
void queue_words(const FilterCore& c, std::array<std::uint32_t, kQueueWords>& w) noexcept {
  const MatchQueue& q = *c.queue;
  w.fill(0U);
  w[0] = q.head;
  w[1] = q.count;
  for (std::uint32_t i = 0; i < q.count && i < kMatchQueueLen; ++i) {
    const std::uint32_t at = (q.head + i) % kMatchQueueLen;
    (void)fdir::msg::encode(kMatchRecord, q.m[at],
                            std::span<std::uint32_t>(w.data() + 2U + static_cast<std::size_t>(at) * kMatchWords, kMatchWords));
  }
  w[kQueueWords - 2U] = c.have_imu ? 1U : 0U;
  w[kQueueWords - 1U] = c.last_imu;
}

}  // namespace

void record_begin(JobRecord& r, std::uint32_t job) noexcept {
  r.w.fill(0U);
  r.w[0] = job;
}

bool record_add_imu(JobRecord& r, const bsp::ImuSample& s) noexcept {
  const std::uint32_t n = r.w[1];
  if (n >= kRecordImuMax) {
    return false;
  }
  (void)fdir::msg::encode(kImuMsg, s,
                          std::span<std::uint32_t>(r.w.data() + kImuAt + static_cast<std::size_t>(n) * kImuWords, kImuWords));
  r.w[1] = n + 1U;
  return true;
}

bool record_add_match(JobRecord& r, std::span<const std::uint32_t, kMatchWords> m) noexcept {
  const std::uint32_t n = r.w[2];
  if (n >= kRecordMatchMax) {
    return false;
  }
  const std::size_t at = kMatchAt + static_cast<std::size_t>(n) * kMatchWords;
  for (std::uint32_t i = 0; i < kMatchWords; ++i) {
    r.w[at + i] = m[i];
  }
  r.w[2] = n + 1U;
  return true;
}

void record_seal(JobRecord& r, bsp::Work& work) noexcept {
  r.w[3] = udn::crc32c_words(record_body(r));
  work.int_ops += 4ULL * kRecordWords;
  work.mem_words += kRecordWords;
}

bool record_ok(const JobRecord& r, std::uint32_t job, bsp::Work& work) noexcept {
  work.int_ops += 4ULL * kRecordWords;
  work.mem_words += kRecordWords;
  return r.w[0] == job && r.w[1] <= kRecordImuMax && r.w[2] <= kRecordMatchMax &&
         r.w[3] == udn::crc32c_words(record_body(r));
}

namespace {

// The settings are doubles only, so their bytes are their values: no padding enters the digest.
static_assert(sizeof(filter::FilterConfig) % sizeof(double) == 0U && sizeof(filter::CameraGeometry) == 13U * sizeof(double),
              "settings without padding");

template <typename T>
std::span<const std::uint8_t> bytes_of(const T& v) noexcept {
  return {reinterpret_cast<const std::uint8_t*>(&v), sizeof v};  // NOLINT(cppcoreguidelines-pro-type-reinterpret-cast): RAM bytes
}

/** The CRC-32C of each part of the EKF's settings, in the order of their bits (kSettingsConfig...). */
std::array<std::uint32_t, 3> settings_digests(const FilterCore& c, bsp::Work& work) noexcept {
  work.int_ops += 8ULL * (kEkfSettingsBytes / 4U);
  work.mem_words += 2ULL * (kEkfSettingsBytes / 4U);
  return {udn::crc32c_bytes(bytes_of(c.ekf->config())), udn::crc32c_bytes(bytes_of(c.ekf->camera())),
          udn::crc32c_bytes(bytes_of(c.ekf->process_noise()))};
}

}  // namespace

bool core_set_up(FilterCore& c, const FilterTaskConfig& cfg, bsp::Region ram) noexcept {
  c = FilterCore{};
  c.cfg = &cfg;
  bsp::MemError err = bsp::MemError::kOk;
  auto* ekf = bsp::carve_array<filter::Ekf>(ram, 1, kEkfCarve, &err);
  if (err != bsp::MemError::kOk) {
    return false;
  }
  ::new (ekf) filter::Ekf{};
  c.ekf = ekf;
  auto* queue = bsp::carve_array<MatchQueue>(ram, 1, "match queue", &err);
  if (err != bsp::MemError::kOk) {
    return false;
  }
  ::new (queue) MatchQueue{};
  c.queue = queue;
  auto* scratch = bsp::carve_array<filter::StateBlock>(ram, 1, "state block", &err);
  if (err != bsp::MemError::kOk) {
    return false;
  }
  ::new (scratch) filter::StateBlock{};
  c.scratch = scratch;
  // The counters last: the core's other carves keep the places they had before the counters were a record.
  c.stats = bsp::carve_record(ram, kFilterTaskStatsRecord, &err);
  if (c.stats == nullptr) {
    return false;
  }
  if (c.ekf->configure(cfg.filter, cfg.camera) != filter::FilterStatus::kOk) {
    return false;
  }
  bsp::Work work{};
  c.settings_crc = settings_digests(c, work);
  bsp::consume(work);
  return true;
}

std::uint32_t core_settings_changed(const FilterCore& c, bsp::Work& work) noexcept {
  const std::array<std::uint32_t, 3> now = settings_digests(c, work);
  std::uint32_t changed = 0U;
  for (std::size_t i = 0; i < now.size(); ++i) {
    changed |= now[i] != c.settings_crc[i] ? 1U << i : 0U;
  }
  return changed;
}

bool core_reload_settings(FilterCore& c, bsp::Work& work) noexcept {
  // The checks of configure() (config ranges, the camera rotation's orthonormality) and the
  // process noise: a few hundred flops.
  work.flops += 300U;
  work.fdivs += 20U;
  if (c.ekf->reload_settings(c.cfg->filter, c.cfg->camera) != filter::FilterStatus::kOk) {
    return false;
  }
  c.settings_crc = settings_digests(c, work);
  return true;
}

filter::UpdateReport core_run(FilterCore& c, const JobRecord& r) noexcept {
  const std::uint32_t n_imu = record_imu_count(r) < kRecordImuMax ? record_imu_count(r) : kRecordImuMax;
  for (std::uint32_t i = 0; i < n_imu; ++i) {
    integrate(c, fdir::msg::read(kImuMsg, std::span<const std::uint32_t, kImuWords>(
                     r.w.data() + kImuAt + static_cast<std::size_t>(i) * kImuWords, kImuWords)));
  }
  bsp::consume(c.ekf->take_work());
  const std::uint32_t n_m = record_match_count(r) < kRecordMatchMax ? record_match_count(r) : kRecordMatchMax;
  for (std::uint32_t i = 0; i < n_m; ++i) {
    push(*c.queue,
         fdir::msg::read(kMatchRecord, std::span<const std::uint32_t, kMatchWords>(
             r.w.data() + kMatchAt + static_cast<std::size_t>(i) * kMatchWords, kMatchWords)),
         *c.stats);
  }
  bsp::consume(bsp::Work{2ULL * n_m * kMatchWords, 4ULL * n_m, 0U, 0U, 0U});
  filter::UpdateReport job{};
  apply_matches(c, job);
  bsp::consume(c.ekf->take_work());
  // The state after the job's updates is a published result: where a corrupted update is injected.
  filter::NominalState x = c.ekf->state().x;
  if (bsp::publish_filter(kFilterStateChannel, &x, sizeof x)) {
    c.ekf->set_nominal(x);
  }
  return job;
}

filter::NavOutput core_output(const FilterCore& c) noexcept {
  return filter::make_nav_output(c.ekf->state(), c.ekf->config());
}

void core_drop_matches(FilterCore& c) noexcept {
  c.queue->head = 0U;
  c.queue->count = 0U;
}

std::uint32_t core_digest(FilterCore& c, bsp::Work& work) noexcept {
  (void)filter::write_state_block(c.ekf->state(), *c.scratch);
  std::uint32_t crc = udn::crc32c_bytes(std::span<const std::uint8_t>(c.scratch->data(), c.scratch->size()));
  // The queue match by match from its head (no copy of it on the task's stack), head included.
  const MatchQueue& q = *c.queue;
  const std::array<std::uint32_t, 2> head{q.head, q.count};
  crc = udn::crc32c_words_continue(crc, head);
  std::array<std::uint32_t, kMatchWords> m{};
  for (std::uint32_t i = 0; i < q.count && i < kMatchQueueLen; ++i) {
    (void)fdir::msg::encode(kMatchRecord, q.m[(q.head + i) % kMatchQueueLen], m);
    crc = udn::crc32c_words_continue(crc, m);
  }
  const std::array<std::uint32_t, 2> tail{c.have_imu ? 1U : 0U, c.last_imu};
  work.int_ops += 8ULL * (filter::kStateBlockBytes / 4U + 4U + q.count * kMatchWords);
  work.mem_words += 2ULL * (filter::kStateBlockBytes / 4U + 4U + q.count * kMatchWords);
  return udn::crc32c_words_continue(crc, tail);
}

void core_save(FilterCore& c, CoreImage& out, bsp::Work& work) noexcept {
  (void)filter::write_state_block(c.ekf->state(), out.block);
  queue_words(c, out.queue);
  work.int_ops += 4ULL * (filter::kStateBlockBytes / 4U + kQueueWords);
  work.mem_words += 2ULL * (filter::kStateBlockBytes / 4U + kQueueWords);
}

bool core_load(FilterCore& c, const CoreImage& in, bsp::Work& work) noexcept {
  work.int_ops += 4ULL * (filter::kStateBlockBytes / 4U + kQueueWords);
  work.mem_words += 2ULL * (filter::kStateBlockBytes / 4U + kQueueWords);
  const std::uint32_t head = in.queue[0];
  const std::uint32_t count = in.queue[1];
  if (head >= kMatchQueueLen || count > kMatchQueueLen || in.queue[kQueueWords - 2U] > 1U) {
    return false;
  }
  // The state stays in the block reader's static scratch (18 KiB off the stack), restored at once.
  filter::BlockError e = filter::BlockError::kOk;
  const filter::FilterState* st = filter::read_state_block_in_place(in.block.data(), filter::kStateBlockBytes, e);
  if (st == nullptr || c.ekf->restore(*st) != filter::FilterStatus::kOk) {
    return false;
  }
  MatchQueue& q = *c.queue;
  q.head = head;
  q.count = count;
  for (std::uint32_t i = 0; i < count; ++i) {
    const std::uint32_t at = (head + i) % kMatchQueueLen;
    q.m[at] = fdir::msg::read(kMatchRecord, std::span<const std::uint32_t, kMatchWords>(
        in.queue.data() + 2U + static_cast<std::size_t>(at) * kMatchWords, kMatchWords));
  }
  c.have_imu = in.queue[kQueueWords - 2U] == 1U;
  c.last_imu = in.queue[kQueueWords - 1U];
  return true;
}

}  // namespace trn::tasks
