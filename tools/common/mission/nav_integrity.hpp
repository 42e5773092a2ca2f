/**
 * @file nav_integrity.hpp
 * @brief Navigation integrity of a run: how often, and how far, the position error after
 *        the first fix leaves the 3-sigma bound the filter reports with it.
 *
 * A ground measure: the host holds each navigation output's error (estimate
 * minus the world's truth) against the 3-sigma the same output carries, per
 * axis. The guidance trusts that covariance, so a confidently wrong position
 * (error far beyond its own sigma) is what this counts. add() allocates
 * nothing (the mission image calls it with the heap sealed).
 */
#pragma once

#include <array>
#include <cstdint>

namespace tools {

/**
 * The filter has a fix once the horizontal 3-sigma it reports first falls
 * below this (the coarse fix does it); every output from then on is held
 * against its own 3-sigma.
 */
inline constexpr double kFixSigma3M = 30.0;
/**
 * The filter has converged once the horizontal 3-sigma it reports first falls
 * to this; the maximum error after convergence is counted from then on. A
 * single frame fixes the position at its capture but not the velocity (the
 * entry's 2 m/s per axis), so between the first frame with matches and the
 * next one the error grows with the velocity's and so does the 3-sigma: the
 * filter claims metres only from its second frame (docs/FILTER.md, "Fix and
 * convergence").
 */
inline constexpr double kConvergedSigma3M = 3.0;

struct NavIntegrity {
  std::uint64_t outputs = 0U;                  ///< outputs held against their bound
  std::array<std::uint64_t, 3> beyond_3sigma{};  ///< per axis: |error| > 3 sigma
  std::array<std::uint64_t, 3> beyond_5sigma{};  ///< per axis: |error| > 5 sigma
  std::array<double, 3> worst_ratio{};         ///< per axis: the largest |error| / (3 sigma)
  double worst_at_s = -1.0;                    ///< when the largest ratio of any axis was seen
  std::uint64_t bad_sigma = 0U;                ///< outputs with a bound not finite and positive, or an error not finite (counted beyond)

  /**
   * One output at @p t_s: its per-axis error and reported 3-sigma. A bound
   * that is not finite and positive counts as exceeded on that axis (and in
   * bad_sigma), its ratio left out.
   */
  void add(double t_s, const std::array<double, 3>& error_m, const std::array<double, 3>& sigma3_m) noexcept;

  /** Fraction of the outputs beyond 3 sigma on @p axis (0 with no output). */
  [[nodiscard]] double fraction_beyond_3sigma(int axis) const noexcept;
};

}  // namespace tools
