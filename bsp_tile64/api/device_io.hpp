/**
 * @file device_io.hpp
 * @brief What flight code sees of the devices: the I/O tile's IMU, camera and telecommand FIFOs.
 *
 * Interface control, like a driver's register map: the devices deliver into
 * bounded FIFOs on the I/O tile and raise Irq::kDevice there; the I/O tile's
 * driver reads them with these calls. Nothing here exposes the world's truth.
 * A FIFO that is full drops the newest record and counts it, as a device does.
 *
 * Cross-strapping: the devices may be wired to two tiles, a prime and a
 * backup, each with its own FIFOs, through a select (the model of a
 * cross-strap switch). They deliver to the selected attachment only; the
 * prime is selected at attach. A driver takes the devices over by setting
 * the select to its own tile (devices_select); what waited in the other
 * attachment's FIFOs is lost with it, and counted.
 */
#pragma once

#include "bsp_tile64/api/imu_sample.hpp"
#include "bsp_tile64/api/port.hpp"

#include <cstdint>

namespace bsp {

/** A captured frame as the camera driver sees it. */
struct FrameRecord {
  const std::uint8_t* pixels;  ///< in shared DDR; valid until the frame ring comes round
  std::uint32_t seq;           ///< capture counter from 0
  std::uint32_t width_px;
  std::uint32_t height_px;
  std::uint32_t status;        ///< 0 valid
  double t_s;                  ///< capture time, emulated seconds
};

/** A command from the ground (the uplink), as its receiver hands it over; codes are the application's. */
struct Telecommand {
  std::uint32_t seq;   ///< from 0, in the order received
  std::uint32_t code;
  std::uint32_t arg;
};

inline constexpr std::uint32_t kImuFifoDepth = 32;
inline constexpr std::uint32_t kFrameFifoDepth = 2;
inline constexpr std::uint32_t kCommandFifoDepth = 8;

/**
 * Reads pop from the calling tile's attachment (from the host, outside any
 * tile: the selected one's); a tile with no attachment reads nothing.
 */
/** Pops the oldest IMU sample. @return false when the FIFO is empty. [task|isr on the I/O tile] */
bool imu_read(ImuSample* out) noexcept;

/** Pops the oldest frame record. @return false when none is ready. [task|isr on the I/O tile] */
bool frame_read(FrameRecord* out) noexcept;

/** Pops the oldest telecommand. @return false when none is waiting. [task|isr on the I/O tile] */
bool command_read(Telecommand* out) noexcept;

/** Device counters, for health monitoring and reports. */
struct DeviceStats {
  std::uint32_t imu_delivered;
  std::uint32_t imu_dropped;     ///< FIFO full
  std::uint32_t frames_delivered;
  std::uint32_t frames_dropped;  ///< FIFO full
  std::uint32_t commands_delivered;
  std::uint32_t commands_dropped;  ///< FIFO full
  std::uint32_t selects;           ///< times the select moved the devices to the other attachment
  std::uint32_t imu_stranded;      ///< samples left in the attachment the select left (lost)
  std::uint32_t frames_stranded;   ///< frame records left there
  std::uint32_t commands_stranded; ///< telecommands left there
};
DeviceStats device_stats() noexcept;

/** The tile the devices deliver to: the selected attachment's (kNoTile before the bus is attached). */
TileId io_tile() noexcept;

enum class SelectResult : std::uint8_t {
  kSelected,  ///< the devices deliver to this tile (already did, or from now on)
  kNoBus,     ///< no devices attached: nothing to select
  kNotWired,  ///< this tile is neither attachment: the select is unchanged
};

/** What one select did. */
struct DeviceSelect {
  SelectResult result;
  TileId from;                      ///< the tile the devices delivered to before (kNoTile if unchanged)
  std::uint32_t imu_stranded;       ///< what was waiting in its FIFOs, lost with the switch-over
  std::uint32_t frames_stranded;
  std::uint32_t commands_stranded;
};

/**
 * The cross-strap select: the devices deliver to the calling tile's
 * attachment from now on. Selecting the attachment already selected changes
 * nothing. [task on an attached tile]
 */
DeviceSelect devices_select() noexcept;

}  // namespace bsp
