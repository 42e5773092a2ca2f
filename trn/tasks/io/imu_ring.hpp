/**
 * @file imu_ring.hpp
 * @brief The I/O tile's record of recent IMU samples in shared DDR, from which a restarted or
 *        moved filter replays what it missed.
 *
 * The I/O task puts every sample it reads into the ring (one writer); entry
 * `seq % kImuRingLen` holds sample `seq`, so a reader asking for a sample that
 * has been overwritten, or not written yet, is told so by the entry's own
 * sequence number. The ring is carved once in DDR by name; a restarted I/O
 * task takes it back, so the samples survive a reset of either tile.
 */
#pragma once

#include "bsp_tile64/api/imu_sample.hpp"

#include <array>
#include <cstdint>

namespace trn::tasks {

/** Samples the ring holds: 2.56 s at 100 Hz. */
inline constexpr std::uint32_t kImuRingLen = 256U;

struct ImuRing {
  std::uint32_t written = 0U;  ///< samples put so far (the next one's seq, when the device counts from 0)
  std::array<bsp::ImuSample, kImuRingLen> entry{};
  std::array<std::uint32_t, kImuRingLen> valid{};  ///< 1 once the entry holds a sample
};

/** The ring in DDR (carved on first use, taken back after); nullptr if DDR is full. [task] */
ImuRing* imu_ring() noexcept;

/** Records @p s (the I/O task, for every sample it reads). */
void imu_ring_put(ImuRing& r, const bsp::ImuSample& s) noexcept;

enum class RingRead : std::uint8_t {
  kOk,
  kNotYet,  ///< @p seq is newer than anything recorded
  kGone,    ///< @p seq was overwritten (or never recorded)
};

/** Sample @p seq into @p out. */
RingRead imu_ring_get(const ImuRing& r, std::uint32_t seq, bsp::ImuSample& out) noexcept;

/** Sequence number of the oldest sample still held (0 if none). */
std::uint32_t imu_ring_oldest(const ImuRing& r) noexcept;

}  // namespace trn::tasks
