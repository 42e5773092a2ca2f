/**
 * @file match_consistency.hpp
 * @brief Consistency of one frame's landmark matches with each other: the pose they fit together,
 *        and the matches that do not fit it (the per-match test of the paper's (w_i, V_i) set).
 *
 * Every match i says: landmark P_i (map frame) is seen at pixel (u_i, v_i).
 * At the true camera pose all of them project to where they were seen, up to
 * the matching noise. The coordinator does not know the true pose, only the
 * prior it planned the frame from (off by the filter's uncertainty, up to tens
 * of metres and milliradians), so each match is not compared to the prior
 * itself but to the pose all matches fit best: a 6-DOF weighted least squares
 * of the pixel residuals about the prior (Gauss-Newton, position and a small
 * rotation of the camera in the map frame), then refitted without the matches
 * past trim_k robust sigmas (a wrong tile's matches must not pull the fit).
 * A pose error of the prior is absorbed by the fit; a match that is wrong on
 * its own is not: it keeps its residual.
 *
 * The test. The residual scale s is estimated robustly from the fitted
 * matches (median residual norm / sqrt(2 ln 2): the per-axis sigma for
 * Gaussian residuals). A match fails when its residual norm exceeds
 * max(k_sigma s, floor_px). For Gaussian residuals the chance of a clean match
 * failing is exp(-k_sigma^2 / 2) (3.4e-4 at 4), less where the floor binds;
 * the measured rate over the mission seeds is in docs/FDIR.md. The floor keeps
 * a frame of very good matches (s of 0.1 px) from failing matches for their
 * terrain-relief and warp errors. Frames with fewer than min_matches matches
 * are not checked (a 6-DOF fit of a few matches absorbs a wrong one).
 *
 * Linear model. With d = P - c and p_C = R_MC^T d, a change dp of the camera
 * centre and a rotation dphi (map frame, R_MC <- Exp(dphi) R_MC) give
 *   dp_C = -R_MC^T dp + R_MC^T [d]x dphi,
 * and the pixel Jacobian is J_pi = [fx/z 0 -fx x/z^2; 0 fy/z -fy y/z^2].
 *
 * Flight code: fixed buffers in the caller's workspace, bounded loops.
 */
#pragma once

#include "bsp_tile64/api/camera_model.hpp"
#include "bsp_tile64/api/work.hpp"
#include "trn/match.hpp"
#include "trn/vision/frame.hpp"

#include <array>
#include <cstdint>

namespace trn::vision {

struct ConsistencyParams {
  std::uint32_t min_matches = 8U;  ///< frames with fewer matches are not checked
  std::uint32_t iterations = 3U;   ///< Gauss-Newton steps of each fit (>= 1)
  double trim_k = 3.0;             ///< the refit leaves out matches past max(trim_k s, floor_px)
  double k_sigma = 4.0;            ///< a match fails past max(k_sigma s, floor_px)
  double floor_px = 1.0;           ///< the smallest threshold, pixels
};

/** Most matches one check takes (a frame's fine matches). */
inline constexpr std::uint32_t kMaxConsistencyMatches = kMaxMatchesPerFrame;

struct ConsistencyWork {
  std::array<double, kMaxConsistencyMatches> norm{};    ///< residual norm per match at the fitted pose, px
  std::array<double, kMaxConsistencyMatches> du{};      ///< signed residual per match at the fitted pose, u (px)
  std::array<double, kMaxConsistencyMatches> dv{};      ///< ... v (px)
  std::array<double, kMaxConsistencyMatches> sorted{};  ///< scratch of the median
  std::array<bool, kMaxConsistencyMatches> in_fit{};    ///< the match takes part in the fit
};

struct ConsistencyResult {
  bool checked = false;       ///< enough matches and a fit: failed[] is meaningful
  std::uint32_t fitted = 0U;  ///< matches in the final fit
  std::uint32_t failed = 0U;  ///< matches past the threshold
  double scale_px = 0.0;      ///< robust per-axis sigma of the fitted residuals
  double threshold_px = 0.0;  ///< the residual norm a match failed past
};

/**
 * Checks @p n matches (no coarse match among them) against the pose they fit
 * together, starting from @p prior. Sets @p failed[i] for each match that
 * does not fit (all false when the frame is not checked). Charges @p work.
 * @return kBadInput for n over kMaxConsistencyMatches, a null pointer, or bad
 *         parameters; kOk otherwise (out.checked says whether it was checked).
 */
Status check_match_consistency(const bsp::CameraModel& cam, const PosePrior& prior, const Match* matches,
                               std::uint32_t n, const ConsistencyParams& params, bool* failed,
                               ConsistencyWork& ws, ConsistencyResult& out, bsp::Work& work) noexcept;

}  // namespace trn::vision
