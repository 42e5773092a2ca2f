/**
 * @file result_trust.cpp
 * @brief Result trust per worker: a sliding window of failed checks, suspect, reset, replace.
 */
#include "fdir/result_trust.hpp"

#include "fdir/event_log.hpp"

#include <algorithm>
#include <cmath>

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
  t.sum_u[i].fill(0.0F);
  t.sum_v[i].fill(0.0F);
  t.fitted[i].fill(0U);
  t.scale[i].fill(0.0F);
}

/** The bias test over worker @p i's window (result_trust_round()). */
struct Bias {
  bool biased = false;
  double mean_px = 0.0;  ///< the larger mean residual on either axis (0 with too few results)
  std::uint32_t n = 0U;  ///< fitted results in the window
};

std::uint32_t bias_window_of(const ResultTrust& t) noexcept {
  return t.config.bias_window == 0U ? 1U : (t.config.bias_window < kMaxTrustWindow ? t.config.bias_window : kMaxTrustWindow);
}

Bias window_bias(const ResultTrust& t, std::uint32_t i) noexcept {
  const std::uint32_t window = bias_window_of(t);
  double su = 0.0;
  double sv = 0.0;
  double scale = 0.0;
  Bias b{};
  for (std::uint32_t k = 0; k < window; ++k) {
    su += static_cast<double>(t.sum_u[i][k]);
    sv += static_cast<double>(t.sum_v[i][k]);
    scale = std::max(scale, static_cast<double>(t.scale[i][k]));
    b.n += t.fitted[i][k];
  }
  if (b.n < std::max(t.config.bias_min, 2U)) {
    return b;
  }
  const double n = static_cast<double>(b.n);
  b.mean_px = std::max(std::fabs(su), std::fabs(sv)) / n;
  const double limit = std::max(static_cast<double>(t.config.bias_sigmas) * scale / std::sqrt(n),
                                1e-3 * static_cast<double>(t.config.bias_floor_mpx));
  b.biased = b.mean_px > limit;  // a non-finite sum (an upset of the rings) is no verdict
  return b;
}

std::uint16_t clamp16(std::uint32_t v) noexcept { return static_cast<std::uint16_t>(v > 0xFFFFU ? 0xFFFFU : v); }

/** Puts worker @p i's round into its windows; @p sum_checked and @p sum_failed: the failure window's sums after it. */
void store_round(ResultTrust& t, std::uint32_t i, std::uint32_t checked, std::uint32_t failed, const RoundResiduals& res,
                 std::uint32_t& sum_checked, std::uint32_t& sum_failed) noexcept {
  const std::uint32_t window = window_of(t);
  const std::uint32_t at = t.round % window;
  t.checked[i][at] = clamp16(checked);
  t.failed[i][at] = clamp16(failed > checked ? checked : failed);
  const std::uint32_t bias_at = t.round % bias_window_of(t);
  t.sum_u[i][bias_at] = static_cast<float>(res.sum_u);
  t.sum_v[i][bias_at] = static_cast<float>(res.sum_v);
  t.fitted[i][bias_at] = clamp16(res.n);
  t.scale[i][bias_at] = static_cast<float>(res.scale);
  for (std::uint32_t k = 0; k < window; ++k) {
    sum_checked += t.checked[i][k];
    sum_failed += t.failed[i][k];
  }
}

std::uint32_t mpx(double px) noexcept {
  return px < 4.0e6 ? static_cast<std::uint32_t>(std::lround(1e3 * px)) : 0xFFFF'FFFFU;
}


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
      config.reset_after == 0U || config.probation == 0U || config.bias_window == 0U ||
      config.bias_window > kMaxTrustWindow || config.bias_min < 2U || config.bias_sigmas == 0U ||
      count > kMaxTrustWorkers ||
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

TrustAction result_trust_round(ResultTrust& t, std::uint32_t i, std::uint32_t checked, std::uint32_t failed,
                               const RoundResiduals& res) noexcept {
  if (i >= count_of(t)) {
    return TrustAction::kNone;
  }
  std::uint32_t sum_checked = 0U;
  std::uint32_t sum_failed = 0U;
  store_round(t, i, checked, failed, res, sum_checked, sum_failed);
  const bool failing = sum_failed >= t.config.min_failed && 2U * sum_failed >= sum_checked;
  const Bias bias = window_bias(t, i);
  const bool fires = failing || bias.biased;
  // A round that brought residuals is clean only once the bias window can judge them: a shifted
  // worker just reset has too few for a verdict, and must not pass probation on that alone.
  const bool judged = res.n == 0U || bias.n >= std::max(t.config.bias_min, 2U);
  const bool clean = checked > 0U && failed == 0U && !bias.biased && judged;
  const bool bad = checked > 0U && (failed > 0U || bias.biased);
  // What the event says: the failures in the window, or (the bias alone) its mean residual and count.
  const std::uint32_t why = failing ? 0U : 2U;
  const std::uint32_t a = failing ? sum_failed : mpx(bias.mean_px);
  const std::uint32_t b = failing ? sum_checked : bias.n;
  switch (t.state[i]) {
    case TrustState::kTrusted:
      if (fires) {
        t.state[i] = TrustState::kSuspect;
        t.rounds_bad[i] = 0U;
        t.clean[i] = 0U;
        report(EventId::kResultsSuspect, t.tile[i], why, a, b);
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
        report(EventId::kResultsSuspect, t.tile[i], 1U + why, a, b);
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

void result_trust_add_residual(const ResultTrust& t, RoundResiduals& r, double du, double dv) noexcept {
  const double c = 1e-3 * static_cast<double>(t.config.bias_clip_mpx);
  r.sum_u += std::clamp(du, -c, c);
  r.sum_v += std::clamp(dv, -c, c);
  ++r.n;
}

double result_trust_bias_px(const ResultTrust& t, std::uint32_t i) noexcept {
  return i < count_of(t) ? window_bias(t, i).mean_px : 0.0;
}

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
