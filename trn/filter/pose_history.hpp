/**
 * @file pose_history.hpp
 * @brief Bounded history of the filter's pose, one entry per propagation, so that a landmark
 *        match measured at an earlier image time is formed against the pose at that time.
 *
 * The entries hold a reference trajectory: the nominal state moved by the same
 * IMU increments as the filter (the same velocity change and body rotation per
 * step) but never corrected by a landmark update. Relative motion read from it
 * is what the filter integrated, and corrections do not disturb it, so the pose
 * of the corrected nominal at an earlier time t follows from the current one:
 *
 *   p(t) = p_now - (w_now - w(t)) - (t_now - t) (v_now - wv_now)
 *   q(t) = q_now (x) q_rel^*,   q_rel = u(t)^* (x) u_now   (body rotation from t to now)
 *
 * with w, u the reference position and attitude (the entries) and wv_now the
 * reference velocity. A correction applied now moves every past pose with it
 * at no cost per entry; nothing in the history is rewritten by an update.
 *
 * Neglected by this back-propagation (the past increments are not re-resolved):
 * a correction of the biases changes the past increments by db (t_now - t), and
 * a correction of the attitude rotates the past velocity increments. Over a lag
 * of 1 s with LN-200 errors: accelerometer bias 2e-3 m/s^2 -> 1 mm, attitude
 * 2 mrad x 3.7 m/s^2 specific force -> 4 mm, gyro bias 5e-6 rad/s -> 5 urad;
 * all below 1 % of a 0.5 px bearing at 1 km (1 m).
 *
 * Storage: kHistoryLen entries of 64 bytes (16 KB), in the filter state (so the
 * TMR state block carries it and a restored replica matches the original).
 */
#pragma once

#include "bsp_tile64/api/work.hpp"
#include "trn/filter/linalg.hpp"
#include "trn/filter/nav_state.hpp"

#include <array>
#include <cstdint>

namespace trn::filter {

/** Entries kept: one per propagation, 2.56 s at 100 Hz (matches lag the image by up to ~1 s). */
inline constexpr std::uint32_t kHistoryLen = 256;

/** Two times closer than this are the same instant (IMU and camera clocks in emulated s). */
inline constexpr double kHistoryTimeTolS = 1e-6;

/** Pose of the reference trajectory at one propagation. */
struct PoseEntry {
  double t_s = 0.0;
  double p_m[3] = {0.0, 0.0, 0.0};
  double q_wxyz[4] = {1.0, 0.0, 0.0, 0.0};  ///< body to map
};

/** Ring of entries, oldest overwritten first, plus the reference velocity at the newest entry. */
struct PoseHistory {
  std::uint32_t newest = 0;  ///< ring index of the newest entry (its time is the filter's t_s)
  std::uint32_t count = 0;   ///< valid entries, 0..kHistoryLen
  double ref_v_mps[3] = {0.0, 0.0, 0.0};
  std::array<PoseEntry, kHistoryLen> e{};
};

/** The nominal pose at an earlier time, and how to map the current error state onto it. */
struct PastPose {
  Vec3 p_m = Vec3::Zero();
  Quat q_mb = Quat::Identity();
  Quat q_rel = Quat::Identity();  ///< body rotation from the past time to now: dtheta(t) = R(q_rel) dtheta_now
  double lag_s = 0.0;             ///< t_now - t, >= 0
};

enum class HistoryStatus : std::uint8_t {
  kOk,       ///< a past pose, interpolated between two entries
  kCurrent,  ///< the time is the newest entry's: use the nominal itself
  kTooOld,   ///< before the oldest entry
  kFuture,   ///< after the newest entry (the filter has not propagated that far)
  kGap,      ///< between two entries further apart than the allowed gap (IMU samples lost)
};

/** Empties @p h (entries zeroed one by one: no 16 KB temporary). */
void history_clear(PoseHistory& h) noexcept;

/** Restarts @p h with one entry: @p x's pose at @p t_s; the reference velocity is @p x's. */
void history_start(PoseHistory& h, double t_s, const NominalState& x) noexcept;

/**
 * Moves the reference over one propagation of @p dt_s (velocity change @p dv_mps in the
 * map frame, body rotation @p dq, both as the nominal took them) and records its pose at
 * @p t_s. A time that does not advance past the newest entry restarts the history from
 * @p x (matches before it are then refused as too old).
 */
void history_record(PoseHistory& h, double t_s, double dt_s, const Vec3& dv_mps, const Quat& dq,
                    const NominalState& x, bsp::Work& work) noexcept;

/**
 * The pose of the nominal @p x_now (at the newest entry's time) at time @p t_s,
 * interpolated linearly in position and normalized-linearly in attitude between
 * the two entries around it (10 ms apart: errors a h^2/8 and dw/dt h^2/8,
 * below 1e-4 m and 2e-6 rad for a descent under a parachute).
 * @p max_gap_s bounds the spacing of those two entries. @p out is written for kOk only.
 */
HistoryStatus history_pose(const PoseHistory& h, double t_s, const NominalState& x_now, double max_gap_s,
                           PastPose& out, bsp::Work& work) noexcept;

/** True if @p h is well formed for a filter at time @p t_s (counts, order, finite, unit quaternions). */
bool history_valid(const PoseHistory& h, double t_s, bool initialized) noexcept;

/** Entry of logical index @p i, 0 = oldest. Pre: i < h.count. */
const PoseEntry& history_entry(const PoseHistory& h, std::uint32_t i) noexcept;

// Counted by hand: a quaternion product is 16 mul + 12 add; a normalization
// 4 mul + 3 add, a square root and 4 divisions.
/** Flops and divisions of history_record: reference velocity, position, attitude, normalization. */
inline constexpr std::uint64_t kFlopsHistoryRecord = 3 + 10 + 28 + 7;
inline constexpr std::uint64_t kFdivsHistoryRecord = 5;
/**
 * Flops and divisions of history_pose for a past time: interpolation weight, position,
 * hemisphere test, attitude and its normalization, lag, back-propagation, q_rel, q(t).
 */
inline constexpr std::uint64_t kFlopsHistoryPose = 2 + 9 + 7 + 12 + 7 + 1 + 15 + 28 + 28;
inline constexpr std::uint64_t kFdivsHistoryPose = 1 + 5;

}  // namespace trn::filter
