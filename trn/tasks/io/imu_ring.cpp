/**
 * @file imu_ring.cpp
 * @brief The DDR record of recent IMU samples (see imu_ring.hpp).
 */
#include "trn/tasks/io/imu_ring.hpp"

#include "trn/tasks/vision/vision_shared.hpp"

namespace trn::tasks {

ImuRing* imu_ring() noexcept {
  return reinterpret_cast<ImuRing*>(  // NOLINT(cppcoreguidelines-pro-type-reinterpret-cast): carve bytes
      ddr_carve_named("imu_ring", sizeof(ImuRing), alignof(ImuRing)));
}

void imu_ring_put(ImuRing& r, const bsp::ImuSample& s) noexcept {
  const std::uint32_t i = s.seq % kImuRingLen;
  r.entry[i] = s;
  r.valid[i] = 1U;
  if (s.seq + 1U > r.written) {
    r.written = s.seq + 1U;
  }
}

RingRead imu_ring_get(const ImuRing& r, std::uint32_t seq, bsp::ImuSample& out) noexcept {
  if (seq >= r.written) {
    return RingRead::kNotYet;
  }
  const std::uint32_t i = seq % kImuRingLen;
  if (r.valid[i] == 0U || r.entry[i].seq != seq) {
    return RingRead::kGone;
  }
  out = r.entry[i];
  return RingRead::kOk;
}

std::uint32_t imu_ring_oldest(const ImuRing& r) noexcept {
  return r.written > kImuRingLen ? r.written - kImuRingLen : 0U;
}

}  // namespace trn::tasks
