/**
 * @file nav_output.hpp
 * @brief The navigation solution published every period, and its byte form for bit-identical voting.
 *
 * Byte form, little-endian, no padding (offsets in bytes):
 *    0 u32 magic 0x564E5254 ("TRNV")   4 u32 version (2)
 *    8 u64 propagations               16 f64 t_s
 *   24 f64 p[3]  48 f64 v[3]  72 f64 q(w,x,y,z)  104 f64 covariance diagonal[15]
 *  224 u32 flags  228 u32 last_accepted  232 u32 last_rejected  236 u32 imu_gaps
 *  240 f64 position variance against the world[3]
 *  264 u32 CRC-32 of bytes [0, 264)
 */
#pragma once

#include "bsp_tile64/api/memory.hpp"
#include "trn/filter/filter_config.hpp"
#include "trn/filter/filter_state.hpp"

#include <array>
#include <cstddef>
#include <cstdint>

namespace trn::filter {

/** Validity flags of a solution. kNavValid is set only when every other flag is. */
enum NavFlag : std::uint32_t {
  kNavInitialized = 1U << 0U,
  kNavFinite = 1U << 1U,        ///< state and covariance finite
  kNavCovPositive = 1U << 2U,   ///< every covariance diagonal entry > 0
  kNavImuOk = 1U << 3U,         ///< the last IMU sample was integrated
  kNavFresh = 1U << 4U,         ///< the newest image with an accepted landmark is within stale_update_s
  kNavPosBounded = 1U << 5U,    ///< largest position sigma below max_sigma_pos_m
  kNavValid = 1U << 7U,
};

struct NavOutput {
  std::uint64_t propagations = 0;
  double t_s = 0.0;
  double p_m[3] = {0.0, 0.0, 0.0};
  double v_mps[3] = {0.0, 0.0, 0.0};
  double q_mb_wxyz[4] = {1.0, 0.0, 0.0, 0.0};
  double var_diag[15] = {};  ///< error-state variances [dp dv dtheta db_g db_a]: relative to the map
  /// Position variance against the world: var_diag[0..2] plus the map's tie variance
  /// (FilterConfig::map_tie_sigma_m). What guidance should trust; the map search uses var_diag.
  double pos_var_world[3] = {};
  std::uint32_t flags = 0;
  std::uint32_t last_accepted = 0;
  std::uint32_t last_rejected = 0;
  std::uint32_t imu_gaps = 0;
};

/** A solution kept in a task's state is emulated state through and through (bsp::ControlLayout). */
inline constexpr std::array kNavOutputFields{
    BSP_CONTROL_STATE(NavOutput, propagations), BSP_CONTROL_STATE(NavOutput, t_s),
    BSP_CONTROL_STATE(NavOutput, p_m),          BSP_CONTROL_STATE(NavOutput, v_mps),
    BSP_CONTROL_STATE(NavOutput, q_mb_wxyz),    BSP_CONTROL_STATE(NavOutput, var_diag),
    BSP_CONTROL_STATE(NavOutput, pos_var_world), BSP_CONTROL_STATE(NavOutput, flags),
    BSP_CONTROL_STATE(NavOutput, last_accepted), BSP_CONTROL_STATE(NavOutput, last_rejected),
    BSP_CONTROL_STATE(NavOutput, imu_gaps)};
inline constexpr bsp::ControlLayout kNavOutputLayout{kNavOutputFields, sizeof(NavOutput), alignof(NavOutput)};
static_assert(bsp::control_layout_ok(kNavOutputLayout), "every member of NavOutput");

inline constexpr std::uint32_t kNavMagic = 0x564E5254U;
inline constexpr std::uint32_t kNavVersion = 2U;
inline constexpr std::uint32_t kNavOutputBytes = 268U;
using NavOutputBytes = std::array<std::uint8_t, kNavOutputBytes>;

/** The solution of state @p s under configuration @p cfg (flags from its limits). */
NavOutput make_nav_output(const FilterState& s, const FilterConfig& cfg) noexcept;

/** Writes @p o in the byte form above; identical solutions give identical bytes. */
void write_nav_output(const NavOutput& o, NavOutputBytes& out) noexcept;

}  // namespace trn::filter
