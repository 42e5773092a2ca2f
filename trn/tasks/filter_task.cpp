/**
 * @file filter_task.cpp
 * @brief The 100 Hz navigation filter job.
 */
#include "trn/tasks/filter_task.hpp"

#include "bsp_tile64/memory.hpp"
#include "kernel/kernel.hpp"
#include "trn/tasks/messages.hpp"
#include "udn/raw.hpp"

#include <array>
#include <new>

namespace trn::tasks {
namespace {

struct Slot {
  filter::Ekf* ekf;
  FilterTaskStats stats;
  filter::NavOutput latest;
  bool published;
};

std::array<Slot, bsp::kMaxTiles> g_slots{};

/** Integrates up to kMaxImuPerJob samples waiting in the IMU queue. */
void consume_imu(Slot& slot) noexcept {
  std::array<std::uint32_t, kImuWords> words{};
  for (std::uint32_t n = 0; n < kMaxImuPerJob; ++n) {
    udn::RxInfo info{};
    if (udn::receive(kImuQueue, info, words, k::kNoWait) != udn::RawError::kOk) {
      return;
    }
    if (info.data_words != kImuWords) {
      ++slot.stats.imu_rejected;
      continue;
    }
    const bsp::ImuSample s = unpack_imu(words);
    filter::UpdateReport rep{};
    const filter::FilterStatus st = slot.ekf->step(filter::StepInput{&s, nullptr, 0}, rep);
    if (st == filter::FilterStatus::kOk) {
      ++slot.stats.imu_used;
    } else if (st == filter::FilterStatus::kImuInvalid) {
      ++slot.stats.imu_rejected;
    } else {
      ++slot.stats.filter_errors;
    }
  }
}

void publish(Slot& slot) noexcept {
  filter::NavOutput out = filter::make_nav_output(slot.ekf->state(), slot.ekf->config());
  // The published value is what a fault may corrupt on its way out.
  (void)bsp::publish_filter(kNavChannel, &out, sizeof out);
  slot.latest = out;
  slot.published = true;
}

bool set_up(Slot& slot, const FilterTaskConfig& cfg) noexcept {
  bsp::MemError err = bsp::MemError::kOk;
  auto* ekf = bsp::carve_array<filter::Ekf>(bsp::Region{bsp::current_tile()}, 1, "ekf", &err);
  if (err != bsp::MemError::kOk) {
    return false;
  }
  ::new (ekf) filter::Ekf{};
  slot.ekf = ekf;
  return slot.ekf->configure(cfg.filter, cfg.camera) == filter::FilterStatus::kOk &&
         slot.ekf->init(cfg.initial) == filter::FilterStatus::kOk && udn::activate() == udn::RawError::kOk &&
         udn::bind(kTagImu, kImuQueue) == udn::RawError::kOk;
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
    consume_imu(slot);
    bsp::consume(slot.ekf->take_work());
    publish(slot);
    ++slot.stats.jobs;
    slot.stats.last_job_cycles = bsp::now() - start;
    if (slot.stats.last_job_cycles > slot.stats.max_job_cycles) {
      slot.stats.max_job_cycles = slot.stats.last_job_cycles;
    }
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
