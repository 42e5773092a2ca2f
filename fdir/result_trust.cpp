/**
 * @file result_trust.cpp
 * @brief Result trust per worker: a sliding window of failed checks, suspect, reset, replace.
 */
#include "fdir/result_trust.hpp"

#include "fdir/event_log.hpp"

namespace fdir {
namespace {

// A ResultTrust may sit in RAM that takes upsets (the vision coordinator's state): its count and
// window are taken bounded, so a flipped one never indexes past the arrays or divides by zero. The
// owner finds and reports the upset itself (vision_coord.cpp, check_coord).
std::uint32_t count_of(const ResultTrust& t) noexcept { return t.count < kMaxTrustWorkers ? t.count : kMaxTrustWorkers; }
std::uint32_t window_of(const ResultTrust& t) noexcept {
  return t.config.window == 0U ? 1U : (t.config.window < kMaxTrustWindow ? t.config.window : kMaxTrustWindow);
}

void clear_window(ResultTrust& t, std::uint32_t i) noexcept {
  t.checked[i].fill(0U);
  t.failed[i].fill(0U);
}

std::uint16_t clamp16(std::uint32_t v) noexcept { return static_cast<std::uint16_t>(v > 0xFFFFU ? 0xFFFFU : v); }

/** A suspect or reset worker's clean round: trusted again after probation of them. */
void take_clean(ResultTrust& t, std::uint32_t i) noexcept {
  ++t.clean[i];
  if (t.clean[i] >= t.config.probation) {
    const std::uint32_t after_reset = t.state[i] == TrustState::kReset ? 1U : 0U;
    report(EventId::kResultsConsistent, t.tile[i], after_reset, t.clean[i]);
    t.state[i] = TrustState::kTrusted;
    t.clean[i] = 0U;
    t.rounds_bad[i] = 0U;
  }
}

}  // namespace

TrustError result_trust_init(ResultTrust& t, const ResultTrustConfig& config, const bsp::TileId* tiles,
                             std::uint32_t count) noexcept {
  if (config.window == 0U || config.window > kMaxTrustWindow || config.min_failed == 0U ||
      config.reset_after == 0U || config.probation == 0U || count > kMaxTrustWorkers ||
      (tiles == nullptr && count > 0U)) {
    return TrustError::kBadConfig;
  }
  t = ResultTrust{};
  t.config = config;
  t.count = count;
  for (std::uint32_t i = 0; i < count; ++i) {
    t.tile[i] = tiles[i];
  }
  return TrustError::kOk;
}

bool result_trust_used(const ResultTrust& t, std::uint32_t i) noexcept {
  return i < count_of(t) && t.state[i] == TrustState::kTrusted;
}

TrustAction result_trust_round(ResultTrust& t, std::uint32_t i, std::uint32_t checked, std::uint32_t failed) noexcept {
  if (i >= count_of(t)) {
    return TrustAction::kNone;
  }
  const std::uint32_t window = window_of(t);
  const std::uint32_t at = t.round % window;
  t.checked[i][at] = clamp16(checked);
  t.failed[i][at] = clamp16(failed > checked ? checked : failed);
  std::uint32_t sum_checked = 0U;
  std::uint32_t sum_failed = 0U;
  for (std::uint32_t k = 0; k < window; ++k) {
    sum_checked += t.checked[i][k];
    sum_failed += t.failed[i][k];
  }
  const bool fires = sum_failed >= t.config.min_failed && 2U * sum_failed >= sum_checked;
  const bool clean = checked > 0U && failed == 0U;
  const bool bad = checked > 0U && failed > 0U;
  switch (t.state[i]) {
    case TrustState::kTrusted:
      if (fires) {
        t.state[i] = TrustState::kSuspect;
        t.rounds_bad[i] = 0U;
        t.clean[i] = 0U;
        report(EventId::kResultsSuspect, t.tile[i], 0U, sum_failed, sum_checked);
      }
      return TrustAction::kNone;
    case TrustState::kSuspect:
      if (clean) {
        take_clean(t, i);
      } else if (bad) {
        t.clean[i] = 0U;
        ++t.rounds_bad[i];
        if (t.rounds_bad[i] >= t.config.reset_after) {
          t.state[i] = TrustState::kReset;
          clear_window(t, i);  // after the reset only new failures count
          return TrustAction::kReset;
        }
      }
      return TrustAction::kNone;
    case TrustState::kReset:
      if (clean) {
        take_clean(t, i);
      } else if (fires) {
        t.state[i] = TrustState::kReplacing;
        report(EventId::kResultsSuspect, t.tile[i], 1U, sum_failed, sum_checked);
        return TrustAction::kReplace;
      } else if (bad) {
        t.clean[i] = 0U;
      }
      return TrustAction::kNone;
    case TrustState::kReplacing:
      return TrustAction::kNone;
  }
  return TrustAction::kNone;
}

void result_trust_close_round(ResultTrust& t) noexcept { ++t.round; }

void result_trust_replace(ResultTrust& t, std::uint32_t i, bsp::TileId tile) noexcept {
  if (i >= count_of(t)) {
    return;
  }
  t.tile[i] = tile;
  t.state[i] = TrustState::kTrusted;
  t.rounds_bad[i] = 0U;
  t.clean[i] = 0U;
  clear_window(t, i);
}

std::uint32_t result_trust_untrusted(const ResultTrust& t) noexcept {
  std::uint32_t n = 0U;
  for (std::uint32_t i = 0; i < count_of(t); ++i) {
    n += t.state[i] == TrustState::kTrusted ? 0U : 1U;
  }
  return n;
}

}  // namespace fdir
