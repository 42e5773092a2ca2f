/**
 * @file frames.hpp
 * @brief Reference frames and planet constants shared by the world, the devices and flight code.
 *
 * Map frame M: a local-level frame fixed to the ground, origin on the datum
 * (height 0) at the centre of the terrain, x east, y north, z up, metres.
 * The planet is modelled flat and non-rotating over the descent area (a few
 * tens of km), with gravity along -z whose magnitude falls with height:
 * g(h) = GM / (R + h)^2. Both truth and filter use this model, so it is
 * consistent by construction; planet rotation (Coriolis ~1e-2 m/s^2) is ignored.
 *
 * Body frame B: x forward, y right, z down (FRD). The attitude q_MB rotates
 * body vectors into the map frame: v_M = q_MB * v_B.
 *
 * Camera frame C: z along the optical axis, x along image columns (u grows),
 * y along image rows (v grows). Its mounting on the body is configuration
 * known to flight code (see camera_model.hpp).
 */
#pragma once

namespace bsp::frames {

/** Mars gravitational parameter, m^3/s^2. */
inline constexpr double kGmMars = 4.282837e13;
/** Mars mean radius, m. */
inline constexpr double kRadiusMars = 3389500.0;

/** Gravity magnitude at height @p h_m above the datum, m/s^2 (~3.71 at the datum). */
constexpr double gravity_mps2(double h_m) noexcept {
  const double r = kRadiusMars + h_m;
  return kGmMars / (r * r);
}

}  // namespace bsp::frames
