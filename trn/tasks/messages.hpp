/**
 * @file messages.hpp
 * @brief UDN tags and word layouts of the messages between TRN tiles.
 *
 * Doubles travel as their IEEE-754 bits, low word first, so a message is
 * reproduced bit for bit on the receiving tile.
 */
#pragma once

#include "bsp_tile64/devices/imu_sample.hpp"

#include <bit>
#include <cstdint>
#include <span>

namespace trn::tasks {

/** UDN tags of TRN traffic (the hardware tag word selects the receive queue). */
inline constexpr std::uint32_t kTagImu = 0x54490001U;  ///< I/O tile -> filter: one ImuSample

/** Demux queue the filter tile binds kTagImu to. */
inline constexpr std::uint32_t kImuQueue = 0;

inline constexpr std::uint32_t kImuWords = 16;

namespace detail {
inline void put_f64(std::span<std::uint32_t> w, std::size_t at, double v) noexcept {
  const auto bits = std::bit_cast<std::uint64_t>(v);
  w[at] = static_cast<std::uint32_t>(bits);
  w[at + 1U] = static_cast<std::uint32_t>(bits >> 32U);
}
inline double get_f64(std::span<const std::uint32_t> w, std::size_t at) noexcept {
  return std::bit_cast<double>(static_cast<std::uint64_t>(w[at]) | (static_cast<std::uint64_t>(w[at + 1U]) << 32U));
}
}  // namespace detail

/** Packs @p s into exactly kImuWords words. */
inline void pack_imu(const bsp::ImuSample& s, std::span<std::uint32_t, kImuWords> w) noexcept {
  w[0] = s.seq;
  w[1] = s.status;
  detail::put_f64(w, 2, s.t_s);
  for (std::size_t i = 0; i < 3U; ++i) {
    detail::put_f64(w, 4U + 2U * i, s.dtheta_rad[i]);
    detail::put_f64(w, 10U + 2U * i, s.dv_mps[i]);
  }
}

/** Unpacks what pack_imu() wrote. */
inline bsp::ImuSample unpack_imu(std::span<const std::uint32_t, kImuWords> w) noexcept {
  bsp::ImuSample s{};
  s.seq = w[0];
  s.status = w[1];
  s.t_s = detail::get_f64(w, 2);
  for (std::size_t i = 0; i < 3U; ++i) {
    s.dtheta_rad[i] = detail::get_f64(w, 4U + 2U * i);
    s.dv_mps[i] = detail::get_f64(w, 10U + 2U * i);
  }
  return s;
}

}  // namespace trn::tasks
