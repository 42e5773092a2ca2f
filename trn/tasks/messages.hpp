/**
 * @file messages.hpp
 * @brief The messages between TRN tiles, each kind declared once: tag, channel, sender and
 *        receiver roles, fields by word with the range its decoder enforces.
 *
 * The encoders, decoders and the dispatch by tag come from these declarations
 * (fdir/message_kind.hpp); docs/ARCHITECTURE.md, "Message kinds", is the table
 * they write (make docs-messages). Doubles travel as their IEEE-754 bits, low
 * word first, so a message is reproduced bit for bit on the receiving tile.
 */
#pragma once

#include "bsp_tile64/api/imu_sample.hpp"
#include "fdir/message_kind.hpp"
#include "fdir/supervisor.hpp"
#include "fdir/tile_health.hpp"
#include "trn/filter/nav_output.hpp"
#include "trn/match.hpp"
#include "trn/tasks/roles.hpp"
#include "udn/endpoint.hpp"

#include <array>
#include <cstdint>
#include <limits>
#include <span>

namespace trn::tasks {

/**
 * Fault-tolerant UDN channels (udn/ft_link.hpp) of TRN traffic. A tile's
 * receive queue is per channel, so each kind of traffic a tile takes has its
 * own; which kinds travel on each is kMessageKinds (below), not these comments.
 */
inline constexpr std::uint32_t kChanControl = 0U;  ///< requests and notices: frames, units, bands, statuses, policies
inline constexpr std::uint32_t kChanResult = 1U;   ///< vision -> coordinator answers
inline constexpr std::uint32_t kChanNav = 2U;      ///< navigation solutions, and the replicas' outputs to the filter
inline constexpr std::uint32_t kChanMatches = 3U;  ///< coordinator -> filter match batches
inline constexpr std::uint32_t kChanImu = 4U;      ///< I/O -> filter IMU samples and telecommands, in order
/** The channels' names in the docs, by number. */
inline constexpr std::array<const char*, 5> kChannelNames{"control", "result", "nav", "matches", "imu"};
/** Word 0 of every tagged message: what it is (four ASCII letters). */
inline constexpr std::uint32_t kMsgFrame = 0x46524D31U;          ///< "FRM1"
inline constexpr std::uint32_t kMsgUnit = 0x554E5431U;           ///< "UNT1"
inline constexpr std::uint32_t kMsgResult = 0x52534C31U;         ///< "RSL1"
inline constexpr std::uint32_t kMsgNav = 0x4E415631U;            ///< "NAV1"
inline constexpr std::uint32_t kMsgMatches = 0x4D544331U;        ///< "MTC1"
inline constexpr std::uint32_t kMsgRelight = 0x524C5431U;        ///< "RLT1"
inline constexpr std::uint32_t kMsgRelightDone = 0x524C4431U;    ///< "RLD1"
inline constexpr std::uint32_t kMsgCoarseBand = 0x43424431U;     ///< "CBD1"
inline constexpr std::uint32_t kMsgCoarseBandDone = 0x43425231U; ///< "CBR1"
inline constexpr std::uint32_t kMsgReplicaOut = 0x52504F31U;     ///< "RPO1" (filter_tmr.hpp)
inline constexpr std::uint32_t kMsgReplicaHello = 0x52504831U;   ///< "RPH1"
inline constexpr std::uint32_t kMsgCommand = 0x434D4431U;        ///< "CMD1"
inline constexpr std::uint32_t kMsgSupCommand = 0x53434D31U;     ///< "SCM1"
inline constexpr std::uint32_t kMsgFilterStatus = 0x46535431U;   ///< "FST1"
inline constexpr std::uint32_t kMsgVisionStatus = 0x56535431U;   ///< "VST1"
inline constexpr std::uint32_t kMsgVisionRate = 0x56525431U;     ///< "VRT1"

/** A telecommand's after_imu when the I/O tile had sent no IMU sample yet. */
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
/** Sequence numbers of supervisor commands in the filter's stream (telecommands count from 1). */
inline constexpr std::uint32_t kSupCommandSeq = 0x8000'0000U;
/** Jobs between two statuses of the filter. */
inline constexpr std::uint32_t kFilterStatusJobs = 10U;
inline constexpr std::uint32_t kFilterModeSimplex = 0U;
inline constexpr std::uint32_t kFilterModeStarting = 1U;
inline constexpr std::uint32_t kFilterModeTmr = 2U;
inline constexpr std::uint32_t kFilterModeStopping = 3U;
/** Most landmarks in one vision work unit (its result fits one FT packet). */
inline constexpr std::uint32_t kMaxLandmarksPerUnit = 5;
/** Most matches in one part of a frame's match batch (a part fits one FT packet). */
inline constexpr std::uint32_t kMatchesPerPart = 5;
/** The filter's TMR replicas. */
inline constexpr std::uint32_t kReplicas = 3U;

// ---------------------------------------------------------------- the messages' fields

/** A frame notice: the image in shared DDR (width and height 1 .. 65535). */
struct FrameNotice {
  std::uint32_t seq = 0;
  std::uint32_t width_px = 0;
  std::uint32_t height_px = 0;
  std::uint32_t status = 0;
  double t_s = 0.0;
  std::uint64_t ddr_offset = 0;  ///< of the pixels from the start of the shared DDR region
};

/**
 * A telecommand for the filter: any code (the filter ignores one it does not
 * know). It travels in order with the IMU samples and is taken at the job that
 * takes the sample after_imu, whenever it arrived.
 */
struct Command {
  std::uint32_t seq = 0U;
  std::uint32_t code = 0U;
  std::uint32_t arg = 0U;
  std::uint32_t after_imu = kNoImuYet;  ///< seq of the IMU sample it follows
};

/**
 * A supervisor's command for the filter: to the I/O tile, which puts it in
 * the filter's IMU stream like a telecommand (code kCmdFilterTmr or kCmdFilterSimplex).
 */
struct SupCommand {
  std::uint32_t code = kCmdFilterTmr;
  std::uint32_t node = 0U;  ///< the supervisor node that sent it
};

/** The filter's status for its supervisor, every kFilterStatusJobs jobs. */
struct FilterStatus {
  std::uint32_t job = 0U;
  std::uint32_t mode = kFilterModeSimplex;  ///< kFilterModeSimplex .. kFilterModeStopping
  std::uint32_t voting = 0U;                ///< voting replicas, a mask of the three
  std::uint32_t no_majority = 0U;           ///< votes without a majority so far
  std::uint32_t skipped = 0U;               ///< outputs skipped so far
};

/** The coordinator's status for the vision supervisor, after each frame. */
struct VisionStatus {
  std::uint32_t frame = 0U;
  std::uint32_t healthy = 0U;  ///< vision tiles in its list, answering, trusted (<= listed)
  std::uint32_t listed = 0U;
  std::uint32_t lost = 0U;     ///< units lost in the frame
  std::uint32_t rate_div = 1U; ///< its image-rate divisor, 1 or 2
};

/** The vision supervisor's image rate for the coordinator. */
struct VisionRate {
  std::uint32_t div = 1U;  ///< 1 or 2
};

/** A band of the coarse map to relight or relit: rows from row0, both 0 .. INT32_MAX. */
struct RelightBand {
  std::int32_t row0 = 0;
  std::int32_t rows = 0;
};

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

/** A vision work unit: n landmarks, each its index and search radius (map px), and the frame's prior. */
struct WorkUnit {
  std::uint32_t frame = 0U;
  std::uint32_t unit = 0U;
  std::uint32_t n = 0U;  ///< 0 .. kMaxLandmarksPerUnit
  double t_s = 0.0;
  std::uint64_t ddr_offset = 0U;
  std::uint32_t width_px = 0U;   ///< 0 .. 65535
  std::uint32_t height_px = 0U;  ///< 0 .. 65535
  double p_m[3] = {0.0, 0.0, 0.0};
  double q_mb_wxyz[4] = {1.0, 0.0, 0.0, 0.0};
  std::uint16_t landmark[kMaxLandmarksPerUnit] = {};
  std::uint16_t radius_px[kMaxLandmarksPerUnit] = {};
};

/** A vision unit's result: m matches (the words after the header), m <= tried. */
struct UnitResult {
  std::uint32_t frame = 0U;
  std::uint32_t unit = 0U;
  std::uint32_t tried = 0U;
  std::uint32_t m = 0U;
  std::uint32_t seal = 0U;  ///< CRC-32C of the whole result, taken as the tile computed it (seal_result)
};

/**
 * A part of a frame's match batch (split into parts of at most
 * kMatchesPerPart): part < parts, 1 .. kMatchesPerPart matches (the words
 * after the header), every one of the part's frame.
 */
struct MatchPart {
  std::uint32_t frame = 0U;
  std::uint32_t part = 0U;
  std::uint32_t parts = 1U;
  std::uint32_t n = 0U;
  std::uint32_t apply_job = 0U;  ///< the filter job whose record takes the batch (0: the next one)
  std::uint32_t seal = 0U;       ///< CRC-32C of the whole part, taken as the coordinator made it (seal_result)
};

/** A TMR replica waits for a seed (filter_tmr.hpp). */
struct ReplicaHello {
  std::uint32_t replica = 0U;  ///< below kReplicas
  std::uint32_t epoch = 0U;    ///< the epoch it saw
  std::uint32_t refused = 0U;  ///< 1: it dropped its state because its own checks refused it (filter_state_bad, filter_settings_bad)
};

/** A replica's output header; its solution follows as a kNavMsg (any bits: voted). */
struct ReplicaOut {
  std::uint32_t replica = 0U;  ///< below kReplicas
  std::uint32_t job = 0U;
  std::uint32_t digest = 0U;   ///< of its state
  std::uint32_t out_crc = 0U;  ///< CRC-32C of its solution's words, taken where they were computed
};

// ---------------------------------------------------------------- the declarations

namespace detail {
namespace m = fdir::msg;
inline constexpr auto kMaxRow = static_cast<std::uint32_t>(std::numeric_limits<std::int32_t>::max());
inline constexpr std::uint32_t kU16 = 0xFFFFU;
constexpr bool healthy_listed(std::span<const std::uint32_t> w) noexcept { return w[2] <= w[3]; }
constexpr bool matched_tried(std::span<const std::uint32_t> w) noexcept { return w[4] <= w[3]; }
bool part_of_frame(std::span<const std::uint32_t> w) noexcept;  // messages.cpp
}  // namespace detail

/** A match inside results and batches (a record, no tag: sigma_px travels as a float). */
inline constexpr auto kMatchRecord = detail::m::kind<Match>(
    {.tag = detail::m::kNoTag, .name = "match", .channel = detail::m::kNoChannel, .from = 0U, .to = 0U},
    detail::m::f64("w_c", &Match::w_c, 0), detail::m::f64("p_m", &Match::p_m, 6), detail::m::f64("u_px", &Match::u_px, 12),
    detail::m::f64("v_px", &Match::v_px, 14), detail::m::f64("t_s", &Match::t_s, 16),
    detail::m::f32("sigma_px", &Match::sigma_px, 18), detail::m::f32("quality", &Match::quality, 19),
    detail::m::bits("landmark", &Match::landmark, 20, 0, 16), detail::m::bits("tile", &Match::tile, 20, 16, 16),
    detail::m::u32("frame", &Match::frame, 21));

/** An IMU sample, untagged (any bits: the filter refuses a bad one itself). */
inline constexpr auto kImuMsg = detail::m::kind<bsp::ImuSample>(
    {.tag = detail::m::kNoTag, .name = "imu", .channel = kChanImu, .from = role_bit(Role::kIo), .to = role_bit(Role::kFilter)},
    detail::m::u32("seq", &bsp::ImuSample::seq, 0), detail::m::u32("status", &bsp::ImuSample::status, 1),
    detail::m::f64("t_s", &bsp::ImuSample::t_s, 2), detail::m::f64("dtheta_rad", &bsp::ImuSample::dtheta_rad, 4),
    detail::m::f64("dv_mps", &bsp::ImuSample::dv_mps, 10));

inline constexpr auto kCommandMsg = detail::m::kind<Command>(
    {.tag = kMsgCommand, .name = "command", .channel = kChanImu, .from = role_bit(Role::kIo), .to = role_bit(Role::kFilter)},
    detail::m::u32("seq", &Command::seq, 1), detail::m::u32("code", &Command::code, 2),
    detail::m::u32("arg", &Command::arg, 3), detail::m::u32("after_imu", &Command::after_imu, 4));

/**
 * A navigation solution (any bits: a corrupted one is for the receiver to
 * judge): the variance diagonal of dp, dv, dtheta relative to the map (the
 * rest reads as zero), and the position variance against the world.
 */
inline constexpr auto kNavMsg = detail::m::kind<filter::NavOutput>(
    {.tag = kMsgNav, .name = "nav", .channel = kChanNav, .from = role_bit(Role::kFilter),
     .to = role_bit(Role::kVisionCoordinator)},
    detail::m::u32("flags", &filter::NavOutput::flags, 1), detail::m::f64("t_s", &filter::NavOutput::t_s, 2),
    detail::m::f64("p_m", &filter::NavOutput::p_m, 4), detail::m::f64("v_mps", &filter::NavOutput::v_mps, 10),
    detail::m::f64("q_mb_wxyz", &filter::NavOutput::q_mb_wxyz, 16),
    detail::m::f64("var_diag", &filter::NavOutput::var_diag, 24, 9),
    detail::m::f64("pos_var_world", &filter::NavOutput::pos_var_world, 42));

inline constexpr auto kFrameMsg = detail::m::kind<FrameNotice>(
    {.tag = kMsgFrame, .name = "frame", .channel = kChanControl, .from = role_bit(Role::kIo),
     .to = role_bit(Role::kVisionCoordinator)},
    detail::m::u32("seq", &FrameNotice::seq, 1), detail::m::bits("width_px", &FrameNotice::width_px, 2, 0, 16, 1U),
    detail::m::bits("height_px", &FrameNotice::height_px, 2, 16, 16, 1U), detail::m::u32("status", &FrameNotice::status, 3),
    detail::m::f64("t_s", &FrameNotice::t_s, 4), detail::m::u64("ddr_offset", &FrameNotice::ddr_offset, 6));

inline constexpr auto kUnitMsg = detail::m::kind<WorkUnit>(
    {.tag = kMsgUnit, .name = "unit", .channel = kChanControl, .from = role_bit(Role::kVisionCoordinator),
     .to = role_bit(Role::kVision), .group = {.count_field = 2U, .elem_words = 1U}},
    detail::m::u32("frame", &WorkUnit::frame, 1), detail::m::u32("unit", &WorkUnit::unit, 2),
    detail::m::u32("n", &WorkUnit::n, 3, 0U, kMaxLandmarksPerUnit), detail::m::f64("t_s", &WorkUnit::t_s, 4),
    detail::m::u64("ddr_offset", &WorkUnit::ddr_offset, 6), detail::m::bits("width_px", &WorkUnit::width_px, 8, 0, 16),
    detail::m::bits("height_px", &WorkUnit::height_px, 8, 16, 16), detail::m::f64("p_m", &WorkUnit::p_m, 9),
    detail::m::f64("q_mb_wxyz", &WorkUnit::q_mb_wxyz, 15), detail::m::each("landmark", &WorkUnit::landmark, 0, 0, 16),
    detail::m::each("radius_px", &WorkUnit::radius_px, 0, 16, 16));

inline constexpr auto kResultMsg = detail::m::kind<UnitResult>(
    {.tag = kMsgResult, .name = "result", .channel = kChanResult, .from = role_bit(Role::kVision),
     .to = role_bit(Role::kVisionCoordinator), .group = {.count_field = 3U, .elem_words = 22U, .record = "match"},
     .check = detail::matched_tried, .rule = "m <= tried"},
    detail::m::u32("frame", &UnitResult::frame, 1), detail::m::u32("unit", &UnitResult::unit, 2),
    detail::m::u32("tried", &UnitResult::tried, 3), detail::m::u32("m", &UnitResult::m, 4, 0U, kMaxLandmarksPerUnit),
    detail::m::u32("seal", &UnitResult::seal, 5));

inline constexpr auto kMatchesMsg = detail::m::kind<MatchPart>(
    {.tag = kMsgMatches, .name = "matches", .channel = kChanMatches, .from = role_bit(Role::kVisionCoordinator),
     .to = role_bit(Role::kFilter), .group = {.count_field = 3U, .elem_words = 22U, .record = "match"},
     .check = detail::part_of_frame, .rule = "part < parts; every match's frame is frame"},
    detail::m::u32("frame", &MatchPart::frame, 1), detail::m::bits("part", &MatchPart::part, 2, 0, 16),
    detail::m::bits("parts", &MatchPart::parts, 2, 16, 16), detail::m::u32("n", &MatchPart::n, 3, 1U, kMatchesPerPart),
    detail::m::u32("apply_job", &MatchPart::apply_job, 4), detail::m::u32("seal", &MatchPart::seal, 5));

inline constexpr auto kRelightMsg = detail::m::kind<RelightBand>(
    {.tag = kMsgRelight, .name = "relight", .channel = kChanControl, .from = role_bit(Role::kVisionCoordinator),
     .to = role_bit(Role::kVision)},
    detail::m::i32("row0", &RelightBand::row0, 1, 0U, detail::kMaxRow), detail::m::i32("rows", &RelightBand::rows, 2, 0U, detail::kMaxRow));

inline constexpr auto kRelightDoneMsg = detail::m::kind<RelightBand>(
    {.tag = kMsgRelightDone, .name = "relight_done", .channel = kChanResult, .from = role_bit(Role::kVision),
     .to = role_bit(Role::kVisionCoordinator)},
    detail::m::i32("row0", &RelightBand::row0, 1, 0U, detail::kMaxRow), detail::m::i32("rows", &RelightBand::rows, 2, 0U, detail::kMaxRow));

inline constexpr auto kCoarseBandMsg = detail::m::kind<CoarseBand>(
    {.tag = kMsgCoarseBand, .name = "coarse_band", .channel = kChanControl, .from = role_bit(Role::kVisionCoordinator),
     .to = role_bit(Role::kVision)},
    detail::m::u32("frame", &CoarseBand::frame, 1), detail::m::i32("row0", &CoarseBand::row0, 2, 0U, detail::kMaxRow),
    detail::m::i32("rows", &CoarseBand::rows, 3, 0U, detail::kMaxRow),
    detail::m::bits("window_w", &CoarseBand::window_w, 4, 0, 16, 1U), detail::m::bits("window_h", &CoarseBand::window_h, 4, 16, 16, 1U),
    detail::m::bits("tmpl_x", &CoarseBand::tmpl_x, 5, 0, 16), detail::m::bits("tmpl_y", &CoarseBand::tmpl_y, 5, 16, 16),
    detail::m::bits("tmpl_w", &CoarseBand::tmpl_w, 6, 0, 16, 1U), detail::m::bits("tmpl_h", &CoarseBand::tmpl_h, 6, 16, 16, 1U),
    detail::m::u32("slot", &CoarseBand::slot, 7));

inline constexpr auto kCoarseBandDoneMsg = detail::m::kind<CoarseBandDone>(
    {.tag = kMsgCoarseBandDone, .name = "coarse_band_done", .channel = kChanResult, .from = role_bit(Role::kVision),
     .to = role_bit(Role::kVisionCoordinator)},
    detail::m::u32("frame", &CoarseBandDone::frame, 1), detail::m::i32("row0", &CoarseBandDone::row0, 2, 0U, detail::kMaxRow),
    detail::m::i32("rows", &CoarseBandDone::rows, 3, 0U, detail::kMaxRow),
    detail::m::i32("flat_windows", &CoarseBandDone::flat_windows, 4, 0U, detail::kMaxRow),
    detail::m::u64("digest", &CoarseBandDone::digest, 5), detail::m::u32("recomputes", &CoarseBandDone::recomputes, 7),
    detail::m::bits("status", &CoarseBandDone::status, 8, 0, 8),
    detail::m::bits("check_failed", &CoarseBandDone::check_failed, 8, 8, 8, 0U, 1U),
    detail::m::bits("first_check", &CoarseBandDone::first_check, 8, 16, 8), detail::m::zero<CoarseBandDone>(8, 24, 8));

inline constexpr auto kReplicaHelloMsg = detail::m::kind<ReplicaHello>(
    {.tag = kMsgReplicaHello, .name = "replica_hello", .channel = kChanNav, .from = role_bit(Role::kFilterReplica),
     .to = role_bit(Role::kFilter)},
    detail::m::u32("replica", &ReplicaHello::replica, 1, 0U, kReplicas - 1U), detail::m::u32("epoch", &ReplicaHello::epoch, 2),
    detail::m::u32("refused", &ReplicaHello::refused, 3, 0U, 1U));

inline constexpr auto kReplicaOutMsg = detail::m::kind<ReplicaOut>(
    {.tag = kMsgReplicaOut, .name = "replica_out", .channel = kChanNav, .from = role_bit(Role::kFilterReplica),
     .to = role_bit(Role::kFilter), .group = {.fixed_count = 1U, .elem_words = kNavMsg.info.words, .record = "nav"}},
    detail::m::u32("replica", &ReplicaOut::replica, 1, 0U, kReplicas - 1U), detail::m::u32("job", &ReplicaOut::job, 2),
    detail::m::u32("digest", &ReplicaOut::digest, 3), detail::m::u32("out_crc", &ReplicaOut::out_crc, 4));

inline constexpr auto kSupCommandMsg = detail::m::kind<SupCommand>(
    {.tag = kMsgSupCommand, .name = "sup_command", .channel = kChanControl, .from = role_bit(Role::kFilterSupervisor),
     .to = role_bit(Role::kIo)},
    detail::m::u32("code", &SupCommand::code, 1, kCmdFilterTmr, kCmdFilterSimplex), detail::m::u32("node", &SupCommand::node, 2));

inline constexpr auto kFilterStatusMsg = detail::m::kind<FilterStatus>(
    {.tag = kMsgFilterStatus, .name = "filter_status", .channel = kChanControl, .from = role_bit(Role::kFilter),
     .to = role_bit(Role::kFilterSupervisor)},
    detail::m::u32("job", &FilterStatus::job, 1), detail::m::u32("mode", &FilterStatus::mode, 2, 0U, kFilterModeStopping),
    detail::m::u32("voting", &FilterStatus::voting, 3, 0U, 7U), detail::m::u32("no_majority", &FilterStatus::no_majority, 4),
    detail::m::u32("skipped", &FilterStatus::skipped, 5));

inline constexpr auto kVisionStatusMsg = detail::m::kind<VisionStatus>(
    {.tag = kMsgVisionStatus, .name = "vision_status", .channel = kChanControl, .from = role_bit(Role::kVisionCoordinator),
     .to = role_bit(Role::kVisionSupervisor), .check = detail::healthy_listed, .rule = "healthy <= listed"},
    detail::m::u32("frame", &VisionStatus::frame, 1), detail::m::u32("healthy", &VisionStatus::healthy, 2),
    detail::m::u32("listed", &VisionStatus::listed, 3), detail::m::u32("lost", &VisionStatus::lost, 4),
    detail::m::u32("rate_div", &VisionStatus::rate_div, 5, 1U, 2U));

inline constexpr auto kVisionRateMsg = detail::m::kind<VisionRate>(
    {.tag = kMsgVisionRate, .name = "vision_rate", .channel = kChanControl, .from = role_bit(Role::kVisionSupervisor),
     .to = role_bit(Role::kVisionCoordinator)},
    detail::m::u32("div", &VisionRate::div, 1, 1U, 2U));

/**
 * fdir's messages that travel on these channels, as they travel here: fdir
 * declares their tags and fields (fdir/health_messages.hpp, fdir/supervisor.hpp);
 * these say on which channel and between which roles, for the receivers'
 * dispatch and the docs.
 */
inline constexpr auto kReplacedOnControl = fdir::msg::routed(fdir::kReplacedMsg, kChanControl, role_bit(Role::kTrnSupervisor),
                                                             role_bit(Role::kVisionCoordinator));
inline constexpr auto kParkDoneOnControl = fdir::msg::routed(fdir::kParkDoneMsg, kChanControl, role_bit(Role::kTrnSupervisor),
                                                             role_bit(Role::kFilterSupervisor));
inline constexpr std::uint32_t kSupervisorRoles =
    role_bit(Role::kTrnSupervisor) | role_bit(Role::kFilterSupervisor) | role_bit(Role::kVisionSupervisor);
inline constexpr auto kPolicyOnControl =
    fdir::msg::routed(fdir::kPolicyMsg, kChanControl, kSupervisorRoles | role_bit(Role::kIo), kSupervisorRoles);
inline constexpr auto kPolicyHeldOnControl = fdir::msg::routed(fdir::kPolicyHeldMsg, kChanControl, kSupervisorRoles, kSupervisorRoles);
inline constexpr auto kEscalateOnControl = fdir::msg::routed(fdir::kEscalateMsg, kChanControl, kSupervisorRoles, kSupervisorRoles);

/** Every kind of message between TRN tiles, and the match record inside them: the docs' table. */
inline constexpr std::array<fdir::msg::KindView, 23> kMessageKinds{{
    fdir::msg::view(kFrameMsg), fdir::msg::view(kUnitMsg), fdir::msg::view(kRelightMsg), fdir::msg::view(kCoarseBandMsg),
    fdir::msg::view(kSupCommandMsg), fdir::msg::view(kFilterStatusMsg), fdir::msg::view(kVisionStatusMsg),
    fdir::msg::view(kVisionRateMsg), fdir::msg::view(kReplacedOnControl), fdir::msg::view(kParkDoneOnControl),
    fdir::msg::view(kPolicyOnControl), fdir::msg::view(kPolicyHeldOnControl), fdir::msg::view(kEscalateOnControl),
    fdir::msg::view(kResultMsg), fdir::msg::view(kRelightDoneMsg),
    fdir::msg::view(kCoarseBandDoneMsg), fdir::msg::view(kNavMsg), fdir::msg::view(kReplicaOutMsg),
    fdir::msg::view(kReplicaHelloMsg), fdir::msg::view(kMatchesMsg), fdir::msg::view(kImuMsg), fdir::msg::view(kCommandMsg),
    fdir::msg::view(kMatchRecord)}};

// ---------------------------------------------------------------- sizes that follow

inline constexpr std::uint32_t kImuWords = kImuMsg.info.words;
inline constexpr std::uint32_t kMatchWords = kMatchRecord.info.words;
inline constexpr std::uint32_t kNavWords = kNavMsg.info.words;
inline constexpr std::uint32_t kFrameNoticeWords = kFrameMsg.info.words;
inline constexpr std::uint32_t kCommandWords = kCommandMsg.info.words;
inline constexpr std::uint32_t kSupCommandWords = kSupCommandMsg.info.words;
inline constexpr std::uint32_t kFilterStatusWords = kFilterStatusMsg.info.words;
inline constexpr std::uint32_t kVisionStatusWords = kVisionStatusMsg.info.words;
inline constexpr std::uint32_t kVisionRateWords = kVisionRateMsg.info.words;
inline constexpr std::uint32_t kRelightWords = kRelightMsg.info.words;
inline constexpr std::uint32_t kCoarseBandWords = kCoarseBandMsg.info.words;
inline constexpr std::uint32_t kCoarseBandDoneWords = kCoarseBandDoneMsg.info.words;
inline constexpr std::uint32_t kUnitHeaderWords = kUnitMsg.info.words;
inline constexpr std::uint32_t kResultHeaderWords = kResultMsg.info.words;
inline constexpr std::uint32_t kMatchHeaderWords = kMatchesMsg.info.words;
inline constexpr std::uint32_t kReplicaHelloWords = kReplicaHelloMsg.info.words;
inline constexpr std::uint32_t kReplicaOutHeaderWords = kReplicaOutMsg.info.words;
inline constexpr std::uint32_t kReplicaOutWords = kReplicaOutHeaderWords + kNavWords;

namespace detail {
/** No tag twice among the kinds (an untagged kind is told by its channel and size). */
constexpr bool tags_unique() noexcept {
  for (std::size_t i = 0; i < kMessageKinds.size(); ++i) {
    for (std::size_t j = i + 1U; j < kMessageKinds.size(); ++j) {
      const fdir::msg::KindInfo* a = kMessageKinds[i].info;
      const fdir::msg::KindInfo* b = kMessageKinds[j].info;
      if (a != nullptr && b != nullptr && a->tag != fdir::msg::kNoTag && a->tag == b->tag) {
        return false;
      }
    }
  }
  return true;
}
}  // namespace detail
static_assert(detail::tags_unique(), "every message kind has its own tag");
static_assert(kImuWords == 16U && kMatchWords == 22U && kNavWords == 48U && kFrameNoticeWords == 8U &&
                  kUnitHeaderWords == 23U && kResultHeaderWords == 6U && kMatchHeaderWords == 6U &&
                  kCoarseBandDoneWords == 9U && kReplicaOutWords == 53U,
              "the wire format of the declared kinds");
static_assert(kMatchesMsg.info.group.elem_words == kMatchWords && kResultMsg.info.group.elem_words == kMatchWords,
              "results and batches carry match records");
static_assert(kMatchHeaderWords + kMatchesPerPart * kMatchWords <= 124U, "a part fits one FT packet");
static_assert(kUnitHeaderWords + kMaxLandmarksPerUnit <= 124U, "a unit fits one FT packet");
static_assert(kResultHeaderWords + kMaxLandmarksPerUnit * kMatchWords <= 124U, "a result fits one FT packet");

// ---------------------------------------------------------------- seals: a result's digest, from where it is computed to where it is used

/** The word of a vision result (kResultMsg) and of a batch part (kMatchesMsg) that holds its seal. */
inline constexpr std::uint32_t kSealWord = 5U;
static_assert(kResultHeaderWords == kSealWord + 1U && kMatchHeaderWords == kSealWord + 1U,
              "the seal is the last word of both headers");

/**
 * Seals @p w, a vision result or a part of the batch, as its tile made it: the
 * CRC-32C of all its words, word kSealWord taken as 0, into word kSealWord.
 * The receiver checks it where it uses the words (result_sealed()), so a bit
 * changed after the sender computed them (its buffer, its copy on the way out)
 * is found there; the network's own ECC covers only the packets. Charges the
 * CRC's work. Does nothing to fewer than kSealWord + 1 words.
 */
void seal_result(std::span<std::uint32_t> w) noexcept;

/** Whether @p w still holds the seal seal_result() wrote (false for fewer than kSealWord + 1 words). Charges the CRC's work. */
[[nodiscard]] bool result_sealed(std::span<const std::uint32_t> w) noexcept;

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

// ---------------------------------------------------------------- thin names left for three tasks

/*
 * Senders and receivers encode and decode with the declarations above
 * (fdir::msg::encode, decode, read; dispatch by tag). One message is two
 * kinds in a row: a replica's output, its header then its solution.
 */
/** The header, then @p nav as a kNavMsg after it. */
inline void pack_replica_out(const ReplicaOut& o, const filter::NavOutput& nav, std::span<std::uint32_t, kReplicaOutWords> w) noexcept {
  (void)fdir::msg::encode(kReplicaOutMsg, o, w);
  (void)fdir::msg::encode(kNavMsg, nav, w.subspan<kReplicaOutHeaderWords, kNavWords>());
}

}  // namespace trn::tasks
