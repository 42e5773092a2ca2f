/**
 * @file device_bus.hpp
 * @brief Board side of the devices: schedules IMU samples and camera frames at their exact cycles.
 *
 * attach_devices() is called by the image after board_init(): every 10 ms of
 * emulated time the IMU's sample for the interval just ended is pushed into the
 * I/O tile's IMU FIFO; at each capture time the camera renders the truth pose
 * into its DDR ring and, after the readout delay, the frame record is pushed
 * into the frame FIFO; a telecommand scheduled by the image (the uplink)
 * goes into the command FIFO at its time. Each delivery goes to the selected
 * attachment (the prime, or the backup once a driver there selected it) and
 * raises Irq::kDevice on its tile; an event scheduled before a select raises
 * it on the tile selected then, while its record goes to the new one.
 * Flight code reads them through device_io.hpp only.
 */
#pragma once

#include "bsp_tile64/emu/devices/camera.hpp"
#include "bsp_tile64/api/device_io.hpp"
#include "bsp_tile64/emu/devices/imu.hpp"

namespace bsp {

struct DeviceBusConfig {
  TileId io_tile = 0;             ///< the prime attachment, selected at attach
  TileId backup_tile = kNoTile;   ///< the cross-strap's second attachment (kNoTile: none)
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
