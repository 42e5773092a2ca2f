/**
 * @file fdir_params.hpp
 * @brief Every FDIR threshold, period, window and cap of the image, in one table.
 *
 * Each row is either a field of the image's configuration (ImageConfig: its
 * default is the field's initialiser, configure_image() refuses a value out of
 * the row's range and names the row) or a constant of the image (its value is
 * the constant's, named where it is used). The table holds no value of its
 * own, so each value is written once; docs/FDIR.md's "Parameters" table is
 * checked against it (FdirParams.TheTableInFdirMdIsTheDeclaration).
 */
#pragma once

#include "fdir/abft.hpp"
#include "fdir/tile_health.hpp"
#include "trn/tasks/filter/filter_task.hpp"
#include "trn/tasks/filter/filter_tmr.hpp"
#include "trn/tasks/io/io_task.hpp"
#include "trn/tasks/messages.hpp"
#include "trn/tasks/supervisors/supervisors.hpp"
#include "trn/tasks/tile_map.hpp"
#include "trn/tasks/vision/vision_coord.hpp"
#include "trn/tasks/vision/vision_shared.hpp"
#include "udn/endpoint.hpp"
#include "udn/ft_link.hpp"

#include <array>
#include <cstddef>
#include <cstdint>
#include <type_traits>

namespace trn::tasks {

/** One FDIR tuning value. */
struct FdirParam {
  const char* name;     ///< the field's path in ImageConfig, or the constant's name in the docs
  const char* unit;
  std::uint32_t min;    ///< a field's range (a constant's: its value)
  std::uint32_t max;
  std::uint32_t (*get)(const ImageConfig&) noexcept;  ///< a field's value; nullptr for a constant
  std::uint32_t& (*set)(ImageConfig&) noexcept;       ///< nullptr for a constant
  std::uint32_t value;  ///< a constant's value
  const char* meaning;
};

namespace detail {
/** Field P1.P2 (or P1.P2.P3) of the image's configuration. */
template <auto P1, auto P2, auto P3 = nullptr>
struct ParamField {
  template <class C>
  static auto& at(C& c) noexcept {
    if constexpr (std::is_same_v<decltype(P3), std::nullptr_t>) {
      return (c.*P1).*P2;
    } else {
      return ((c.*P1).*P2).*P3;
    }
  }
  static std::uint32_t get(const ImageConfig& c) noexcept { return at(c); }
  static std::uint32_t& set(ImageConfig& c) noexcept { return at(c); }
};
}  // namespace detail

/** A row for a field of the configuration, accepted in [@p min, @p max]. */
template <auto P1, auto P2, auto P3 = nullptr>
constexpr FdirParam field(const char* name, const char* unit, std::uint32_t min, std::uint32_t max,
                          const char* meaning) noexcept {
  // The pointers are to static member functions, which live as long as the program.
  // cppcheck-suppress returnDanglingLifetime
  return {name, unit, min, max, &detail::ParamField<P1, P2, P3>::get, &detail::ParamField<P1, P2, P3>::set, 0U,
          meaning};
}

/** A row for a constant of the image. */
constexpr FdirParam constant(const char* name, const char* unit, std::uint32_t value, const char* meaning) noexcept {
  return {name, unit, value, value, nullptr, nullptr, value, meaning};
}

/** The table: configuration fields first, by part, then the image's constants. */
inline constexpr std::array<FdirParam, 66> kFdirParams{{
    // ---- messaging: probes and the fault-tolerant links (udn)
    field<&ImageConfig::endpoint, &udn::EndpointConfig::probe_period_ticks>(
        "endpoint.probe_period_ticks", "ticks", 2U, 1000U, "a tile pings its neighbours and transit targets this often"),
    field<&ImageConfig::endpoint, &udn::EndpointConfig::probe_miss_threshold>(
        "endpoint.probe_miss_threshold", "probe rounds", 1U, 100U, "missed pings in a row before a neighbour is reported"),
    field<&ImageConfig::endpoint, &udn::EndpointConfig::ft, &udn::FtConfig::timeout_ticks>(
        "endpoint.ft.timeout_ticks", "ticks", 1U, 1000U, "least first retransmit timeout (doubles per retry)"),
    field<&ImageConfig::endpoint, &udn::EndpointConfig::ft, &udn::FtConfig::max_retries>(
        "endpoint.ft.max_retries", "retransmissions", 1U, 64U, "before a packet is given up"),
    // ---- core health: the agents and the tile-health supervisor (fdir)
    field<&ImageConfig::agent, &fdir::HealthAgentConfig::watchdog_ticks>(
        "agent.watchdog_ticks", "ticks", 2U * fdir::kAgentPeriodTicks, 100000U,
        "hardware watchdog timeout of every role tile"),
    field<&ImageConfig::agent, &fdir::HealthAgentConfig::watcher_timeout_ticks>(
        "agent.watcher_timeout_ticks", "ticks", 1U, 100000U,
        "the supervisor's heartbeat missing this long: its watcher resets it (> watchdog + a boot)"),
    field<&ImageConfig::agent, &fdir::HealthAgentConfig::max_watcher_resets>(
        "agent.max_watcher_resets", "resets", 0U, 1000U, "resets of the supervisor's tile by its watcher"),
    field<&ImageConfig::tile_health, &fdir::TileHealthConfig::max_resets>(
        "tile_health.max_resets", "resets", 1U, 1000U, "resets of a tile before its role moves to a spare"),
    field<&ImageConfig::tile_health, &fdir::TileHealthConfig::boot_timeout_ticks>(
        "tile_health.boot_timeout_ticks", "ticks", 1U, 1000000U, "a reset tile reports within this or is lost"),
    field<&ImageConfig::tile_health, &fdir::TileHealthConfig::poll_ticks>(
        "tile_health.poll_ticks", "ticks", 1U, 1000U, "the supervisor looks at boot reports and timeouts this often"),
    field<&ImageConfig::tile_health, &fdir::TileHealthConfig::self_test_ticks>(
        "tile_health.self_test_ticks", "ticks", 0U, 1000000U, "a self-test round this often (0: none)"),
    field<&ImageConfig::tile_health, &fdir::TileHealthConfig::self_test_wait_ticks>(
        "tile_health.self_test_wait_ticks", "ticks", 1U, 1000000U,
        "a round's results are voted this long after the requests (< the round)"),
    field<&ImageConfig::tile_health, &fdir::TileHealthConfig::disagreements_to_fail>(
        "tile_health.disagreements_to_fail", "rounds", 1U, 1000U,
        "self-tests in a row a tile is outvoted in before it is retired"),
    // ---- network health (fdir)
    field<&ImageConfig::net_health, &fdir::NetHealthConfig::votes_to_fail>(
        "net_health.votes_to_fail", "reporters", 2U, 4U, "distinct neighbours that fail a switch"),
    field<&ImageConfig::net_health, &fdir::NetHealthConfig::idle_ticks>(
        "net_health.idle_ticks", "ticks", 1U, 1000U, "between looks at the reports when nothing is published"),
    field<&ImageConfig::net_health, &fdir::NetHealthConfig::settle_ticks>(
        "net_health.settle_ticks", "ticks", 1U, 100000U, "quiet time before transits are judged"),
    field<&ImageConfig::net_health, &fdir::NetHealthConfig::end_tile_ticks>(
        "net_health.end_tile_ticks", "ticks", 1U, 100000U,
        "transits all lost this long, at an end tile or a heard end of a link: its switch or the link failed (a hung core is reset sooner)"),
    field<&ImageConfig::net_health, &fdir::NetHealthConfig::relearn_ticks>(
        "net_health.relearn_ticks", "ticks", 0U, 100000U,
        "after the task starts, no transit counts as answering before the endpoints report again"),
    // ---- vision: the coordinator's view of its tiles (trn)
    field<&ImageConfig::coord, &VisionCoordConfig::liveness, &fdir::LivenessConfig::suspect_after_misses>(
        "coord.liveness.suspect_after_misses", "frames", 1U, 1000U,
        "frames a vision tile misses in a row before it gets no more work"),
    field<&ImageConfig::coord, &VisionCoordConfig::liveness, &fdir::LivenessConfig::probe_every>(
        "coord.liveness.probe_every", "frames", 1U, 1000U, "a silent vision tile is tried again this often"),
    field<&ImageConfig::coord, &VisionCoordConfig::trust, &fdir::ResultTrustConfig::window>(
        "coord.trust.window", "frames", 1U, fdir::kMaxTrustWindow, "sliding window of a tile's checked results"),
    field<&ImageConfig::coord, &VisionCoordConfig::trust, &fdir::ResultTrustConfig::min_failed>(
        "coord.trust.min_failed", "results", 1U, 10000U, "failed results in the window that make a tile suspect"),
    field<&ImageConfig::coord, &VisionCoordConfig::trust, &fdir::ResultTrustConfig::reset_after>(
        "coord.trust.reset_after", "frames", 1U, 10000U, "frames a tile stays suspect before its reset is asked"),
    field<&ImageConfig::coord, &VisionCoordConfig::trust, &fdir::ResultTrustConfig::probation>(
        "coord.trust.probation", "frames", 1U, 10000U, "clean frames in a row that make a suspect tile trusted"),
    field<&ImageConfig::coord, &VisionCoordConfig::trust, &fdir::ResultTrustConfig::bias_window>(
        "coord.trust.bias_window", "frames", 1U, fdir::kMaxTrustWindow, "sliding window of a tile's residuals (the bias test)"),
    field<&ImageConfig::coord, &VisionCoordConfig::trust, &fdir::ResultTrustConfig::bias_min>(
        "coord.trust.bias_min", "matches", 2U, 10000U, "fitted matches in the window before a tile's bias is judged"),
    field<&ImageConfig::coord, &VisionCoordConfig::trust, &fdir::ResultTrustConfig::bias_sigmas>(
        "coord.trust.bias_sigmas", "sigmas", 1U, 100U,
        "a tile's mean residual past this many standard errors of the mean (and the floor) makes it suspect"),
    field<&ImageConfig::coord, &VisionCoordConfig::trust, &fdir::ResultTrustConfig::bias_floor_mpx>(
        "coord.trust.bias_floor_mpx", "1/1000 px", 1U, 100000U,
        "the least mean residual of a tile's matches that makes it suspect"),
    field<&ImageConfig::coord, &VisionCoordConfig::trust, &fdir::ResultTrustConfig::bias_clip_mpx>(
        "coord.trust.bias_clip_mpx", "1/1000 px", 1U, 100000U,
        "each residual taken at most this far from 0 in the mean (a few large ones weigh no more)"),
    // ---- the filter and its TMR (trn)
    field<&ImageConfig::filter, &FilterTaskConfig::checkpoint_every>(
        "filter.checkpoint_every", "jobs", 0U, 100000U, "between DDR checkpoints (0: none, no resume)"),
    field<&ImageConfig::filter, &FilterTaskConfig::tmr, &fdir::TmrGroupConfig::disagree_to_exclude>(
        "filter.tmr.disagree_to_exclude", "jobs", 1U, 1000U, "disagreements in a row that exclude a replica"),
    field<&ImageConfig::filter, &FilterTaskConfig::tmr, &fdir::TmrGroupConfig::miss_to_exclude>(
        "filter.tmr.miss_to_exclude", "jobs", 1U, 1000U, "missed jobs in a row that exclude a replica"),
    field<&ImageConfig::filter, &FilterTaskConfig::innovation, &fdir::InnovationMonitorConfig::block_matches>(
        "filter.innovation.block_matches", "matches", 1U, 1000U, "measurements per block of the innovation monitor"),
    field<&ImageConfig::filter, &FilterTaskConfig::innovation, &fdir::InnovationMonitorConfig::window_blocks>(
        "filter.innovation.window_blocks", "blocks", 1U, fdir::kMaxInnovationBlocks, "blocks in the window judged"),
    field<&ImageConfig::filter, &FilterTaskConfig::innovation, &fdir::InnovationMonitorConfig::nis_sigmas>(
        "filter.innovation.nis_sigmas", "sigmas", 1U, 100U,
        "a window's mean clipped d2 past its chi-square mean by this many standard errors ..."),
    field<&ImageConfig::filter, &FilterTaskConfig::innovation, &fdir::InnovationMonitorConfig::nis_floor_milli>(
        "filter.innovation.nis_floor_milli", "1/1000", 1U, 1000000U, "... and past this fails it"),
    field<&ImageConfig::filter, &FilterTaskConfig::innovation, &fdir::InnovationMonitorConfig::reject_sigmas>(
        "filter.innovation.reject_sigmas", "sigmas", 1U, 100U,
        "a window's rejected fraction past the gate's by this many standard errors ..."),
    field<&ImageConfig::filter, &FilterTaskConfig::innovation, &fdir::InnovationMonitorConfig::reject_floor_pct>(
        "filter.innovation.reject_floor_pct", "%", 0U, 100U, "... and past this fails it"),
    field<&ImageConfig::filter, &FilterTaskConfig::widen_pos_m>(
        "filter.widen_pos_m", "m", 0U, 100000U, "a failed window widens the position sigma by this (in quadrature)"),
    field<&ImageConfig::filter, &FilterTaskConfig::widen_vel_cmps>(
        "filter.widen_vel_cmps", "cm/s", 0U, 100000U, "... the velocity sigma by this"),
    field<&ImageConfig::filter, &FilterTaskConfig::widen_att_mrad>(
        "filter.widen_att_mrad", "mrad", 0U, 1000U, "... the attitude sigma by this"),
    // ---- supervisors (trn)
    field<&ImageConfig::sup, &SupervisorsConfig::vision_min_full>(
        "sup.vision_min_full", "tiles", 0U, kMaxVisionTiles, "healthy vision tiles the full image rate needs"),
    field<&ImageConfig::sup, &SupervisorsConfig::vision_min_half>(
        "sup.vision_min_half", "tiles", 0U, kMaxVisionTiles, "healthy vision tiles half the rate needs (<= full)"),
    field<&ImageConfig::sup, &SupervisorsConfig::wake_lead_ticks>(
        "sup.wake_lead_ticks", "ticks", 0U, 1000000U, "parked replicas are woken this long before a phase needs them"),
    // ---- constants of the image
    constant("fdir::kAgentPeriodTicks", "ticks", fdir::kAgentPeriodTicks,
             "a tile's health agent looks at the check-ins and kicks its watchdog this often"),
    constant("fdir::kParkOffTicks", "ticks", fdir::kParkOffTicks,
             "a parked tile is switched off this long after the others are told"),
    constant("udn::kCommWatchTicks", "ticks", udn::kCommWatchTicks, "check-in budget of the messaging service"),
    constant("kWatchSupervisor", "ticks", kWatchSupervisor, "check-in budget of the supervisors' tasks"),
    constant("kWatchIo", "ticks", kWatchIo, "check-in budget of the I/O task"),
    constant("kWatchFilter", "ticks", kWatchFilter, "check-in budget of the filter and its replicas"),
    constant("kWatchCoordinator", "ticks", kWatchCoordinator, "check-in budget of the vision coordinator"),
    constant("kWatchVision", "ticks", kWatchVision, "check-in budget of a vision tile"),
    constant("udn::kReReportRounds", "probe rounds", udn::kReReportRounds,
             "a suspicion that still holds is reported again this often"),
    constant("udn::kMaxRttTicks", "ticks", udn::kMaxRttTicks, "largest round trip the retransmit timer takes"),
    constant("kIdleCheckinTicks", "ticks", kIdleCheckinTicks, "the I/O task checks in at least this often"),
    constant("kNoticeTicks", "ticks", kNoticeTicks, "a frame notice may wait this long for the network"),
    constant("kTicksPerSecond", "ticks", kTicksPerSecond, "the mission tick (1 ms) every value in ticks assumes"),
    constant("kControlSendTicks", "ticks", kControlSendTicks,
             "an IMU sample or a supervisor's message may wait this long for the network"),
    constant("kVisionSendTicks", "ticks", kVisionSendTicks, "a vision unit or result may wait this long"),
    constant("kSupPeriodTicks", "ticks", kSupPeriodTicks, "a supervisor's loop runs this often"),
    constant("kPolicyRefreshTicks", "ticks", kPolicyRefreshTicks, "the TRN supervisor hands its policies down again"),
    constant("kFilterSettle", "status reports", kFilterSettle, "ignored by the filter supervisor after a command"),
    constant("kFilterStatusJobs", "jobs", kFilterStatusJobs, "the filter reports its status this often"),
    constant("kStartJobs", "jobs", kStartJobs, "a switch to TMR not established by then is given up"),
    constant("kVoteLag", "jobs", kVoteLag, "the voter votes a job this many jobs after its record"),
    constant("fdir::kAbftMaxRecompute", "recomputations", fdir::kAbftMaxRecompute,
             "of a checked product that fails its checksums"),
}};

/**
 * The first field of @p cfg out of its row's range; nullptr if every one is in range.
 * configure_image() refuses such a configuration and names the row.
 */
const FdirParam* fdir_param_out_of_range(const ImageConfig& cfg) noexcept;

}  // namespace trn::tasks
