/**
 * @file vision_coord.hpp
 * @brief The vision coordinator: a frame's landmarks spread over 40 tiles
 *        by the fault-tolerant UDN, gathered before the frame's deadline, sent to the filter.
 *
 * Coordinator (one tile): selects the landmarks from the reference map at its
 * start (into a shared DDR table the vision tiles read) and relights a copy of
 * the coarse map layer from the orbital sun to the descent sun (DDR), which
 * the coarse stage searches; keeps the filter's
 * recent solutions (kChanNav); on each frame notice from the I/O tile
 * (kChanControl) takes the solution at the capture time as the prior, runs
 * the coarse stage when the horizontal position sigma is large (the
 * footprint warped and decimated here, the correlation surface dealt in bands
 * to the vision tiles, gathered and checked here; a band not back right in
 * time computed here: kCoarseBandRedone), plans
 * the frame's landmarks, and sends each vision tile a work unit of up to
 * kMaxLandmarksPerUnit of them (round robin, so each tile's share is spread
 * over the image). Results (kChanResult) are gathered until every unit has
 * answered or the frame's deadline passes: a late or lost unit is dropped,
 * never waited for, so a lost tile costs its share of landmarks, not the
 * frame. The batch (coarse match first) goes to the filter on kChanMatches.
 * A tile that misses kSuspectAfterMisses frames in a row gets no more units
 * (its landmarks go to the others) except one probe unit every
 * kProbeEveryFrames frames, which brings it back when it answers.
 *
 */
#pragma once

#include "bsp_tile64/api/camera_model.hpp"
#include "bsp_tile64/api/memory.hpp"
#include "bsp_tile64/api/port.hpp"
#include "fdir/liveness.hpp"
#include "fdir/result_trust.hpp"
#include "trn/vision/match_consistency.hpp"
#include "trn/vision/frame.hpp"
#include "trn/vision/landmarks.hpp"

#include <array>
#include <cstddef>
#include <cstdint>

namespace trn::tasks {

/** Most vision tiles one coordinator drives. */
inline constexpr std::uint32_t kMaxVisionTiles = 48;
/** Frames a tile may miss in a row before the coordinator stops giving it work. */
inline constexpr std::uint32_t kSuspectAfterMisses = 2;
/** A suspect tile is sent one unit every this many frames (it comes back by answering). */
inline constexpr std::uint32_t kProbeEveryFrames = 5;

/**
 * The coordinator's coarse stage. Its correlation runs in bands on the vision
 * tiles (spatially); when the coordinator correlates in one piece (too few
 * tiles, or too many bands to redo) it uses the exact transform, which gives
 * the spatial result bit for bit at about a fifth of its cycles (docs/VISION.md,
 * "Coarse search by an exact transform", "The coarse stage in bands").
 */
constexpr vision::CoarseFrameParams coord_coarse_params() noexcept {
  vision::CoarseFrameParams p{};
  p.coarse.method = vision::CorrelationMethod::kTransform;
  return p;
}

/**
 * The coordinator's landmark selection: a landmark per 32 px cell (192 m on
 * the 6 m layer), down to a faint corner strength, and a dense set of 26 px
 * cells (156 m) for frames with a tight prior, so that the frame still holds
 * 80 landmarks and more near the end of the descent, where it sees ~2 km of
 * ground (docs/VISION.md, "Landmarks by altitude").
 */
constexpr vision::SelectParams coord_select_params() noexcept {
  vision::SelectParams p{};
  p.cell_px = 32;
  p.cell_inset_px = 8;
  p.min_separation_px = 16;
  p.min_corner = 5.0F;
  p.min_stddev = 4.0F;
  p.dense_cell_px = 26;
  p.dense_cell_inset_px = 8;
  return p;
}

/** The coordinator's frame plan: faint landmarks (below the former selection's corner strength) only with a tight prior. */
constexpr vision::FramePlanParams coord_plan_params() noexcept {
  vision::FramePlanParams p{};
  p.strong_corner = 20.0F;
  p.weak_max_radius_px = 8;
  return p;
}

struct VisionCoordConfig {
  bsp::CameraModel camera{};
  double descent_sun_m[3] = {0.0, 0.0, 0.0};  ///< unit vector to the descent sun, map frame (mission knowledge)
  bsp::TileId filter_tile = bsp::kNoTile;
  std::array<bsp::TileId, kMaxVisionTiles> vision_tiles{};
  std::uint32_t vision_count = 0;
  vision::SelectParams select = coord_select_params();  ///< landmark selection on the fine map layer
  vision::FramePlanParams plan = coord_plan_params();
  vision::CoarseFrameParams coarse = coord_coarse_params();
  double coarse_above_sigma_m = 150.0; ///< coarse stage when the horizontal sigma exceeds this
  double deadline_s = 0.8;             ///< from the frame notice to the batch leaving for the filter (frames come every 1 s)
  /// The prior comes from the newest solution at least this much older than the capture: two
  /// filter jobs, so a voted solution (delivered two jobs after a simplex one, still before the
  /// frame's 20 ms readout ends) gives the same prior as a simplex one.
  double prior_lag_s = 0.02;
  double max_prior_age_s = 0.07;       ///< ... and that solution must be at most this old
  /// The tile-health supervisor: asked to reset a tile whose matches stay wrong, and to replace
  /// it by a spare when they are wrong again after the reset (kNoTile: nobody is asked).
  bsp::TileId health_tile = bsp::kNoTile;
  vision::ConsistencyParams consistency{};  ///< each frame's matches against the pose they fit
  /// A fine match's sigma grows, in quadrature, by this many image pixels per degree of its frame's
  /// prior attitude sigma (the norm of its three; weighed_sigma_px()): matched through warps made at
  /// a wrong attitude, a frame's matches share an error their own sigmas (the correlation's) do not
  /// carry, and the first fine batch after the coarse fix, applied as independent, made the filter's
  /// attitude overconfident (docs/FILTER.md, "Over 100 seeds"). 0: the correlation's sigma alone.
  double sigma_px_per_prior_deg = 0.4;
  fdir::ResultTrustConfig trust{};          ///< when a tile's failed matches make it suspect
  /** When a silent tile is left out of the frames, and how often it is tried again. */
  fdir::LivenessConfig liveness{kSuspectAfterMisses, kProbeEveryFrames};
  /** Boot tile of the vision supervisor (slot kSlotVisionSupervisor): sent a status after each frame, it sets the image rate (kNoTile: none). */
  bsp::TileId vision_supervisor_tile = bsp::kNoTile;
};

/**
 * The settings a frame uses, as the coordinator's tile holds them: copied from
 * its configuration (the image) into its RAM at the end of its set-up (carve
 * kCoordSettingsCarve), under a CRC-32C checked as each frame starts and again
 * before its batch leaves (trn/tasks/settings_copy.hpp). The tiles it deals to
 * and the supervisors' tiles are its wiring: they stay the image's, and its
 * lists of them are checked against it (check_lists()); the landmark selection
 * and the sun are used at set-up only.
 */
struct CoordSettings {
  bsp::CameraModel camera;
  vision::FramePlanParams plan;
  vision::CoarseFrameParams coarse;
  vision::ConsistencyParams consistency;
  double coarse_above_sigma_m;
  double deadline_s;
  double prior_lag_s;
  double max_prior_age_s;
  double sigma_px_per_prior_deg;
};

/** The settings of a configuration (what the copy in RAM is built from). */
CoordSettings coord_settings_of(const VisionCoordConfig& cfg) noexcept;

/** Name of the carve that holds the coordinator's settings in its tile's RAM (a plan's upset names it). */
inline constexpr const char* kCoordSettingsCarve = "coord_settings";

/**
 * The sigma the filter gets for a fine match of correlation sigma @p sigma_px
 * made from @p prior: sqrt(sigma_px^2 + (px_per_deg * |sigma_att| in degrees)^2)
 * (VisionCoordConfig::sigma_px_per_prior_deg). @p sigma_px itself when the
 * attitude sigmas are not finite or px_per_deg is not positive.
 */
double weighed_sigma_px(double sigma_px, const vision::PosePrior& prior, double px_per_deg) noexcept;

/** The part weighed_sigma_px() adds in quadrature: px_per_deg times |sigma_att| in degrees (0: nothing added). */
double prior_attitude_px(const vision::PosePrior& prior, double px_per_deg) noexcept;

struct VisionCoordStats {
  std::uint32_t landmarks_selected;
  std::uint32_t landmarks_from_ground;  ///< 1: the table is the ground's (landmark_product.hpp); 0: selected on board
  std::uint32_t ready_ms;               ///< when the set-up ended (table, relit coarse layer), emulated ms since boot
  std::uint32_t frames_seen;
  std::uint32_t frames_processed;     ///< planned and sent out
  std::uint32_t frames_skipped;       ///< no prior, bad notice, or busy with another frame
  /// Frames captured before the coordinator's set-up ended: not processed. With the ground's
  /// landmark table none (the set-up ends at ~0.1 s); selecting on board (~1 s), the frame at 1 s.
  std::uint32_t frames_before_ready;
  std::uint32_t coarse_runs;
  std::uint32_t coarse_accepted;
  std::uint32_t coarse_bands_sent;    ///< bands of the coarse surface sent to vision tiles
  std::uint32_t coarse_bands_redone;  ///< ... computed by the coordinator instead (kCoarseBandRedone)
  std::uint32_t coarse_one_piece;     ///< coarse correlations the coordinator ran whole (no tile to deal to, or too much missing)
  bsp::Cycles max_coarse_cycles;      ///< the coarse stage (warp, decimation, bands dealt and gathered, match), longest
  std::uint32_t units_sent;
  std::uint32_t units_answered;
  std::uint32_t units_lost;           ///< not answered by the deadline
  std::uint32_t units_send_failed;    ///< the network refused or had no route
  std::uint32_t results_late;         ///< answers to a frame already closed (units, and coarse bands after their stage)
  std::uint32_t results_unsealed;     ///< results that fail their seal or decode: dropped (kResultSealBroken)
  std::uint32_t planned_total;
  std::uint32_t matches_total;        ///< fine matches gathered (coarse not included)
  std::uint32_t last_frame_matches;
  std::uint32_t batch_send_failed;    ///< batch parts the filter tile did not take
  std::uint32_t status_send_failed;   ///< frame statuses the vision supervisor did not take
  std::uint32_t suspect_tiles;        ///< tiles currently given no work
  std::uint32_t frames_checked;       ///< frames whose matches were checked for consistency
  std::uint32_t matches_checked;
  std::uint32_t matches_failed;       ///< matches off the pose the frame's matches fit (left out of the batch)
  std::uint32_t matches_unused;       ///< matches of untrusted tiles, not sent to the filter
  std::uint32_t tiles_untrusted;      ///< tiles whose matches are not used now
  std::uint32_t resets_asked;         ///< tiles the supervisor was asked to reset for wrong matches
  std::uint32_t replacements_asked;
  std::uint32_t tiles_replaced;       ///< replacements the supervisor confirmed
  std::uint32_t frames_rate_skipped;  ///< frames left out by the vision supervisor's image rate
  std::uint32_t rate_div;             ///< the image rate now: every frame (1), every other (2)
  std::uint32_t healthy_tiles;        ///< vision tiles answering and trusted at the last frame
  std::uint32_t settings_rebuilt;     ///< frames whose settings in RAM had changed and were built again (coord_settings)
  double residual_scale_max_px;       ///< the largest robust residual scale of a checked frame
  double tile_bias_max_px;            ///< the largest mean residual of a trusted tile's window (the bias test)
  bsp::Cycles max_frame_cycles;       ///< notice to batch sent, longest
  bsp::Cycles last_frame_cycles;
};

/** The coordinator's counters are emulated state through and through (bsp::ControlLayout). */
inline constexpr std::array kVisionCoordStatsFields{
    BSP_CONTROL_STATE(VisionCoordStats, landmarks_selected),
    BSP_CONTROL_STATE(VisionCoordStats, landmarks_from_ground),
    BSP_CONTROL_STATE(VisionCoordStats, ready_ms),
    BSP_CONTROL_STATE(VisionCoordStats, frames_seen),
    BSP_CONTROL_STATE(VisionCoordStats, frames_processed),
    BSP_CONTROL_STATE(VisionCoordStats, frames_skipped),
    BSP_CONTROL_STATE(VisionCoordStats, frames_before_ready),
    BSP_CONTROL_STATE(VisionCoordStats, coarse_runs),
    BSP_CONTROL_STATE(VisionCoordStats, coarse_accepted),
    BSP_CONTROL_STATE(VisionCoordStats, coarse_bands_sent),
    BSP_CONTROL_STATE(VisionCoordStats, coarse_bands_redone),
    BSP_CONTROL_STATE(VisionCoordStats, coarse_one_piece),
    BSP_CONTROL_STATE(VisionCoordStats, max_coarse_cycles),
    BSP_CONTROL_STATE(VisionCoordStats, units_sent),
    BSP_CONTROL_STATE(VisionCoordStats, units_answered),
    BSP_CONTROL_STATE(VisionCoordStats, units_lost),
    BSP_CONTROL_STATE(VisionCoordStats, units_send_failed),
    BSP_CONTROL_STATE(VisionCoordStats, results_late),
    BSP_CONTROL_STATE(VisionCoordStats, results_unsealed),
    BSP_CONTROL_STATE(VisionCoordStats, planned_total),
    BSP_CONTROL_STATE(VisionCoordStats, matches_total),
    BSP_CONTROL_STATE(VisionCoordStats, last_frame_matches),
    BSP_CONTROL_STATE(VisionCoordStats, batch_send_failed),
    BSP_CONTROL_STATE(VisionCoordStats, status_send_failed),
    BSP_CONTROL_STATE(VisionCoordStats, suspect_tiles),
    BSP_CONTROL_STATE(VisionCoordStats, frames_checked),
    BSP_CONTROL_STATE(VisionCoordStats, matches_checked),
    BSP_CONTROL_STATE(VisionCoordStats, matches_failed),
    BSP_CONTROL_STATE(VisionCoordStats, matches_unused),
    BSP_CONTROL_STATE(VisionCoordStats, tiles_untrusted),
    BSP_CONTROL_STATE(VisionCoordStats, resets_asked),
    BSP_CONTROL_STATE(VisionCoordStats, replacements_asked),
    BSP_CONTROL_STATE(VisionCoordStats, tiles_replaced),
    BSP_CONTROL_STATE(VisionCoordStats, frames_rate_skipped),
    BSP_CONTROL_STATE(VisionCoordStats, rate_div),
    BSP_CONTROL_STATE(VisionCoordStats, healthy_tiles),
    BSP_CONTROL_STATE(VisionCoordStats, settings_rebuilt),
    BSP_CONTROL_STATE(VisionCoordStats, residual_scale_max_px),
    BSP_CONTROL_STATE(VisionCoordStats, tile_bias_max_px),
    BSP_CONTROL_STATE(VisionCoordStats, max_frame_cycles),
    BSP_CONTROL_STATE(VisionCoordStats, last_frame_cycles),
};
inline constexpr bsp::ControlLayout kVisionCoordStatsLayout{kVisionCoordStatsFields, sizeof(VisionCoordStats),
                                                           alignof(VisionCoordStats)};
static_assert(bsp::control_layout_ok(kVisionCoordStatsLayout), "every member of VisionCoordStats");
/** The coordinator's counters: a record in its tile's RAM, carved at task start (the host reads it by this name). */
inline constexpr bsp::RamRecord<VisionCoordStats> kVisionCoordStatsRecord{"coord_stats", &kVisionCoordStatsLayout};

/**
 * The coordinator reports through the flight event log: a tile isolated or
 * back (fdir/liveness.hpp: kWorkerSilent, kWorkerBack), a tile whose matches
 * are wrong or right again (fdir/result_trust.hpp: kResultsSuspect,
 * kResultsConsistent) and every frame's batch (kFrameDone: frame, matches,
 * units lost).
 *
 * Each frame's fine matches are checked against the pose they fit together
 * (vision/match_consistency.hpp) before the batch leaves; the failed and
 * checked matches of each tile go to its result trust. An untrusted tile's
 * matches are left out of the batch. A tile still wrong reset_after frames
 * after it became suspect is reported to the tile-health supervisor
 * (fdir::kMsgResultsBad, reset); wrong again after the reset, it is reported
 * for replacement, and the supervisor's answer (fdir::kMsgReplaced, on
 * kChanControl) puts the spare in its place in the coordinator's tile list.
 */

/** Coordinator entry (arg: const VisionCoordConfig*). */
void vision_coord_main(void* arg) noexcept;

/** Name of the coordinator's state carve, and its layout (bsp::ControlLayout: what an upset of it does). [host] */
inline constexpr const char* kVisionCoordCarve = "vision_coord";
const bsp::ControlLayout& vision_coord_state_layout() noexcept;

}  // namespace trn::tasks
