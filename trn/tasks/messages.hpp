/**
 * @file messages.hpp
 * @brief UDN tags and word layouts of the messages between TRN tiles.
 *
 * Doubles travel as their IEEE-754 bits, low word first, so a message is
 * reproduced bit for bit on the receiving tile.
 */
#pragma once

#include "bsp_tile64/api/imu_sample.hpp"
#include "trn/filter/nav_output.hpp"
#include "trn/match.hpp"

#include <bit>
#include <cstdint>
#include <span>

namespace trn::tasks {

/**
 * Fault-tolerant UDN channels (udn/ft_link.hpp) of TRN traffic. A tile's
 * receive queue is per channel, so each kind of traffic a tile takes has its own.
 */
inline constexpr std::uint32_t kChanControl = 0U;  ///< I/O -> coordinator frame notices; coordinator -> vision work units
inline constexpr std::uint32_t kChanResult = 1U;   ///< vision -> coordinator unit results
inline constexpr std::uint32_t kChanNav = 2U;      ///< filter -> coordinator navigation solutions (pose priors)
inline constexpr std::uint32_t kChanMatches = 3U;  ///< coordinator -> filter match batches
/**
 * Role slots of the messaging role directory (udn::RoleDirectory): a sender
 * to one of these roles asks the directory where it runs now, the configured
 * tile being the answer until a role has a directory entry.
 */
inline constexpr std::uint32_t kSlotCoordinator = 0U;
inline constexpr std::uint32_t kSlotIo = 1U;
inline constexpr std::uint32_t kSlotFilter = 2U;
/** The filter's TMR replicas: slots kSlotReplica0 .. kSlotReplica0 + 2. */
inline constexpr std::uint32_t kSlotReplica0 = 3U;
/**
 * Not a directory slot: the boot slot (fdir::boot_slot) of a spare switched on
 * to take the place of a vision tile whose matches stayed wrong. Nobody sends
 * to it by slot; the coordinator learns the spare's tile from the supervisor.
 */
inline constexpr std::uint32_t kSlotVisionPool = 8U;
/** The filter and vision supervisors (trn/tasks/supervisors/supervisors.hpp). */
inline constexpr std::uint32_t kSlotFilterSupervisor = 6U;
inline constexpr std::uint32_t kSlotVisionSupervisor = 7U;
inline constexpr std::uint32_t kChanImu = 4U;      ///< I/O -> filter IMU samples, one per message

/** First word of every FT message: what it is. */
inline constexpr std::uint32_t kMsgFrame = 0x46524D31U;    ///< "FRM1" frame notice
inline constexpr std::uint32_t kMsgUnit = 0x554E5431U;     ///< "UNT1" vision work unit
inline constexpr std::uint32_t kMsgResult = 0x52534C31U;   ///< "RSL1" vision unit result
inline constexpr std::uint32_t kMsgNav = 0x4E415631U;      ///< "NAV1" navigation solution
inline constexpr std::uint32_t kMsgMatches = 0x4D544331U;  ///< "MTC1" part of a frame's match batch
inline constexpr std::uint32_t kMsgRelight = 0x524C5431U;  ///< "RLT1" relight a band of the coarse map: [1] row0 [2] rows
inline constexpr std::uint32_t kMsgRelightDone = 0x524C4431U;  ///< "RLD1" the band is done: [1] row0 [2] rows
inline constexpr std::uint32_t kRelightWords = 3;
/// "CBD1" compute a band of the coarse surface (CoarseBand): [1] frame [2] row0 [3] rows [4] window width | height << 16
/// [5] template x | y << 16 in the decimated image [6] template width | height << 16 [7] slot
inline constexpr std::uint32_t kMsgCoarseBand = 0x43424431U;
inline constexpr std::uint32_t kCoarseBandWords = 8;
/// "CBR1" the band is in the tile's slot (CoarseBandDone): [1] frame [2] row0 [3] rows [4] flat windows
/// [5..6] digest (low, high) [7] recomputes [8] status | check failed << 8 | first check << 16
inline constexpr std::uint32_t kMsgCoarseBandDone = 0x43425231U;
inline constexpr std::uint32_t kCoarseBandDoneWords = 9;
inline constexpr std::uint32_t kMsgReplicaOut = 0x52504F31U;    ///< "RPO1" a TMR replica's job output (filter_tmr.hpp)
inline constexpr std::uint32_t kMsgReplicaHello = 0x52504831U;  ///< "RPH1" a TMR replica waits for a seed
/**
 * Telecommand (I/O -> filter, kChanImu, in order with the samples), 5 words:
 * [0] kMsgCommand [1] sequence number [2] code [3] argument [4] seq of the
 * last IMU sample the I/O tile sent before it (kNoImuYet: none). The filter
 * takes it at the job that takes that sample, whenever it arrived.
 */
inline constexpr std::uint32_t kMsgCommand = 0x434D4431U;  ///< "CMD1"
inline constexpr std::uint32_t kCommandWords = 5U;
inline constexpr std::uint32_t kNoImuYet = 0xFFFFFFFFU;
/** Telecommand codes of the filter. */
inline constexpr std::uint32_t kCmdFilterTmr = 1U;      ///< run the filter as TMR from the next job
inline constexpr std::uint32_t kCmdFilterSimplex = 2U;  ///< back to one filter
/**
 * Policy telecommands: the I/O tile hands them to the TRN supervisor (not the
 * filter), which hands the policy down its tree (trn/tasks/supervisors/supervisors.hpp).
 */
inline constexpr std::uint32_t kCmdReliabilityNormal = 16U;
inline constexpr std::uint32_t kCmdReliabilityHigh = 17U;
inline constexpr std::uint32_t kCmdPowerFull = 18U;
inline constexpr std::uint32_t kCmdPowerSave = 19U;
/** First policy code: codes from here go to the TRN supervisor. */
inline constexpr std::uint32_t kCmdFirstPolicy = kCmdReliabilityNormal;

/**
 * A supervisor's command for the filter (kChanControl, to the I/O tile, which
 * puts it in the filter's IMU stream like a telecommand): [0] kMsgSupCommand
 * [1] code (kCmdFilterTmr, kCmdFilterSimplex) [2] the node that sent it.
 */
inline constexpr std::uint32_t kMsgSupCommand = 0x53434D31U;  ///< "SCM1"
inline constexpr std::uint32_t kSupCommandWords = 3U;
/** Sequence numbers of supervisor commands in the filter's stream (telecommands count from 1). */
inline constexpr std::uint32_t kSupCommandSeq = 0x8000'0000U;

/**
 * The filter front's status for its supervisor (kChanControl, every
 * kFilterStatusJobs jobs): [0] kMsgFilterStatus [1] job [2] mode (0 simplex, 1
 * starting TMR, 2 TMR, 3 stopping) [3] voting replicas (bit mask) [4] votes
 * without a majority so far [5] outputs skipped so far.
 */
inline constexpr std::uint32_t kMsgFilterStatus = 0x46535431U;  ///< "FST1"
inline constexpr std::uint32_t kFilterStatusWords = 6U;
inline constexpr std::uint32_t kFilterStatusJobs = 10U;
inline constexpr std::uint32_t kFilterModeSimplex = 0U;
inline constexpr std::uint32_t kFilterModeStarting = 1U;
inline constexpr std::uint32_t kFilterModeTmr = 2U;
inline constexpr std::uint32_t kFilterModeStopping = 3U;

/**
 * The coordinator's status for the vision supervisor (kChanControl, after
 * each frame): [0] kMsgVisionStatus [1] frame seq [2] healthy vision tiles
 * (in its list, answering, trusted) [3] tiles in its list [4] units lost in
 * the frame [5] its image-rate divisor.
 */
inline constexpr std::uint32_t kMsgVisionStatus = 0x56535431U;  ///< "VST1"
inline constexpr std::uint32_t kVisionStatusWords = 6U;
/** The vision supervisor's image rate for the coordinator (kChanControl): [0] kMsgVisionRate [1] divisor (1, 2). */
inline constexpr std::uint32_t kMsgVisionRate = 0x56525431U;  ///< "VRT1"
inline constexpr std::uint32_t kVisionRateWords = 2U;

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

/** Words of one packed Match. */
inline constexpr std::uint32_t kMatchWords = 22;

/** Packs @p m into exactly kMatchWords words (doubles bit-exact). */
inline void pack_match(const Match& m, std::span<std::uint32_t, kMatchWords> w) noexcept {
  for (std::size_t i = 0; i < 3U; ++i) {
    detail::put_f64(w, 2U * i, m.w_c[i]);
    detail::put_f64(w, 6U + 2U * i, m.p_m[i]);
  }
  detail::put_f64(w, 12, m.u_px);
  detail::put_f64(w, 14, m.v_px);
  detail::put_f64(w, 16, m.t_s);
  w[18] = std::bit_cast<std::uint32_t>(static_cast<float>(m.sigma_px));
  w[19] = std::bit_cast<std::uint32_t>(m.quality);
  w[20] = static_cast<std::uint32_t>(m.landmark) | (static_cast<std::uint32_t>(m.tile) << 16U);
  w[21] = m.frame;
}

/** Unpacks what pack_match() wrote (sigma_px travels as a float). */
inline Match unpack_match(std::span<const std::uint32_t, kMatchWords> w) noexcept {
  Match m{};
  for (std::size_t i = 0; i < 3U; ++i) {
    m.w_c[i] = detail::get_f64(w, 2U * i);
    m.p_m[i] = detail::get_f64(w, 6U + 2U * i);
  }
  m.u_px = detail::get_f64(w, 12);
  m.v_px = detail::get_f64(w, 14);
  m.t_s = detail::get_f64(w, 16);
  m.sigma_px = static_cast<double>(std::bit_cast<float>(w[18]));
  m.quality = std::bit_cast<float>(w[19]);
  m.landmark = static_cast<std::uint16_t>(w[20] & 0xFFFFU);
  m.tile = static_cast<std::uint16_t>(w[20] >> 16U);
  m.frame = w[21];
  return m;
}

/**
 * Match batch message (coordinator -> filter, kChanMatches):
 *   [0] kMsgMatches [1] frame seq [2] part index | (part count << 16) [3] matches in this part (n)
 *   [4] the filter job whose record takes the batch (0: the next one)
 *   then n x kMatchWords. A frame's batch is split into parts of at most kMatchesPerPart.
 */
inline constexpr std::uint32_t kMatchHeaderWords = 5;
/** The filter's period in kernel ticks: its job j is released at tick j x kFilterPeriodTicks. */
inline constexpr std::uint32_t kFilterPeriodTicks = 10U;
/**
 * Mission ticks per second: the kernel tick is 1 ms (the board's default),
 * and every period, wait and time in ticks of the tasks assumes it.
 */
inline constexpr std::uint32_t kTicksPerSecond = 1000U;
/**
 * Ticks an IMU sample of the I/O tile or a supervisor's message may wait for
 * the network before it is dropped (a sample is counted, a policy sent again
 * at the next refresh).
 */
inline constexpr std::uint32_t kControlSendTicks = 5U;
/**
 * The filter job whose record takes a frame's batch, counted from the job of
 * its capture: after the 20 ms readout, the frame's processing (fine frames
 * 40-85 ms; a frame with the coarse stage 174-228 ms on seeds 1-200, the
 * coarse stage about 130 ms of it) and the parts' crossing (8 a job). A
 * function of the frame, not of when the batch arrives, so which job takes a
 * match depends neither on the network's timing nor on a correction's
 * recomputation; a part later than that is taken when it comes. Every job of
 * lag is the velocity's uncertainty times 10 ms on the position a coarse
 * frame fixes (docs/FILTER.md, "Fix and convergence"): the coarse frame's
 * margin is about 80 ms over the slowest seen, no longer.
 */
inline constexpr std::uint32_t kFineApplyJobs = 15U;
inline constexpr std::uint32_t kCoarseApplyJobs = 35U;
inline constexpr std::uint32_t kMatchesPerPart = 5;
static_assert(kMatchHeaderWords + kMatchesPerPart * kMatchWords <= 124U, "a part fits one FT packet");

/**
 * Navigation solution message (filter -> coordinator, kChanNav), 48 words:
 *   [0] kMsgNav [1] flags [2..3] t_s [4..9] p [10..15] v [16..23] q (w x y z)
 *   [24..41] variance diagonal of dp, dv, dtheta (9 doubles, relative to the map)
 *   [42..47] position variance against the world (3 doubles: the map's tie variance added).
 */
inline constexpr std::uint32_t kNavWords = 48;

inline void pack_nav(const filter::NavOutput& o, std::span<std::uint32_t, kNavWords> w) noexcept {
  w[0] = kMsgNav;
  w[1] = o.flags;
  detail::put_f64(w, 2, o.t_s);
  for (std::size_t i = 0; i < 3U; ++i) {
    detail::put_f64(w, 4U + 2U * i, o.p_m[i]);
    detail::put_f64(w, 10U + 2U * i, o.v_mps[i]);
  }
  for (std::size_t i = 0; i < 4U; ++i) {
    detail::put_f64(w, 16U + 2U * i, o.q_mb_wxyz[i]);
  }
  for (std::size_t i = 0; i < 9U; ++i) {
    detail::put_f64(w, 24U + 2U * i, o.var_diag[i]);
  }
  for (std::size_t i = 0; i < 3U; ++i) {
    detail::put_f64(w, 42U + 2U * i, o.pos_var_world[i]);
  }
}

/** Unpacks what pack_nav() wrote (the covariance diagonal beyond attitude reads as zero). */
inline filter::NavOutput unpack_nav(std::span<const std::uint32_t, kNavWords> w) noexcept {
  filter::NavOutput o{};
  o.flags = w[1];
  o.t_s = detail::get_f64(w, 2);
  for (std::size_t i = 0; i < 3U; ++i) {
    o.p_m[i] = detail::get_f64(w, 4U + 2U * i);
    o.v_mps[i] = detail::get_f64(w, 10U + 2U * i);
  }
  for (std::size_t i = 0; i < 4U; ++i) {
    o.q_mb_wxyz[i] = detail::get_f64(w, 16U + 2U * i);
  }
  for (std::size_t i = 0; i < 9U; ++i) {
    o.var_diag[i] = detail::get_f64(w, 24U + 2U * i);
  }
  for (std::size_t i = 0; i < 3U; ++i) {
    o.pos_var_world[i] = detail::get_f64(w, 42U + 2U * i);
  }
  return o;
}

/**
 * Frame notice (I/O -> coordinator, kChanControl), 8 words:
 *   [0] kMsgFrame [1] seq [2] width | height << 16 [3] status [4..5] t_s [6..7] byte offset of the
 *   pixels from the start of the shared DDR region.
 */
inline constexpr std::uint32_t kFrameNoticeWords = 8;

struct FrameNotice {
  std::uint32_t seq = 0;
  std::uint32_t width_px = 0;
  std::uint32_t height_px = 0;
  std::uint32_t status = 0;
  double t_s = 0.0;
  std::uint64_t ddr_offset = 0;
};

inline void pack_frame_notice(const FrameNotice& f, std::span<std::uint32_t, kFrameNoticeWords> w) noexcept {
  w[0] = kMsgFrame;
  w[1] = f.seq;
  w[2] = (f.width_px & 0xFFFFU) | ((f.height_px & 0xFFFFU) << 16U);
  w[3] = f.status;
  detail::put_f64(w, 4, f.t_s);
  w[6] = static_cast<std::uint32_t>(f.ddr_offset);
  w[7] = static_cast<std::uint32_t>(f.ddr_offset >> 32U);
}

inline FrameNotice unpack_frame_notice(std::span<const std::uint32_t, kFrameNoticeWords> w) noexcept {
  FrameNotice f{};
  f.seq = w[1];
  f.width_px = w[2] & 0xFFFFU;
  f.height_px = w[2] >> 16U;
  f.status = w[3];
  f.t_s = detail::get_f64(w, 4);
  f.ddr_offset = static_cast<std::uint64_t>(w[6]) | (static_cast<std::uint64_t>(w[7]) << 32U);
  return f;
}

/** Most landmarks in one vision work unit (its result fits one FT packet). */
inline constexpr std::uint32_t kMaxLandmarksPerUnit = 5;

/**
 * Vision work unit (coordinator -> vision tile, kChanControl), kUnitHeaderWords + n words:
 *   [0] kMsgUnit [1] frame seq [2] unit id [3] n [4..5] t_s [6..7] frame DDR offset
 *   [8] width | height << 16 [9..14] prior p [15..22] prior q (w x y z)
 *   then n words: landmark index | search radius (map px) << 16.
 */
inline constexpr std::uint32_t kUnitHeaderWords = 23;

/**
 * Vision unit result (vision tile -> coordinator, kChanResult), kResultHeaderWords + m x kMatchWords:
 *   [0] kMsgResult [1] frame seq [2] unit id [3] landmarks tried [4] matches m, then the matches.
 */
inline constexpr std::uint32_t kResultHeaderWords = 5;
static_assert(kUnitHeaderWords + kMaxLandmarksPerUnit <= 124U, "a unit fits one FT packet");
static_assert(kResultHeaderWords + kMaxLandmarksPerUnit * kMatchWords <= 124U, "a result fits one FT packet");

/*
 * Decoders of received words (messages.cpp). Each returns false, leaving its
 * output as it was, unless the words are exactly that message (size, tag)
 * with every field in the range its layout above documents; the handlers of
 * the tasks read messages through them (tests/fuzz/flight_msg_fuzz.cpp checks
 * them against the packers).
 */

/** A telecommand for the filter: any code (the filter ignores one it does not know). */
struct Command {
  std::uint32_t seq = 0U;
  std::uint32_t code = 0U;
  std::uint32_t arg = 0U;
  std::uint32_t after_imu = kNoImuYet;  ///< seq of the IMU sample it follows
};
void pack_command(const Command& c, std::span<std::uint32_t, kCommandWords> w) noexcept;
[[nodiscard]] bool unpack_command(std::span<const std::uint32_t> w, Command& out) noexcept;

/** A supervisor's command for the filter: code kCmdFilterTmr or kCmdFilterSimplex. */
struct SupCommand {
  std::uint32_t code = kCmdFilterTmr;
  std::uint32_t node = 0U;
};
void pack_sup_command(const SupCommand& c, std::span<std::uint32_t, kSupCommandWords> w) noexcept;
[[nodiscard]] bool unpack_sup_command(std::span<const std::uint32_t> w, SupCommand& out) noexcept;

/** The filter front's status: mode kFilterModeSimplex .. kFilterModeStopping, voting a mask of the three replicas. */
struct FilterStatus {
  std::uint32_t job = 0U;
  std::uint32_t mode = kFilterModeSimplex;
  std::uint32_t voting = 0U;
  std::uint32_t no_majority = 0U;
  std::uint32_t skipped = 0U;
};
void pack_filter_status(const FilterStatus& f, std::span<std::uint32_t, kFilterStatusWords> w) noexcept;
[[nodiscard]] bool unpack_filter_status(std::span<const std::uint32_t> w, FilterStatus& out) noexcept;

/** The coordinator's status: healthy <= listed, rate divisor 1 or 2. */
struct VisionStatus {
  std::uint32_t frame = 0U;
  std::uint32_t healthy = 0U;
  std::uint32_t listed = 0U;
  std::uint32_t lost = 0U;
  std::uint32_t rate_div = 1U;
};
void pack_vision_status(const VisionStatus& v, std::span<std::uint32_t, kVisionStatusWords> w) noexcept;
[[nodiscard]] bool unpack_vision_status(std::span<const std::uint32_t> w, VisionStatus& out) noexcept;

/** The vision supervisor's image rate divisor: 1 or 2. */
[[nodiscard]] bool unpack_vision_rate(std::span<const std::uint32_t> w, std::uint32_t& div) noexcept;

/** A band of the coarse map to relight (kMsgRelight) or relit (kMsgRelightDone): rows from row0, both 0 .. INT32_MAX. */
struct RelightBand {
  std::int32_t row0 = 0;
  std::int32_t rows = 0;
};
void pack_relight(std::uint32_t tag, const RelightBand& b, std::span<std::uint32_t, kRelightWords> w) noexcept;
[[nodiscard]] bool unpack_relight(std::uint32_t tag, std::span<const std::uint32_t> w, RelightBand& out) noexcept;

/** A band of the coarse stage's surface for a vision tile: rows [row0, row0 + rows) of the decimated template over the window. */
struct CoarseBand {
  std::uint32_t frame = 0U;
  std::int32_t row0 = 0;
  std::int32_t rows = 0;
  std::int32_t window_w = 0;  ///< the decimated map region (the coarse workspace's map_small), 1 .. 65535
  std::int32_t window_h = 0;
  std::int32_t tmpl_x = 0;    ///< the template in the decimated image (image_small), 0 .. 65535
  std::int32_t tmpl_y = 0;
  std::int32_t tmpl_w = 0;    ///< 1 .. 65535
  std::int32_t tmpl_h = 0;
  std::uint32_t slot = 0U;    ///< the DDR band slot to compute it in (the receiver checks its range)
};
void pack_coarse_band(const CoarseBand& b, std::span<std::uint32_t, kCoarseBandWords> w) noexcept;
[[nodiscard]] bool unpack_coarse_band(std::span<const std::uint32_t> w, CoarseBand& out) noexcept;

/** A vision tile's answer to a CoarseBand: the band is in its slot, with what its checks found. */
struct CoarseBandDone {
  std::uint32_t frame = 0U;
  std::int32_t row0 = 0;
  std::int32_t rows = 0;
  std::int32_t flat_windows = 0;
  std::uint64_t digest = 0U;      ///< vision::surface_digest() of the band as computed and checked
  std::uint32_t recomputes = 0U;
  std::uint32_t status = 0U;      ///< vision::Status of the computation (0: kOk), 0 .. 255
  bool check_failed = false;      ///< still wrong after its recomputations: not to be used
  std::uint32_t first_check = 0U; ///< vision::CorrelationCheck, 0 .. 255
};
void pack_coarse_band_done(const CoarseBandDone& d, std::span<std::uint32_t, kCoarseBandDoneWords> w) noexcept;
[[nodiscard]] bool unpack_coarse_band_done(std::span<const std::uint32_t> w, CoarseBandDone& out) noexcept;

/** A navigation solution (any bits: a corrupted one is for the receiver to judge). */
[[nodiscard]] bool unpack_nav_msg(std::span<const std::uint32_t> w, filter::NavOutput& out) noexcept;

/** A frame notice: width and height 1 .. 65535. */
[[nodiscard]] bool unpack_frame_msg(std::span<const std::uint32_t> w, FrameNotice& out) noexcept;

/** An IMU sample (any bits: the filter refuses a bad one itself). */
[[nodiscard]] bool unpack_imu_msg(std::span<const std::uint32_t> w, bsp::ImuSample& out) noexcept;

/** A vision work unit: n 0 .. kMaxLandmarksPerUnit landmarks, each its index and search radius. */
struct WorkUnit {
  std::uint32_t frame = 0U;
  std::uint32_t unit = 0U;
  std::uint32_t n = 0U;
  double t_s = 0.0;
  std::uint64_t ddr_offset = 0U;
  std::uint32_t width_px = 0U;   ///< 0 .. 65535
  std::uint32_t height_px = 0U;  ///< 0 .. 65535
  double p_m[3] = {0.0, 0.0, 0.0};
  double q_mb_wxyz[4] = {1.0, 0.0, 0.0, 0.0};
  std::uint16_t landmark[kMaxLandmarksPerUnit] = {};
  std::uint16_t radius_px[kMaxLandmarksPerUnit] = {};
};
/** Writes kUnitHeaderWords + u.n words (pre: u.n <= kMaxLandmarksPerUnit, w that long). */
void pack_unit(const WorkUnit& u, std::span<std::uint32_t> w) noexcept;
[[nodiscard]] bool unpack_unit(std::span<const std::uint32_t> w, WorkUnit& out) noexcept;

/** A vision unit's result: m 0 .. kMaxLandmarksPerUnit matches, m <= tried; the matches are the words after the header. */
struct UnitResult {
  std::uint32_t frame = 0U;
  std::uint32_t unit = 0U;
  std::uint32_t tried = 0U;
  std::uint32_t m = 0U;
};
[[nodiscard]] bool unpack_result(std::span<const std::uint32_t> w, UnitResult& out) noexcept;

/**
 * A part of a match batch: part < parts, 1 .. kMatchesPerPart matches, every
 * one of the part's frame; the matches are the words after the header.
 */
struct MatchPart {
  std::uint32_t frame = 0U;
  std::uint32_t part = 0U;
  std::uint32_t parts = 1U;
  std::uint32_t n = 0U;
  std::uint32_t apply_job = 0U;  ///< 0: the next job
};
[[nodiscard]] bool unpack_match_part(std::span<const std::uint32_t> w, MatchPart& out) noexcept;

}  // namespace trn::tasks
