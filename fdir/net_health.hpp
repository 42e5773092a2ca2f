/**
 * @file net_health.hpp
 * @brief Network health on the health tile: votes the probes' suspects into failed switches and
 *        links, and publishes each new fault map to every live tile by message.
 *
 * Every tile's endpoint probes its mesh neighbours and reports a neighbour that
 * misses kProbeMissThreshold rounds (udn::kMsgSuspect on kFtChanFdir). One
 * report is never enough: a tile that lost its own links would accuse all its
 * neighbours.
 * - Switch: declared failed once votes_to_fail distinct neighbours report it.
 * - Link: a link has two observers, its ends. When both ends report each other
 *   and nobody else reports either, the switches answer everyone else: the
 *   link between them is declared failed (both ways).
 * - Transits (fdir/transit.hpp): a switch no two live neighbours can vote on
 *   (a spare's, or a live tile's with one live neighbour) is declared failed
 *   when every planned transit through it is reported lost and the reports
 *   have been quiet for settle_ticks (so neighbour votes on live switches,
 *   which explain lost transits too, come first).
 * - Links by transits: when no switch explains the lost transits, a link no
 *   neighbour vote can name (a spare or a tile that does not probe at one end)
 *   whose heard transits are exactly the lost ones is declared failed; where
 *   nothing heard crosses a spare's switch at its end but over the link, the
 *   two look the same from here and the spare's switch is taken out instead
 *   (fdir::transit_link_verdict, kLinkOrSwitchFailed).
 * - Core or switch: a tile reported by a neighbour whose transits keep
 *   answering for settle_ticks has a switch that routes: its core is silent
 *   (kCoreSuspect), which is what the evidence can tell.
 * Each decision is a new fault-map version, applied on the health tile and
 * sent to every tile that is neither off by design nor failed (kFtChanMap),
 * paced by the messaging window; when every target was sent it, a
 * kMapPublished event closes the recovery. Reports about tiles off by design,
 * already failed, or from a tile about itself are ignored. The state (votes,
 * decisions, the map, the publication cursor) is carved in the health tile's
 * RAM at the task's start.
 */
#pragma once

#include "bsp_tile64/api/memory.hpp"
#include "bsp_tile64/api/port.hpp"
#include "fdir/transit.hpp"
#include "udn/route.hpp"

#include <array>
#include <cstdint>

namespace fdir {

struct NetHealthConfig {
  std::uint64_t not_voted = 0U;       ///< tiles off by design (spares): they answer no ping, so reports are expected
  std::uint32_t votes_to_fail = 2U;   ///< distinct reporters that fail a switch (>= 2)
  std::uint32_t idle_ticks = 4U;      ///< ticks between looks at the reports when nothing is being published
  TransitPlan transits{};              ///< the transit probes the endpoints run (same plan as their configuration)
  std::uint64_t transit_subjects = 0U; ///< switches judged by transits (the plan's subjects)
  std::uint32_t settle_ticks = 60U;    ///< quiet time before transits are judged
  /**
   * An end tile (end_tile_verdict: transits end there, none crosses it
   * between two independent probers) whose every transit stays lost this
   * long is cut off: longer than a hung core takes to be named by its
   * watchdog, reset and answer again.
   */
  std::uint32_t end_tile_ticks = 150U;
  /**
   * After the task starts (its tile restarted, or a standby took the
   * supervisor's role over) it knows no transit lost yet: the endpoints send
   * again what still holds every kReReportRounds probe rounds. Until this
   * long has passed, no transit counts as answering, so no silent tile is
   * taken for a silent core behind a switch that routes.
   */
  std::uint32_t relearn_ticks = 220U;
};

/** Health task entry (arg: const NetHealthConfig*). */
void net_health_task_main(void* arg) noexcept;

/**
 * The tiles the power policy switched off (the tile-health supervisor, on the
 * same tile, says so): off by design like spares, their neighbours' reports
 * are not votes and transits to or from them tell nothing; no map is sent to
 * them (a woken tile is sent the current one at its boot report). [task, the health tile]
 */
void net_health_set_parked(std::uint64_t parked) noexcept;

/** What the health tile has decided so far. [host: displays and tests] */
struct NetHealthView {
  std::uint64_t failed_switches = 0U;
  std::uint32_t failed_links = 0U;     ///< links declared failed (pairs)
  std::uint32_t map_version = 0U;      ///< latest version decided
  std::uint32_t published_version = 0U;///< latest version every target was sent
};

/** The decisions of the health task on @p tile (all zero if it does not run there). [host] */
NetHealthView net_health_view(bsp::TileId tile) noexcept;

/** Name of the network-health task's state carve, and its layout (bsp::ControlLayout). [host] */
inline constexpr const char* kNetHealthCarve = "net_health";
const bsp::ControlLayout& net_health_state_layout() noexcept;

/** Pure vote step, for tests: see net_health.cpp. */
namespace detail {

struct Votes {
  std::uint64_t not_voted = 0U;
  std::uint32_t votes_to_fail = 2U;
  std::uint64_t failed = 0U;                         ///< switches declared failed
  std::uint32_t links = 0U;                          ///< links declared failed
  std::array<std::uint64_t, udn::kRouteMaxTiles> reporters{};  ///< per suspect: bit r = tile r reported it
};

/** Votes are emulated state through and through (bsp::ControlLayout). */
inline constexpr std::array kVotesFields{
    BSP_CONTROL_STATE(Votes, not_voted), BSP_CONTROL_STATE(Votes, votes_to_fail), BSP_CONTROL_STATE(Votes, failed),
    BSP_CONTROL_STATE(Votes, links),     BSP_CONTROL_STATE(Votes, reporters),
};
inline constexpr bsp::ControlLayout kVotesLayout{kVotesFields, sizeof(Votes), alignof(Votes)};
static_assert(bsp::control_layout_ok(kVotesLayout), "every member of Votes");

enum class Verdict : std::uint8_t { kIgnored, kCounted, kSwitchFailed, kLinkFailed };

/**
 * Takes one report of @p reporter about @p suspect into @p v and, on a
 * decision, marks it in @p map (version moves). @p votes_out: distinct reporters
 * of the suspect after the report.
 */
Verdict take_report(Votes& v, udn::FaultMap& map, bsp::TileId reporter, bsp::TileId suspect,
                    std::uint32_t& votes_out) noexcept;

}  // namespace detail

}  // namespace fdir
