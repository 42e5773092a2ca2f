/**
 * @file frame.hpp
 * @brief Per-frame vision: landmark prediction from the prior pose, the coarse stage on a
 *        frame, and one landmark's fine match turned into a trn::Match.
 *
 * The vision coordinator plans a frame (plan_frame), runs the coarse stage on
 * it when the position is uncertain (coarse_frame), and hands each vision tile
 * a few planned landmarks; a vision tile calls match_landmark() for each.
 * Both only read the frame (shared DDR), the reference-map product and the
 * camera configuration: never the world's truth.
 *
 * Common geometry: the image around a landmark's prediction is warped into the
 * map's geometry (north-up, the map layer's metres per pixel, on the plane at
 * the landmark's elevation) through the homography of the prior pose, and the
 * landmark's map template is correlated inside it. A peak offset (dx, dy) map
 * pixels from the predicted spot means the landmark is seen where the prior
 * pose projects the map point at that offset: that image position, turned
 * into a camera ray with the intrinsics, is the measurement w_c; the
 * landmark's 3D map position is p_m.
 *
 * Implementation notes (docs/VISION.md, "Per-frame vision"): the window's
 * pixels are lifted from the plane to the map's elevation (ortho.hpp), the
 * template is relit from the map's sun to the descent's when the MapView
 * knows both (relight_region()), and a second, small window around the
 * search peak refines it (frame_match.cpp). Frames and the homography:
 * pose_geometry.hpp.
 */
#pragma once

#include "bsp_tile64/api/camera_model.hpp"
#include "bsp_tile64/api/map_product.hpp"
#include "bsp_tile64/api/work.hpp"
#include "trn/match.hpp"
#include "trn/vision/coarse.hpp"
#include "trn/vision/fine.hpp"
#include "trn/vision/image.hpp"
#include "trn/vision/landmarks.hpp"
#include "trn/vision/pose_geometry.hpp"
#include "trn/vision/status.hpp"
#include "trn/vision/warp.hpp"

#include <cstdint>

namespace trn::vision {

/** The filter's solution at the image time, as vision needs it. */
struct PosePrior {
  double t_s = 0.0;                             ///< image capture time
  double p_m[3] = {0.0, 0.0, 0.0};              ///< body position in the map frame
  double q_mb[4] = {1.0, 0.0, 0.0, 0.0};        ///< body-to-map attitude, w x y z
  double sigma_p_m[3] = {0.0, 0.0, 0.0};        ///< 1-sigma position (map axes)
  double sigma_att_rad[3] = {0.0, 0.0, 0.0};    ///< 1-sigma attitude error
};

/** One layer of the reference-map product, as views. */
struct MapView {
  ConstImageU8 image{};
  const std::int16_t* elevation = nullptr;  ///< same layout as image (stride = width)
  double elevation_scale_m = 0.1;
  MapGeometry geo{};
  double sun_m[3] = {0.0, 0.0, 0.0};  ///< unit vector to the sun of the map images (map frame); zero if unknown
  /**
   * Unit vector to the sun at the descent (map frame), or zero. Mission
   * knowledge (landing time and ephemeris), set by the caller after
   * map_view(). With both suns known, match_landmark() relights each template
   * from the map's sun to this one (relight_region()).
   */
  double descent_sun_m[3] = {0.0, 0.0, 0.0};
};

/** Unit vector to a sun at @p azimuth_deg (clockwise from north) and @p elevation_deg, map frame (x east, y north, z up). */
void sun_direction(double azimuth_deg, double elevation_deg, double out[3]) noexcept;

/** Views of layer @p layer of @p product. @return kBadInput for a null product or layer out of range. */
Status map_view(const bsp::MapProductHeader* product, std::uint32_t layer, MapView& out) noexcept;

/**
 * Elevation of @p map at the fractional pixel (@p col, @p row), metres, bilinear,
 * clamped to the layer's edge. Pre: the view has an elevation layer.
 */
double map_elevation_m(const MapView& map, double col, double row) noexcept;

/** Extra map pixels added to every planned search radius (peak-edge margin and rounding). */
/**
 * Publication channel (bsp::publish_filter) of each match's image position
 * (u, v, two doubles) on the vision tile, before its bearing is formed from
 * it: where an `sdc` makes a tile's matches wrong (trn/tasks/sdc_points.hpp).
 */
inline constexpr std::uint32_t kMatchPositionChannel = 6;

inline constexpr std::int32_t kPlanRadiusMarginPx = 2;
/** Largest side of the image grid plan_frame() spreads landmarks over. */
inline constexpr std::int32_t kPlanMaxGrid = 16;
/**
 * 1-sigma of a fine match per axis in map pixels, before conversion to image
 * pixels by the local scale. On rendered frames (relit templates, terrain-lifted
 * windows, priors 30 m and 1 deg off) the robust per-axis spread of the errors
 * was 0.05-0.07 map px at 4000-2500 m and ~0.15 at 1200 m (docs/VISION.md).
 */
inline constexpr double kFineSigmaMapPx = 0.15;
/** Smallest fine-match sigma reported, image pixels. */
inline constexpr double kFineSigmaFloorPx = 0.1;

/** How a frame is planned. */
struct FramePlanParams {
  std::uint32_t max_landmarks = 150;  ///< most landmarks planned per frame
  std::int32_t border_px = 48;        ///< predictions this close to the image edge are skipped
  double sigma_k = 3.0;               ///< search radius covers this many sigma of the prior
  std::int32_t min_radius_px = 4;     ///< map pixels
  std::int32_t max_radius_px = kFineMaxSearchPx;
  bool footprint_cull = true;  ///< skip landmarks outside the frame's map footprint (same plan, less work)
  /// A landmark whose corner strength (Landmark::corner) is below this is planned only with a search
  /// radius of at most weak_max_radius_px: a faint patch matched over a wide window can lock onto a
  /// wrong peak that passes the quality checks, so faint landmarks wait for a tight prior. The
  /// table's dense set (LandmarkTable::first_tight on) waits for it too, whatever its strength.
  float strong_corner = 0.0F;
  std::int32_t weak_max_radius_px = kFineMaxSearchPx;
};

/** A landmark predicted inside the frame. */
struct PlannedLandmark {
  std::uint16_t landmark = 0;  ///< index in the landmark table
  float u_px = 0.0F;           ///< predicted image position
  float v_px = 0.0F;
  std::int32_t radius_px = 0;  ///< fine search radius, map pixels
};

/**
 * Predicts every landmark of @p table in the image at @p prior and keeps up to
 * p.max_landmarks of those inside the frame (less the border), spread evenly
 * over it, each with the search radius its prior uncertainty needs (position
 * and attitude sigmas projected at the landmark's range), clamped to
 * [min_radius_px, max_radius_px].
 * @param map the layer the landmarks were selected on (for the radius in its pixels)
 * @return kBadInput for a bad camera, a null output with cap > 0, or bad params.
 */
Status plan_frame(const LandmarkTable& table, const MapView& map, const bsp::CameraModel& cam,
                  const PosePrior& prior, const FramePlanParams& p, PlannedLandmark* out, std::uint32_t cap,
                  std::uint32_t& n, bsp::Work& work) noexcept;

/** Predictions of one plan's first pass, kept for its second (plan_frame with a scratch). DDR or static, ~150 KB. */
struct PlanScratch {
  PlannedLandmark kept[kMaxLandmarks];
  std::uint16_t cell[kMaxLandmarks];  ///< the plan grid's visit index of each kept prediction
};

/**
 * The same plan, bit for bit, with each landmark predicted once: the first
 * pass keeps its predictions in @p scratch and the second reads them back
 * instead of predicting the table again (about half the work when many
 * landmarks are in view). A null @p scratch plans as above.
 */
Status plan_frame(const LandmarkTable& table, const MapView& map, const bsp::CameraModel& cam,
                  const PosePrior& prior, const FramePlanParams& p, PlannedLandmark* out, std::uint32_t cap,
                  std::uint32_t& n, PlanScratch* scratch, bsp::Work& work) noexcept;

/** Buffers of one landmark match: the warped window and the correlator's. Static or carved, ~130 KiB. */
struct LandmarkWorkspace {
  FixedImage<std::uint8_t, kFineMaxWindowPx, kFineMaxWindowPx> window;
  FineWorkspace corr;
  FixedImage<std::uint8_t, kFineMaxTemplatePx, kFineMaxTemplatePx> tmpl;  ///< relit template
};

/** Diagnostics of one landmark match. */
struct LandmarkDiag {
  MatchResult fine{};          ///< the correlation outcome (reject reason when not accepted): the refinement's, or the search's when it stopped there
  std::int32_t outside_px = 0; ///< window pixels the frame did not cover (any: not correlated)
  MatchResult search{};        ///< the search pass (its surface view is overwritten by the refinement)
  double shift_px[2] = {0.0, 0.0};  ///< offset of the search peak from the prediction, map px (the refinement's shift)
  std::uint32_t recomputes = 0U;  ///< correlation surfaces computed again after a failed check, both passes
  bool check_failed = false;      ///< a pass was still wrong after its recomputations: not matched
  CorrelationCheck first_check = CorrelationCheck::kNone;  ///< what found the first wrong surface
};

/**
 * Fine match of landmark @p index of @p table in @p frame: warps the frame
 * around the prior's prediction into map geometry, correlates the landmark's
 * template, and on acceptance fills @p out (w_c, p_m, u/v, sigma_px, quality,
 * landmark; the caller sets tile, frame and t_s).
 * @param accepted set true when @p out holds a match
 * @return kBadInput for bad views/indices/radius; a rejected match is kOk with accepted false.
 */
Status match_landmark(ConstImageU8 frame, const bsp::CameraModel& cam, const PosePrior& prior, const MapView& map,
                      const LandmarkTable& table, std::uint16_t index, std::int32_t radius_px,
                      LandmarkWorkspace& ws, Match& out, bool& accepted, LandmarkDiag& diag,
                      bsp::Work& work) noexcept;

/** Checks, illumination and uncertainty model of a landmark match. */
struct LandmarkMatchParams {
  QualityParams quality = kFineQuality;     ///< correlation checks
  double sigma_map_px = kFineSigmaMapPx;    ///< 1-sigma of the peak, map pixels
  double sigma_floor_px = kFineSigmaFloorPx;  ///< smallest sigma_px reported, image pixels
  /** Relight templates to the map view's descent sun when both suns are known. */
  bool relight = true;
  /** Lift each window pixel to its map height (ortho.hpp) instead of the landmark's plane. */
  bool terrain = true;
  /** Samples per window pixel and axis (1..kMaxSubsamples); 0: the image pixels per map pixel, rounded. */
  std::int32_t subsamples = 0;
};

/**
 * Relights the region of @p map whose top-left pixel is (@p col0, @p row0) and
 * whose size is @p out's, from the map's sun (map.sun_m) to @p sun_m: each
 * pixel's DN times cos_i(sun_m) / cos_i(map sun), both from the Lambert normal
 * of the map's elevation (central differences; one-sided at the layer's edge),
 * the map-sun cosine floored at 0.1 (a pixel in the map's shade carries no
 * albedo), rounded and clamped to 0..255. The renderer and the map product
 * shade the same way (Lambert, no cast shadows), so this removes most of the
 * illumination difference but the sub-pixel relief. Per landmark (21x21) it
 * costs ~10 k flops; a whole coarse layer (~1.9 M px) belongs at init.
 * @return kBadInput for a missing elevation or sun, or a region outside the map.
 */
Status relight_region(const MapView& map, std::int32_t col0, std::int32_t row0, const double sun_m[3], ImageU8 out,
                      bsp::Work& work) noexcept;

/** match_landmark() with explicit checks and uncertainty model (the form above uses the defaults). */
Status match_landmark(ConstImageU8 frame, const bsp::CameraModel& cam, const PosePrior& prior, const MapView& map,
                      const LandmarkTable& table, std::uint16_t index, std::int32_t radius_px,
                      const LandmarkMatchParams& mp, LandmarkWorkspace& ws, Match& out, bool& accepted,
                      LandmarkDiag& diag, bsp::Work& work) noexcept;

/** Coarse stage settings. */
struct CoarseFrameParams {
  CoarseParams coarse{};              ///< decimation, template side, checks
  std::int32_t footprint_px = 256;    ///< side of the image centre warped to map geometry, map px
  std::int32_t search_px = 1024;      ///< side of the map region searched, map px (centred on the prior)
  double sigma_coarse_px = 0.5;       ///< 1-sigma of an accepted coarse match, decimated (coarse-scale) pixels
  /**
   * Footprint warp: the homography exact every warp_grid_px footprint pixels and
   * interpolated in fixed point between (warp_homography_grid(), a power of two
   * in kGridWarpMinPx..kGridWarpMaxPx); 0: exact at every pixel (warp_homography()).
   * At 8 px the footprints of the 4000 m descent are within 0.004 px and 1 DN of
   * the exact warp (16 px: 0.013 px, 2 DN) for ~3.7 M of its ~96 M TILE64 cycles.
   */
  std::int32_t warp_grid_px = 8;
};

/** Buffers of the coarse stage (~3 MiB): DDR or static storage, one per coarse task. */
struct CoarseFrameWorkspace {
  FixedImage<std::uint8_t, 1024, 1024> footprint;  ///< image centre in map geometry
  CoarseWorkspace coarse;
};

/** Outcome of the coarse stage. */
struct CoarseFrameResult {
  bool accepted = false;
  double dp_m[2] = {0.0, 0.0};  ///< horizontal correction to the prior position (map x, y)
  double sigma_m = 0.0;         ///< 1-sigma of the correction
  Match match{};                ///< the image centre's ray against its map point (landmark kCoarseLandmark)
  CoarseResult coarse{};        ///< the correlation outcome
  double ground_z_m = 0.0;      ///< height of the plane the footprint was warped onto (map elevation near the prior)
  std::int32_t outside_px = 0;  ///< footprint pixels the frame did not cover (any: not searched, not accepted)
  Homography footprint_h{};     ///< footprint pixel to frame pixel, as warped (identity when no footprint was warped)
};

/**
 * Coarse stage on @p frame: warps the image centre into the geometry of
 * @p map (the coarse layer) at the prior pose, searches it over the map region
 * around the prior, and on acceptance gives the horizontal position correction
 * and a Match of the image centre (sigma_px from the coarse pixel size).
 * The map's own sun and the descent's differ: searching a copy of the coarse
 * layer relit to the descent sun (relight_region(), once at init) removes a
 * ~50-65 m bias the unrelit layer leaves (docs/VISION.md).
 * @return kBadInput for bad inputs; kTooLarge when a size exceeds the workspace.
 */
Status coarse_frame(ConstImageU8 frame, const bsp::CameraModel& cam, const PosePrior& prior, const MapView& map,
                    const CoarseFrameParams& p, CoarseFrameWorkspace& ws, CoarseFrameResult& out,
                    bsp::Work& work) noexcept;

/**
 * coarse_frame() around its correlation, for a surface computed in bands by
 * other tiles (correlate_band(), correlate_gathered()): coarse_frame_prepare()
 * warps and decimates, coarse_frame_finish() turns the correlation's outcome
 * into the result. prepare, the bands, gathered, finish give coarse_frame()'s
 * result bit for bit (tests/trn/vision_frame/rendered_test.cpp).
 */
struct CoarseFrameStage {
  bool search = false;       ///< the footprint was warped whole: correlate prep.tmpl over prep.window
  CoarsePrepared prep{};     ///< the decimated template and window (in the workspace)
  PoseGeometry pose{};       ///< the prior's camera
  double t_s = 0.0;          ///< the prior's time
  std::int32_t search_col = 0;  ///< map column of search-region pixel (0, 0)
  std::int32_t search_row = 0;
};

/**
 * The coarse stage up to its correlation; fills @p out's ground height,
 * footprint and coverage. stage.search is false when the footprint is not
 * searched (the frame does not cover it): @p out is then final (not accepted).
 * @return as coarse_frame().
 */
Status coarse_frame_prepare(ConstImageU8 frame, const bsp::CameraModel& cam, const PosePrior& prior,
                            const MapView& map, const CoarseFrameParams& p, CoarseFrameWorkspace& ws,
                            CoarseFrameStage& stage, CoarseFrameResult& out, bsp::Work& work) noexcept;

/** The coarse stage after its correlation: @p m (of stage.prep) as the position correction and Match in @p out. */
void coarse_frame_finish(const bsp::CameraModel& cam, const MapView& map, const CoarseFrameParams& p,
                         const CoarseFrameStage& stage, const MatchResult& m, CoarseFrameResult& out,
                         bsp::Work& work) noexcept;

}  // namespace trn::vision
