/**
 * @file innovation_monitor.hpp
 * @brief Whether a Kalman filter's measurements still agree with its own covariance: the
 *        fraction it rejects and its normalised innovations over a window, against the
 *        chi-square law the covariance predicts.
 *
 * A filter whose state or covariance went wrong without failing its
 * plausibility check (a state off by less than the check's sigmas, a
 * covariance too small) meets its measurements with innovations larger than
 * its covariance says: first larger normalised innovations, then rejections
 * at the gate, until it rejects all and is corrected by none. This module
 * watches that.
 *
 * Each measurement that reaches the gate gives d2 = r^T S^-1 r. For a filter
 * whose covariance is right, d2 of a 2-row measurement is chi-square with 2
 * degrees of freedom: exponential with mean 2. Clipped at the gate g (an
 * outlier weighs no more than g), its mean is mu = 2 (1 - e^{-g/2}), its
 * variance 8 (1 - e^{-g/2} (1 + g/2)) - mu^2, and the probability of a
 * rejection p = e^{-g/2} (99.9 % gate: mu = 1.998, sd 1.99, p = 0.001).
 *
 * The filter tells the monitor, per job, how many measurements reached the
 * gate, how many it rejected and the sum of their clipped d2. These are
 * gathered in blocks of block_matches measurements; over the last
 * window_blocks blocks the window fails when
 *   - the mean clipped d2 is more than nis_sigmas standard errors above mu and
 *     above nis_floor_milli / 1000 (cause kNisHigh), or
 *   - the rejected fraction is more than reject_sigmas standard errors above p
 *     and above reject_floor_pct % (cause kRejectedHigh).
 * The floors are there because the filter's matches are not the ideal law:
 * their sigmas are estimates, so a clean flight's windows have means a little
 * off mu, never near the floors (docs/FDIR.md, "Innovation monitor", the
 * measured clean maxima). A window that fails is cleared: what the filter does
 * about it (trn/tasks/filter/filter_task.cpp) changes its innovations, and the
 * next verdict is on measurements made after it.
 *
 * Flight code: plain data in the filter task's carved state, integer sums,
 * bounded loops; a count an upset made absurd is bounded where it is used.
 */
#pragma once

#include "bsp_tile64/api/memory.hpp"
#include "bsp_tile64/api/work.hpp"

#include <array>
#include <cstdint>

namespace fdir {

inline constexpr std::uint32_t kMaxInnovationBlocks = 16U;

struct InnovationMonitorConfig {
  std::uint32_t block_matches = 20U;       ///< measurements per block (>= 1)
  std::uint32_t window_blocks = 6U;        ///< blocks in the window judged (1..kMaxInnovationBlocks)
  std::uint32_t nis_sigmas = 6U;           ///< the window's mean clipped d2 past mu by this many standard errors ...
  std::uint32_t nis_floor_milli = 4000U;   ///< ... and past this (thousandths) fails it
  std::uint32_t reject_sigmas = 6U;        ///< the rejected fraction past p by this many standard errors ...
  std::uint32_t reject_floor_pct = 20U;    ///< ... and past this percentage fails it
};

/** True when every field of @p c is in its range. */
bool innovation_config_ok(const InnovationMonitorConfig& c) noexcept;

/** One block of measurements (also the open block being filled). */
struct InnovationBlock {
  std::uint32_t n;          ///< measurements that reached the gate
  std::uint32_t rejected;   ///< of them, rejected by it
  std::uint32_t nis_milli;  ///< sum of their clipped d2, in thousandths
};

struct InnovationMonitor {
  std::array<InnovationBlock, kMaxInnovationBlocks> ring;
  InnovationBlock open;
  std::uint32_t next;    ///< the ring's next place
  std::uint32_t filled;  ///< blocks in the ring since the last clear
};

/** The monitor is emulated state through and through (bsp::ControlLayout); next and filled are bounded at use. */
inline constexpr std::array kInnovationBlockFields{BSP_CONTROL_STATE(InnovationBlock, n),
                                                   BSP_CONTROL_STATE(InnovationBlock, rejected),
                                                   BSP_CONTROL_STATE(InnovationBlock, nis_milli)};
inline constexpr bsp::ControlLayout kInnovationBlockLayout{kInnovationBlockFields, sizeof(InnovationBlock),
                                                           alignof(InnovationBlock)};
inline constexpr std::array kInnovationMonitorFields{
    BSP_CONTROL_NESTED(InnovationMonitor, ring, kInnovationBlockLayout),
    BSP_CONTROL_NESTED(InnovationMonitor, open, kInnovationBlockLayout), BSP_CONTROL_STATE(InnovationMonitor, next),
    BSP_CONTROL_STATE(InnovationMonitor, filled)};
inline constexpr bsp::ControlLayout kInnovationMonitorLayout{kInnovationMonitorFields, sizeof(InnovationMonitor),
                                                             alignof(InnovationMonitor)};
static_assert(bsp::control_layout_ok(kInnovationMonitorLayout), "every member of InnovationMonitor");

enum class InnovationVerdict : std::uint8_t {
  kNone,          ///< no window closed, or the window is not full yet
  kConsistent,    ///< a full window that agrees with the covariance
  kNisHigh,       ///< the mean clipped d2 is too high
  kRejectedHigh,  ///< too many rejected (checked first: it is the plainer symptom)
};

/** What the window held when it was judged (for the event). */
struct InnovationWindow {
  std::uint32_t n = 0U;
  std::uint32_t rejected = 0U;
  std::uint32_t mean_nis_milli = 0U;  ///< the mean clipped d2, thousandths
};

/** Empties @p m (at start, and after a verdict the filter acts on). */
void innovation_clear(InnovationMonitor& m) noexcept;

/**
 * Adds a job's measurements: @p n reached the gate of gate @p gate_chi2, @p rejected of them
 * were rejected, @p nis_sum is the sum of their d2 clipped at the gate. When that closes a block
 * and the window is full, judges it (into @p win); charges @p work.
 */
InnovationVerdict innovation_add(InnovationMonitor& m, const InnovationMonitorConfig& c, double gate_chi2,
                                 std::uint32_t n, std::uint32_t rejected, double nis_sum, InnovationWindow& win,
                                 bsp::Work& work) noexcept;

/** The mean of a gate-clipped 2-dof chi-square (mu above) for gate @p g. */
double clipped_chi2_mean(double g) noexcept;
/** Its variance. */
double clipped_chi2_var(double g) noexcept;

}  // namespace fdir
