/**
 * @file imu.hpp
 * @brief The IMU device model: 100 Hz delta-angle / delta-velocity increments from the truth, LN-200 errors.
 *
 * Each sample integrates the true body rate and specific force over its 10 ms
 * interval (Gauss-Legendre quadrature on sub-intervals: exact far below the
 * noise for the smooth descent), then applies, per axis:
 *   measured = (1 + scale_factor) * true + (turn_on_bias + in_run_bias) * dt + random walk,
 * with the in-run bias a first-order Gauss-Markov process (sigma, correlation
 * time) and the random walk white noise of density ARW (gyro) / VRW (accel).
 * Error draws come from StreamId::kSensor (index kImuStreamIndex), so the same
 * seed gives the same bits. Defaults are the LN-200 figures of FACTS.md.
 *
 * The board's driver calls sample(seq) for seq = 0, 1, 2, ... at the end of
 * each interval ((seq + 1) / 100 s) and queues the record to the I/O tile.
 */
#pragma once

#include "bsp_tile64/api/imu_sample.hpp"
#include "bsp_tile64/emu/rng.hpp"
#include "bsp_tile64/world/trajectory.hpp"

#include <cstdint>

namespace bsp {

/** LN-200 class error figures (1 sigma per axis), in the units of the data sheet. */
struct ImuErrorConfig {
  bool enabled = true;                   ///< false: a perfect IMU (tests)
  double gyro_bias_turn_on_dph = 1.0;    ///< deg/h, 0..1000
  double gyro_bias_in_run_dph = 0.35;    ///< deg/h, 0..1000
  double gyro_bias_tau_s = 100.0;        ///< s, 1..100000
  double gyro_arw_dpsh = 0.07;           ///< deg/sqrt(h), 0..100
  double gyro_scale_ppm = 100.0;         ///< ppm, 0..100000
  double accel_bias_turn_on_ug = 200.0;  ///< micro-g (9.80665 m/s^2), 0..100000
  double accel_bias_in_run_ug = 50.0;    ///< micro-g, 0..100000
  double accel_bias_tau_s = 60.0;        ///< s, 1..100000
  double accel_vrw_mpsph = 0.03;         ///< m/s/sqrt(h), 0..100
  double accel_scale_ppm = 300.0;        ///< ppm, 0..100000
};

/** Stream index of the IMU within StreamId::kSensor (the camera uses another). */
inline constexpr std::uint64_t kImuStreamIndex = 1;

/** ImuSample::status values. */
inline constexpr std::uint32_t kImuStatusOk = 0;
inline constexpr std::uint32_t kImuStatusSequence = 1;  ///< seq not the next expected: no data

enum class ImuError : std::uint8_t { kOk, kBadConfig, kNoTruth };

/** The error state actually drawn (exposed for tests and telemetry of the truth). */
struct ImuErrorState {
  double gyro_bias_rps[3];      ///< turn-on bias, rad/s
  double gyro_gm_rps[3];        ///< in-run Gauss-Markov bias now, rad/s
  double gyro_scale[3];         ///< scale factor error, dimensionless
  double accel_bias_mps2[3];
  double accel_gm_mps2[3];
  double accel_scale[3];
};

class ImuModel {
 public:
  /**
   * Draws the turn-on errors and resets the sequence to 0.
   * @param truth the trajectory sensed; must outlive the model.
   * @return kNoTruth if @p truth is null, kBadConfig if a figure is out of range.
   */
  ImuError init(const world::Trajectory* truth, const ImuErrorConfig& cfg, std::uint64_t seed) noexcept;

  /**
   * The sample for the interval ((seq) / 100 s, (seq + 1) / 100 s].
   * Pre: seq is the next expected (0 after init, then +1); otherwise the record
   * has status kImuStatusSequence, zero data, and the state does not advance.
   */
  ImuSample sample(std::uint32_t seq) noexcept;

  const ImuErrorState& errors() const noexcept { return err_; }

  /** The noise-free increments of the interval ending at (seq + 1) / 100 s (truth). */
  static void true_increments(const world::Trajectory& truth, std::uint32_t seq, double dtheta_rad[3],
                              double dv_mps[3]) noexcept;

 private:
  void apply_errors(ImuSample& s) noexcept;
  const world::Trajectory* truth_ = nullptr;
  ImuErrorConfig cfg_{};
  ImuErrorState err_{};
  Rng rng_{0, StreamId::kSensor, kImuStreamIndex};
  std::uint32_t next_seq_ = 0;
};

}  // namespace bsp
