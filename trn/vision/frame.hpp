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
 */
#pragma once

#include "bsp_tile64/devices/camera_model.hpp"
#include "bsp_tile64/devices/map_product.hpp"
#include "bsp_tile64/work.hpp"
#include "trn/match.hpp"
#include "trn/vision/coarse.hpp"
#include "trn/vision/fine.hpp"
#include "trn/vision/image.hpp"
#include "trn/vision/landmarks.hpp"
#include "trn/vision/status.hpp"

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
};

/** Views of layer @p layer of @p product. @return kBadInput for a null product or layer out of range. */
Status map_view(const bsp::MapProductHeader* product, std::uint32_t layer, MapView& out) noexcept;

/** How a frame is planned. */
struct FramePlanParams {
  std::uint32_t max_landmarks = 150;  ///< most landmarks planned per frame
  std::int32_t border_px = 48;        ///< predictions this close to the image edge are skipped
  double sigma_k = 3.0;               ///< search radius covers this many sigma of the prior
  std::int32_t min_radius_px = 4;     ///< map pixels
  std::int32_t max_radius_px = kFineMaxSearchPx;
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

/** Buffers of one landmark match: the warped window and the correlator's. Static or carved, ~130 KiB. */
struct LandmarkWorkspace {
  FixedImage<std::uint8_t, kFineMaxWindowPx, kFineMaxWindowPx> window;
  FineWorkspace corr;
};

/** Diagnostics of one landmark match. */
struct LandmarkDiag {
  MatchResult fine{};          ///< the correlation outcome (reject reason when not accepted)
  std::int32_t outside_px = 0; ///< window pixels the frame did not cover
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

/** Coarse stage settings. */
struct CoarseFrameParams {
  CoarseParams coarse{};              ///< decimation, template side, checks
  std::int32_t footprint_px = 256;    ///< side of the image centre warped to map geometry, map px
  std::int32_t search_px = 1024;      ///< side of the map region searched, map px (centred on the prior)
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
};

/**
 * Coarse stage on @p frame: warps the image centre into the geometry of
 * @p map (the coarse layer) at the prior pose, searches it over the map region
 * around the prior, and on acceptance gives the horizontal position correction
 * and a Match of the image centre (sigma_px from the coarse pixel size).
 * @return kBadInput for bad inputs; kTooLarge when a size exceeds the workspace.
 */
Status coarse_frame(ConstImageU8 frame, const bsp::CameraModel& cam, const PosePrior& prior, const MapView& map,
                    const CoarseFrameParams& p, CoarseFrameWorkspace& ws, CoarseFrameResult& out,
                    bsp::Work& work) noexcept;

}  // namespace trn::vision
