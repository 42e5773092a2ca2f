/**
 * @file match.hpp
 * @brief One landmark match: what vision hands the navigation filter.
 *
 * w_c is the unit vector from the camera centre toward the landmark, in the
 * camera frame, from the matched (sub-pixel) image position; p_m is the
 * landmark's 3D position in the map frame, from the reference map and its
 * elevation. The paper's V_i (camera to landmark in map coordinates) is
 * p_m minus the camera position, which the filter forms from its own state.
 */
#pragma once

#include <cstdint>

namespace trn {

struct Match {
  double w_c[3];          ///< unit bearing in the camera frame
  double p_m[3];          ///< landmark position in the map frame, m
  double u_px;            ///< matched image column (sub-pixel)
  double v_px;            ///< matched image row (sub-pixel)
  double sigma_px;        ///< 1-sigma matching uncertainty, pixels
  float quality;          ///< NCC peak value, 0..1
  std::uint16_t landmark; ///< landmark index in the map table
  std::uint16_t tile;     ///< tile that produced the match
  std::uint32_t frame;    ///< frame sequence number
  double t_s;             ///< capture time of the frame (emulated s): the measurement time
};

/** Landmark index of a coarse-stage match (the image centre against the map, not a table entry). */
inline constexpr std::uint16_t kCoarseLandmark = 0xFFFFU;

/** Most matches one frame can carry. */
inline constexpr std::uint32_t kMaxMatchesPerFrame = 200;

}  // namespace trn
