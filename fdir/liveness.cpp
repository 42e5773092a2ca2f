/**
 * @file liveness.cpp
 * @brief Worker liveness: misses in a row, isolation, probe rounds, return.
 */
#include "fdir/liveness.hpp"

#include "fdir/event_log.hpp"

namespace fdir {
namespace {

// A Liveness may sit in RAM that takes upsets (the vision coordinator's state): every count and
// divisor it holds is taken bounded, so a flipped one never indexes past its arrays or divides by
// zero. The owner finds and reports the upset itself (vision_coord.cpp, check_coord).
std::uint32_t count_of(const Liveness& l) noexcept { return l.count < kMaxWorkers ? l.count : kMaxWorkers; }
std::uint32_t probe_every_of(const Liveness& l) noexcept { return l.config.probe_every != 0U ? l.config.probe_every : 1U; }

}  // namespace

LivenessError liveness_init(Liveness& l, const LivenessConfig& config, const bsp::TileId* tiles,
                            std::uint32_t count) noexcept {
  if (config.suspect_after_misses == 0U || config.probe_every == 0U || count > kMaxWorkers ||
      (tiles == nullptr && count > 0U)) {
    return LivenessError::kBadConfig;
  }
  l = Liveness{};
  l.config = config;
  l.count = count;
  for (std::uint32_t i = 0; i < count; ++i) {
    l.tile[i] = tiles[i];
  }
  return LivenessError::kOk;
}

bool liveness_gets_work(const Liveness& l, std::uint32_t i, std::uint32_t round) noexcept {
  return i < count_of(l) && (l.misses[i] < l.config.suspect_after_misses || round % probe_every_of(l) == 0U);
}

void liveness_answered(Liveness& l, std::uint32_t i) noexcept {
  if (i >= count_of(l)) {
    return;
  }
  if (l.misses[i] >= l.config.suspect_after_misses) {
    report(EventId::kWorkerBack, l.tile[i], 0U, l.misses[i]);
  }
  l.misses[i] = 0U;
}

void liveness_missed(Liveness& l, std::uint32_t i) noexcept {
  if (i >= count_of(l)) {
    return;
  }
  ++l.misses[i];
  if (l.misses[i] == l.config.suspect_after_misses) {
    report(EventId::kWorkerSilent, l.tile[i], 0U, l.misses[i]);
  }
}

std::uint32_t liveness_isolated(const Liveness& l) noexcept {
  std::uint32_t n = 0U;
  for (std::uint32_t i = 0; i < count_of(l); ++i) {
    n += l.misses[i] >= l.config.suspect_after_misses ? 1U : 0U;
  }
  return n;
}

}  // namespace fdir
