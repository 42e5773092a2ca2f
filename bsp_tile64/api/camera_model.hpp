/**
 * @file camera_model.hpp
 * @brief Camera intrinsics and mounting (interface control: configuration known to flight code).
 *
 * Pinhole model in the camera frame (frames.hpp): a point p_C = (x, y, z),
 * z > 0, projects to pixel u = cx + fx * x / z, v = cy + fy * y / z, with pixel
 * centres at integer coordinates (pixel (0,0) covers [-0.5, 0.5)^2).
 * Frames are 8-bit greyscale, row-major, width * height bytes.
 */
#pragma once

#include <cmath>
#include <cstdint>

namespace bsp {

struct CameraModel {
  std::uint32_t width_px = 1024;
  std::uint32_t height_px = 1024;
  double fx_px = 512.0;  ///< 90 deg horizontal FOV at 1024 px: fx = (w/2) / tan(45 deg)
  double fy_px = 512.0;
  double cx_px = 511.5;  ///< optical centre at the middle of the array
  double cy_px = 511.5;
  /** Mounting: rotation from camera to body frame, row-major 3x3 (identity: optical axis = body z, down). */
  double r_bc[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
};

/** Intrinsics of a camera of @p w x @p h pixels with horizontal field of view @p fov_deg. */
inline CameraModel make_camera(std::uint32_t w, std::uint32_t h, double fov_deg) noexcept {
  CameraModel c;
  c.width_px = w;
  c.height_px = h;
  constexpr double kPi = 3.14159265358979323846;
  c.fx_px = (0.5 * static_cast<double>(w)) / std::tan(0.5 * fov_deg * kPi / 180.0);
  c.fy_px = c.fx_px;
  c.cx_px = 0.5 * static_cast<double>(w) - 0.5;
  c.cy_px = 0.5 * static_cast<double>(h) - 0.5;
  return c;
}

}  // namespace bsp
