/**
 * @file result_trust.hpp
 * @brief Trust in the results of the workers a coordinator hands work to: a worker whose results
 *        fail a consistency check far more often than chance is suspect, its results are not used,
 *        it is reset, and it is replaced if it stays wrong (the paper's check of the (w_i, V_i) set).
 *
 * Liveness (liveness.hpp) covers a worker that does not answer; this covers one
 * that answers wrong. The coordinator checks each round's results against each
 * other (for the vision tiles: every match against the pose the frame's matches
 * fit together, trn/tasks/match_consistency.hpp) and tells this module, per
 * worker, how many of its results were checked and how many failed. Over the
 * last `window` rounds a worker is suspect when at least `min_failed` of its
 * results failed and at least half of those checked did.
 *
 * False-alarm rate. If a clean result fails independently with probability p,
 * a worker with c results in the window is falsely suspect only if at least
 * max(min_failed, c/2) of them fail: P <= C(c, f) p^f with f that bound. With
 * the measured p (docs/FDIR.md: about 1e-3 per match) and min_failed 3, a
 * worker with 15 matches in its window (5 a frame, 40 tiles) is falsely suspect
 * with P <= C(15, 8) 1e-24 ~ 6e-21 a window; a worker with only 3 results
 * (the least that can fire) with P <= 1e-9. Over 40 workers and 300 frames that
 * is at most about 1e-5 a mission.
 *
 * The states, each change an event written by the coordinator's tile:
 *   trusted  --(window fires: failures or bias)--> suspect (kResultsSuspect)
 *   suspect  --(probation clean rounds)-->       trusted   (kResultsConsistent: a transient)
 *   suspect  --(reset_after rounds still bad)--> reset asked (the action kReset)
 *   reset    --(probation clean rounds)-->       trusted   (kResultsConsistent)
 *   reset    --(window fires again)-->           replace asked (the action kReplace)
 * A suspect worker's results are still checked (that is how it proves itself)
 * but not used. A clean round is one with results checked and none failed;
 * a round where the worker had nothing checked does not count either way.
 *
 * Flight code: plain data in the coordinator's carved state, bounded loops.
 */
#pragma once

#include "bsp_tile64/api/port.hpp"

#include <array>
#include <cstdint>

namespace fdir {

inline constexpr std::uint32_t kMaxTrustWorkers = 48U;
inline constexpr std::uint32_t kMaxTrustWindow = 8U;

struct ResultTrustConfig {
  std::uint32_t window = 3U;       ///< rounds in the sliding window (1..kMaxTrustWindow)
  std::uint32_t min_failed = 3U;   ///< failed results in the window before a worker can be suspect (>= 1)
  std::uint32_t reset_after = 2U;  ///< rounds suspect (not clean again) before its reset is asked (>= 1)
  std::uint32_t probation = 3U;    ///< clean rounds in a row that make a suspect or reset worker trusted (>= 1)
  std::uint32_t bias_window = 8U;       ///< rounds in the bias test's window (1..kMaxTrustWindow)
  std::uint32_t bias_min = 12U;         ///< fitted results in that window before its bias is judged (>= 2)
  std::uint32_t bias_sigmas = 6U;       ///< a mean residual past this many standard errors ... (>= 1)
  std::uint32_t bias_floor_mpx = 280U;  ///< ... and past this (thousandths of a pixel) makes a worker suspect
  std::uint32_t bias_clip_mpx = 600U;   ///< each residual taken at most this far from 0 (a few large ones weigh no more)
};

/**
 * A worker's fitted results of a round: the sums of their signed residuals on each axis against
 * the fit of all workers' results, and the round's robust per-axis residual scale. A worker whose
 * results are all shifted alike by less than the per-result threshold passes that test result by
 * result; the mean of its residuals over the window does not (the bias test).
 */
struct RoundResiduals {
  double sum_u = 0.0;
  double sum_v = 0.0;
  std::uint32_t n = 0U;
  double scale = 0.0;
};

enum class TrustState : std::uint8_t { kTrusted, kSuspect, kReset, kReplacing };

/** What the coordinator is to do about a worker after a round. */
enum class TrustAction : std::uint8_t { kNone, kReset, kReplace };

struct ResultTrust {
  ResultTrustConfig config{};
  std::uint32_t count = 0U;
  std::array<bsp::TileId, kMaxTrustWorkers> tile{};
  std::array<TrustState, kMaxTrustWorkers> state{};
  std::array<std::array<std::uint16_t, kMaxTrustWindow>, kMaxTrustWorkers> checked{};  ///< ring per worker
  std::array<std::array<std::uint16_t, kMaxTrustWindow>, kMaxTrustWorkers> failed{};
  std::array<std::uint32_t, kMaxTrustWorkers> rounds_bad{};  ///< rounds since suspect that were not clean
  std::array<std::uint32_t, kMaxTrustWorkers> clean{};       ///< clean rounds in a row while not trusted
  std::uint32_t round = 0U;                                  ///< rounds closed (ring index = round % window)
  std::array<std::array<float, kMaxTrustWindow>, kMaxTrustWorkers> sum_u{};  ///< ring per worker: RoundResiduals
  std::array<std::array<float, kMaxTrustWindow>, kMaxTrustWorkers> sum_v{};
  std::array<std::array<std::uint16_t, kMaxTrustWindow>, kMaxTrustWorkers> fitted{};
  std::array<std::array<float, kMaxTrustWindow>, kMaxTrustWorkers> scale{};
};

enum class TrustError : std::uint8_t { kOk, kBadConfig };

/** Starts tracking @p count workers (tiles @p tiles), all trusted. @return kBadConfig for a bad setting or too many. */
[[nodiscard]] TrustError result_trust_init(ResultTrust& t, const ResultTrustConfig& config, const bsp::TileId* tiles,
                                           std::uint32_t count) noexcept;

/** Whether the results of worker @p i are to be used (only a trusted worker's are). */
[[nodiscard]] bool result_trust_used(const ResultTrust& t, std::uint32_t i) noexcept;

/**
 * Records worker @p i's round: @p checked results checked, @p failed of them
 * failed, and the residuals @p res of those that were fitted. Call once per
 * worker per round (0, 0 for a worker with nothing checked), then
 * result_trust_close_round(). The window fires when it holds at least
 * min_failed failed results and at least half of those checked failed, or
 * when, over the last bias_window rounds, the mean residual of its fitted
 * results (each clipped to bias_clip_mpx) on either axis is past both
 * bias_sigmas standard errors (the largest scale of its rounds over the
 * square root of their count) and bias_floor_mpx, with at least bias_min of
 * them (the bias test). A round is clean when it had results checked, none
 * failed and the window shows no bias; one that brought residuals, only once
 * the bias window holds bias_min of them (a verdict). Writes kResultsSuspect or
 * kResultsConsistent on a change. [task]
 * @return what the coordinator is to ask for this worker now.
 */
TrustAction result_trust_round(ResultTrust& t, std::uint32_t i, std::uint32_t checked, std::uint32_t failed,
                               const RoundResiduals& res = {}) noexcept;

/** Adds one fitted result's residual (@p du, @p dv, pixels) to @p r, each axis clipped to bias_clip_mpx. */
void result_trust_add_residual(const ResultTrust& t, RoundResiduals& r, double du, double dv) noexcept;

/** The larger mean residual of worker @p i's bias window on either axis, in pixels (0 with fewer than bias_min). */
[[nodiscard]] double result_trust_bias_px(const ResultTrust& t, std::uint32_t i) noexcept;

/** Closes the round: the window moves on. */
void result_trust_close_round(ResultTrust& t) noexcept;

/** Worker @p i now runs on tile @p tile (a replacement): trusted, its window emptied. */
void result_trust_replace(ResultTrust& t, std::uint32_t i, bsp::TileId tile) noexcept;

/** Workers whose results are not used now. */
[[nodiscard]] std::uint32_t result_trust_untrusted(const ResultTrust& t) noexcept;

}  // namespace fdir
