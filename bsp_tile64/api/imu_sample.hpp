/**
 * @file imu_sample.hpp
 * @brief The IMU device's output record (interface control: what flight code receives).
 *
 * Like an LN-200, the IMU delivers integrated increments over each sample
 * interval, in the body frame (frames.hpp): delta angle (rad) and delta
 * velocity (m/s, specific force integrated, gravity not included).
 */
#pragma once

#include <cstdint>

namespace bsp {

inline constexpr std::uint32_t kImuRateHz = 100;

struct ImuSample {
  std::uint32_t seq;         ///< sample counter, +1 per sample from 0
  std::uint32_t status;      ///< 0 valid; non-zero flags a device error
  double t_s;                ///< end of the integration interval, emulated seconds
  double dtheta_rad[3];      ///< body-frame delta angle over the interval
  double dv_mps[3];          ///< body-frame delta velocity (specific force) over the interval
};

}  // namespace bsp
