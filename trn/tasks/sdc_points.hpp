/**
 * @file sdc_points.hpp
 * @brief The named points where the flight code publishes a result (bsp::publish_filter): where a
 *        silent data corruption (`sdc`) is injected, one table for the flight code and the plans.
 *
 * Each point is a channel of bsp::publish_filter, called on a result just
 * before it is used or sent, in place: a fault armed there flips one bit of
 * it, and what follows uses the corrupted value. Unarmed, a point costs one
 * scan of the (empty) armed list. A plan names a point (`point = "..."`); the
 * plan is refused when the tile or role it names never publishes there.
 */
#pragma once

#include "fdir/tile_health.hpp"
#include "trn/filter/covariance.hpp"
#include "trn/tasks/filter/filter_task.hpp"
#include "trn/tasks/tile_map.hpp"
#include "trn/vision/correlator.hpp"
#include "trn/vision/frame.hpp"

#include <array>
#include <cstdint>

namespace trn::tasks {

/** The filter's nominal state after each job's updates (filter::NominalState). */
inline constexpr std::uint32_t kFilterStateChannel = 2;
/** A vision tile's result message (its landmark matches) just before it is sent. */
inline constexpr std::uint32_t kVisionMatchesChannel = 3;
/** One part of the coordinator's match batch (header and matches) just before it is sent to the filter. */
inline constexpr std::uint32_t kCoordinatorBatchChannel = 4;

/** A vision tile's band of the coarse stage's surface in its DDR slot, after its checks, just before it is reported done. */
inline constexpr std::uint32_t kCoarseBandChannel = 11;

struct SdcPoint {
  const char* name;
  std::uint32_t channel;
  std::uint32_t roles;  ///< role_bit of each role whose tile publishes there
  const char* what;     ///< what is corrupted (for the plan's documentation and errors)
  bool shifts = false;  ///< the value starts with a double: a plan's `shift` (a lasting error) applies
};

inline constexpr std::array<SdcPoint, 11> kSdcPoints{{
    {"nav_output", kNavChannel, role_bit(Role::kFilter) | role_bit(Role::kFilterReplica),
     "the filter's solution as delivered (in TMR: the voted one on the filter's tile, each replica's own on a "
     "replica)"},
    {"filter_state", kFilterStateChannel, role_bit(Role::kFilter) | role_bit(Role::kFilterReplica),
     "the filter's nominal state after each job's updates (position, velocity, attitude, biases)"},
    {"vision_matches", kVisionMatchesChannel, role_bit(Role::kVision),
     "a vision tile's result message (its landmark matches) before it is sent"},
    {"coordinator_batch", kCoordinatorBatchChannel, role_bit(Role::kVisionCoordinator),
     "one part of the coordinator's match batch (header and matches) before it is sent"},
    {"filter_product", filter::kFilterProductChannel, role_bit(Role::kFilter) | role_bit(Role::kFilterReplica),
     "one of the covariance propagation's products (F P, then (F P) F^T; 225 doubles) before its checksums are "
     "checked"},
    {"filter_update_product", filter::kFilterUpdateProductChannel,
     role_bit(Role::kFilter) | role_bit(Role::kFilterReplica),
     "one of the Kalman update's products (P H^T, the gain K = (P H^T) S^-1, K (P H^T)^T; the next one computed: "
     "P H^T of the next measurement) before its row checksums are checked"},
    {"match_position", vision::kMatchPositionChannel, role_bit(Role::kVision),
     "a vision tile's matched image position (u, v in pixels, two doubles) before its bearing is formed; a shift "
     "moves u of every match the tile makes",
     true},
    {"self_test", fdir::kSelfTestChannel,
     role_bit(Role::kTrnSupervisor) | role_bit(Role::kVisionCoordinator) | role_bit(Role::kIo) |
         role_bit(Role::kFilter) | role_bit(Role::kVision) | role_bit(Role::kFilterReplica),
     "the tile's self-test digest"},
    {"correlation_surface", vision::kCorrelationSurfaceChannel,
     role_bit(Role::kVision) | role_bit(Role::kVisionCoordinator),
     "a correlation surface (floats, row-major) after it is computed, before its peak is searched: a landmark's "
     "on a vision tile; the coarse stage's bands where they are computed (vision tiles, the coordinator for a band "
     "it does itself) or its whole surface on the coordinator when it correlates in one piece"},
    {"correlation_dot", vision::kCorrelationDotChannel, role_bit(Role::kVision) | role_bit(Role::kVisionCoordinator),
     "one dot product of a correlation surface (a uint32 of template times window) before it is used: a "
     "landmark's on a vision tile, the coarse stage's where its bands are computed (or from the transform on the "
     "coordinator when it correlates in one piece)"},
    {"coarse_band", kCoarseBandChannel, role_bit(Role::kVision),
     "a vision tile's band of the coarse stage's surface (floats, row-major) in its DDR slot after its checks, "
     "before it is reported done: the coordinator's copy no longer matches the band's digest"},
}};

/** The point publishing on @p channel; nullptr when no flight code publishes there. */
constexpr const SdcPoint* sdc_point_of_channel(std::uint32_t channel) noexcept {
  for (const SdcPoint& p : kSdcPoints) {
    if (p.channel == channel) {
      return &p;
    }
  }
  return nullptr;
}

namespace detail {
constexpr bool sdc_channels_unique() noexcept {
  for (std::size_t i = 0; i < kSdcPoints.size(); ++i) {
    for (std::size_t j = i + 1U; j < kSdcPoints.size(); ++j) {
      if (kSdcPoints[i].channel == kSdcPoints[j].channel) {
        return false;
      }
    }
  }
  return true;
}
}  // namespace detail
static_assert(detail::sdc_channels_unique(), "one channel per point");

}  // namespace trn::tasks
