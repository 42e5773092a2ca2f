/**
 * @file device_bus.hpp
 * @brief Board side of the devices: schedules IMU samples and camera frames at their exact cycles.
 *
 * attach_devices() is called by the image after board_init(): every 10 ms of
 * emulated time the IMU's sample for the interval just ended is pushed into the
 * I/O tile's IMU FIFO; at each capture time the camera renders the truth pose
 * into its DDR ring and, after the readout delay, the frame record is pushed
 * into the frame FIFO; a telecommand scheduled by the image (the uplink)
 * goes into the command FIFO at its time. Each delivery raises Irq::kDevice on the I/O tile.
 * Flight code reads them through device_io.hpp only.
 */
#pragma once

#include "bsp_tile64/emu/devices/camera.hpp"
#include "bsp_tile64/api/device_io.hpp"
#include "bsp_tile64/emu/devices/imu.hpp"

namespace bsp {

struct DeviceBusConfig {
  TileId io_tile = 0;
  ImuModel* imu = nullptr;        ///< nullptr: no IMU
  CameraDevice* camera = nullptr; ///< nullptr: no camera
  double first_frame_s = 1.0;     ///< first capture time, emulated seconds
  double frame_readout_s = 0.02;  ///< capture to frame-ready delay
  double last_time_s = 1.0e9;     ///< no deliveries after this time (end of the descent)
};

enum class DeviceBusError : std::uint8_t { kOk, kBadConfig, kScheduleFailed };

/**
 * Attaches the devices to the board (after board_init(); board_init() detaches
 * nothing by itself, so call this once per run). Resets the FIFOs and counters.
 */
DeviceBusError attach_devices(const DeviceBusConfig& cfg) noexcept;

/**
 * The uplink: a telecommand (@p code, @p arg; their meaning is the
 * application's) received at emulated time @p t_s goes into the I/O tile's
 * command FIFO and raises Irq::kDevice there. After attach_devices().
 */
DeviceBusError schedule_command(double t_s, std::uint32_t code, std::uint32_t arg) noexcept;

}  // namespace bsp
