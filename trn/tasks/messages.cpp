/**
 * @file messages.cpp
 * @brief Decoders (and the packers they mirror) of the messages between TRN tiles: each
 *        reads received words into a typed message, or refuses them without writing.
 */
#include "trn/tasks/messages.hpp"

#include "udn/ft_link.hpp"

#include <cstdint>
#include <limits>

namespace trn::tasks {

namespace {

constexpr auto kMaxRow = static_cast<std::uint32_t>(std::numeric_limits<std::int32_t>::max());

}  // namespace

void pack_command(const Command& c, std::span<std::uint32_t, kCommandWords> w) noexcept {
  w[0] = kMsgCommand;
  w[1] = c.seq;
  w[2] = c.code;
  w[3] = c.arg;
  w[4] = c.after_imu;
}

bool unpack_command(std::span<const std::uint32_t> w, Command& out) noexcept {
  if (!udn::is_message(w, kMsgCommand, kCommandWords)) {
    return false;
  }
  out = Command{w[1], w[2], w[3], w[4]};
  return true;
}

void pack_sup_command(const SupCommand& c, std::span<std::uint32_t, kSupCommandWords> w) noexcept {
  w[0] = kMsgSupCommand;
  w[1] = c.code;
  w[2] = c.node;
}

bool unpack_sup_command(std::span<const std::uint32_t> w, SupCommand& out) noexcept {
  if (!udn::is_message(w, kMsgSupCommand, kSupCommandWords) || (w[1] != kCmdFilterTmr && w[1] != kCmdFilterSimplex)) {
    return false;
  }
  out = SupCommand{w[1], w[2]};
  return true;
}

void pack_filter_status(const FilterStatus& f, std::span<std::uint32_t, kFilterStatusWords> w) noexcept {
  w[0] = kMsgFilterStatus;
  w[1] = f.job;
  w[2] = f.mode;
  w[3] = f.voting;
  w[4] = f.no_majority;
  w[5] = f.skipped;
}

bool unpack_filter_status(std::span<const std::uint32_t> w, FilterStatus& out) noexcept {
  if (!udn::is_message(w, kMsgFilterStatus, kFilterStatusWords) || w[2] > kFilterModeStopping || w[3] > 7U) {
    return false;
  }
  out = FilterStatus{w[1], w[2], w[3], w[4], w[5]};
  return true;
}

void pack_vision_status(const VisionStatus& v, std::span<std::uint32_t, kVisionStatusWords> w) noexcept {
  w[0] = kMsgVisionStatus;
  w[1] = v.frame;
  w[2] = v.healthy;
  w[3] = v.listed;
  w[4] = v.lost;
  w[5] = v.rate_div;
}

bool unpack_vision_status(std::span<const std::uint32_t> w, VisionStatus& out) noexcept {
  if (!udn::is_message(w, kMsgVisionStatus, kVisionStatusWords) || w[2] > w[3] || (w[5] != 1U && w[5] != 2U)) {
    return false;
  }
  out = VisionStatus{w[1], w[2], w[3], w[4], w[5]};
  return true;
}

bool unpack_vision_rate(std::span<const std::uint32_t> w, std::uint32_t& div) noexcept {
  if (!udn::is_message(w, kMsgVisionRate, kVisionRateWords) || (w[1] != 1U && w[1] != 2U)) {
    return false;
  }
  div = w[1];
  return true;
}

void pack_relight(std::uint32_t tag, const RelightBand& b, std::span<std::uint32_t, kRelightWords> w) noexcept {
  w[0] = tag;
  w[1] = static_cast<std::uint32_t>(b.row0);
  w[2] = static_cast<std::uint32_t>(b.rows);
}

bool unpack_relight(std::uint32_t tag, std::span<const std::uint32_t> w, RelightBand& out) noexcept {
  if (!udn::is_message(w, tag, kRelightWords) || w[1] > kMaxRow || w[2] > kMaxRow) {
    return false;
  }
  out = RelightBand{static_cast<std::int32_t>(w[1]), static_cast<std::int32_t>(w[2])};
  return true;
}

void pack_coarse_band(const CoarseBand& b, std::span<std::uint32_t, kCoarseBandWords> w) noexcept {
  const auto u = [](std::int32_t v) { return static_cast<std::uint32_t>(v) & 0xFFFFU; };
  w[0] = kMsgCoarseBand;
  w[1] = b.frame;
  w[2] = static_cast<std::uint32_t>(b.row0);
  w[3] = static_cast<std::uint32_t>(b.rows);
  w[4] = u(b.window_w) | (u(b.window_h) << 16U);
  w[5] = u(b.tmpl_x) | (u(b.tmpl_y) << 16U);
  w[6] = u(b.tmpl_w) | (u(b.tmpl_h) << 16U);
  w[7] = b.slot;
}

bool unpack_coarse_band(std::span<const std::uint32_t> w, CoarseBand& out) noexcept {
  if (!udn::is_message(w, kMsgCoarseBand, kCoarseBandWords) || w[2] > kMaxRow || w[3] > kMaxRow) {
    return false;
  }
  const auto lo = [](std::uint32_t v) { return static_cast<std::int32_t>(v & 0xFFFFU); };
  const auto hi = [](std::uint32_t v) { return static_cast<std::int32_t>(v >> 16U); };
  CoarseBand b{w[1], static_cast<std::int32_t>(w[2]), static_cast<std::int32_t>(w[3]), lo(w[4]), hi(w[4]),
               lo(w[5]),  hi(w[5]), lo(w[6]), hi(w[6]), w[7]};
  if (b.window_w == 0 || b.window_h == 0 || b.tmpl_w == 0 || b.tmpl_h == 0) {
    return false;
  }
  out = b;
  return true;
}

void pack_coarse_band_done(const CoarseBandDone& d, std::span<std::uint32_t, kCoarseBandDoneWords> w) noexcept {
  w[0] = kMsgCoarseBandDone;
  w[1] = d.frame;
  w[2] = static_cast<std::uint32_t>(d.row0);
  w[3] = static_cast<std::uint32_t>(d.rows);
  w[4] = static_cast<std::uint32_t>(d.flat_windows);
  w[5] = static_cast<std::uint32_t>(d.digest & 0xFFFFFFFFULL);
  w[6] = static_cast<std::uint32_t>(d.digest >> 32U);
  w[7] = d.recomputes;
  w[8] = (d.status & 0xFFU) | ((d.check_failed ? 1U : 0U) << 8U) | ((d.first_check & 0xFFU) << 16U);
}

bool unpack_coarse_band_done(std::span<const std::uint32_t> w, CoarseBandDone& out) noexcept {
  if (!udn::is_message(w, kMsgCoarseBandDone, kCoarseBandDoneWords) || w[2] > kMaxRow || w[3] > kMaxRow ||
      w[4] > kMaxRow || (w[8] >> 24U) != 0U || ((w[8] >> 8U) & 0xFFU) > 1U) {
    return false;
  }
  out.frame = w[1];
  out.row0 = static_cast<std::int32_t>(w[2]);
  out.rows = static_cast<std::int32_t>(w[3]);
  out.flat_windows = static_cast<std::int32_t>(w[4]);
  out.digest = static_cast<std::uint64_t>(w[5]) | (static_cast<std::uint64_t>(w[6]) << 32U);
  out.recomputes = w[7];
  out.status = w[8] & 0xFFU;
  out.check_failed = ((w[8] >> 8U) & 1U) != 0U;
  out.first_check = (w[8] >> 16U) & 0xFFU;
  return true;
}

bool unpack_nav_msg(std::span<const std::uint32_t> w, filter::NavOutput& out) noexcept {
  if (!udn::is_message(w, kMsgNav, kNavWords)) {
    return false;
  }
  out = unpack_nav(w.first<kNavWords>());
  return true;
}

bool unpack_frame_msg(std::span<const std::uint32_t> w, FrameNotice& out) noexcept {
  if (!udn::is_message(w, kMsgFrame, kFrameNoticeWords) || (w[2] & 0xFFFFU) == 0U || (w[2] >> 16U) == 0U) {
    return false;
  }
  out = unpack_frame_notice(w.first<kFrameNoticeWords>());
  return true;
}

bool unpack_imu_msg(std::span<const std::uint32_t> w, bsp::ImuSample& out) noexcept {
  if (w.size() != kImuWords) {
    return false;
  }
  out = unpack_imu(w.first<kImuWords>());
  return true;
}

void pack_unit(const WorkUnit& u, std::span<std::uint32_t> w) noexcept {
  w[0] = kMsgUnit;
  w[1] = u.frame;
  w[2] = u.unit;
  w[3] = u.n;
  detail::put_f64(w, 4, u.t_s);
  w[6] = static_cast<std::uint32_t>(u.ddr_offset);
  w[7] = static_cast<std::uint32_t>(u.ddr_offset >> 32U);
  w[8] = (u.width_px & 0xFFFFU) | ((u.height_px & 0xFFFFU) << 16U);
  for (std::size_t i = 0; i < 3U; ++i) {
    detail::put_f64(w, 9U + 2U * i, u.p_m[i]);
  }
  for (std::size_t i = 0; i < 4U; ++i) {
    detail::put_f64(w, 15U + 2U * i, u.q_mb_wxyz[i]);
  }
  for (std::uint32_t i = 0; i < u.n && i < kMaxLandmarksPerUnit; ++i) {
    w[kUnitHeaderWords + i] = static_cast<std::uint32_t>(u.landmark[i]) | (static_cast<std::uint32_t>(u.radius_px[i]) << 16U);
  }
}

bool unpack_unit(std::span<const std::uint32_t> w, WorkUnit& out) noexcept {
  if (w.size() < kUnitHeaderWords || w[0] != kMsgUnit || w[3] > kMaxLandmarksPerUnit ||
      w.size() != kUnitHeaderWords + w[3]) {
    return false;
  }
  out.frame = w[1];
  out.unit = w[2];
  out.n = w[3];
  out.t_s = detail::get_f64(w, 4);
  out.ddr_offset = static_cast<std::uint64_t>(w[6]) | (static_cast<std::uint64_t>(w[7]) << 32U);
  out.width_px = w[8] & 0xFFFFU;
  out.height_px = w[8] >> 16U;
  for (std::size_t i = 0; i < 3U; ++i) {
    out.p_m[i] = detail::get_f64(w, 9U + 2U * i);
  }
  for (std::size_t i = 0; i < 4U; ++i) {
    out.q_mb_wxyz[i] = detail::get_f64(w, 15U + 2U * i);
  }
  for (std::uint32_t i = 0; i < kMaxLandmarksPerUnit; ++i) {
    const std::uint32_t x = i < out.n ? w[kUnitHeaderWords + i] : 0U;
    out.landmark[i] = static_cast<std::uint16_t>(x & 0xFFFFU);
    out.radius_px[i] = static_cast<std::uint16_t>(x >> 16U);
  }
  return true;
}

bool unpack_result(std::span<const std::uint32_t> w, UnitResult& out) noexcept {
  if (w.size() < kResultHeaderWords || w[0] != kMsgResult || w[4] > kMaxLandmarksPerUnit || w[4] > w[3] ||
      w.size() != kResultHeaderWords + w[4] * kMatchWords) {
    return false;
  }
  out = UnitResult{w[1], w[2], w[3], w[4]};
  return true;
}

bool unpack_match_part(std::span<const std::uint32_t> w, MatchPart& out) noexcept {
  if (w.size() < kMatchHeaderWords || w[0] != kMsgMatches) {
    return false;
  }
  const std::uint32_t part = w[2] & 0xFFFFU;
  const std::uint32_t parts = w[2] >> 16U;
  const std::uint32_t n = w[3];
  if (part >= parts || n == 0U || n > kMatchesPerPart || w.size() != kMatchHeaderWords + n * kMatchWords) {
    return false;
  }
  for (std::uint32_t i = 0; i < n; ++i) {
    // Word 21 of a packed match is its frame number.
    if (w[kMatchHeaderWords + i * kMatchWords + 21U] != w[1]) {
      return false;
    }
  }
  out = MatchPart{w[1], part, parts, n, w[4]};
  return true;
}

}  // namespace trn::tasks
