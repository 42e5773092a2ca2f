/**
 * @file transit.hpp
 * @brief Transit probes: how the switches of spare tiles, which route traffic but run nothing
 *        that could answer a probe, are tested, and how a lost transit names the failed one.
 *
 * A transit is a PING from one live tile (the prober) to another (the target),
 * sent straight (one X-then-Y leg, no routing) and answered straight: the
 * round trip crosses every switch on both legs. The plan (plan_transits, made
 * once by the image before boot) chooses transits so that every subject
 * switch on a leg between live tiles (every spare that carries traffic, and
 * live tiles too poorly watched for a neighbour vote) is crossed by at least
 * kTransitsPerSpare of them, two of them independent (no end in common: a
 * transit relies on its prober's report and its target's answer, so one
 * faulty tile is an end of at most one of the two), and no two subjects
 * touch the same transits. A failed switch kills exactly the transits through it, so the
 * verdict names the one subject whose transits are all lost, two independent
 * ones among them (voted, like a neighbour report that needs two
 * neighbours), and are not a part of another such subject's. A live switch whose failure kills a
 * subject's transits is voted by its neighbours first; its transits then tell
 * nothing and are left out. Each prober pings its targets every probe round
 * (udn/endpoint.hpp) and reports a target lost after the miss threshold and
 * back when it answers again (udn::kMsgTransit); the health tile decides
 * (fdir/net_health.hpp).
 *
 * Static storage, bounded loops; the plan is computed from the boot fault map.
 */
#pragma once

#include "bsp_tile64/api/memory.hpp"
#include "bsp_tile64/api/port.hpp"
#include "bsp_tile64/api/work.hpp"
#include "udn/route.hpp"

#include <array>
#include <cstdint>

namespace fdir {

inline constexpr std::uint32_t kMaxTransits = 64U;        ///< transits in one plan (bits of a 64-bit mask)
inline constexpr std::uint32_t kTransitsPerProber = 4U;   ///< targets one tile pings at most
inline constexpr std::uint32_t kTransitsPerSpare = 2U;    ///< transits crossing each testable subject, at least (two independent)

struct Transit {
  bsp::TileId prober = bsp::kNoTile;
  bsp::TileId target = bsp::kNoTile;
  std::uint64_t path = 0U;  ///< switches of the round trip (bit per tile), both ends included
  udn::LinkSet links{};     ///< links of the round trip
};

struct TransitPlan {
  std::uint32_t count = 0U;
  std::array<Transit, kMaxTransits> t{};
  std::uint64_t tested = 0U;      ///< subjects that meet the plan's rule (two independent transits, told apart)
  std::uint64_t untested = 0U;    ///< subjects on some leg between probers the plan could not test so: never failed by transits
  /**
   * Links no neighbour vote can name (an end that does not probe) on some leg
   * between probers that the plan's transits can name (transit_link_verdict):
   * two across each with no end in common, no third switch on all of them, and
   * no other link lost with the same transits.
   */
  udn::LinkSet links_named{};
};

enum class TransitError : std::uint8_t { kOk, kBadArgs };

/**
 * Plans the transits between tiles in @p probers (live tiles running an
 * endpoint) for the switches of @p subjects on @p map's grid: the spares, and
 * live tiles with too few live neighbours for a vote. A transit tests a switch
 * it passes through, never its own ends. Mesh neighbours are never paired
 * (the neighbour probe tests them). Deterministic: the same inputs give the
 * same plan. [host, before boot]
 * @return kBadArgs for an empty grid or more than 64 tiles.
 */
TransitError plan_transits(const udn::FaultMap& map, std::uint64_t probers, std::uint64_t subjects,
                           TransitPlan& out) noexcept;

/** Transits of @p plan that pass through @p tile (bit per plan index), its own ends excluded. */
std::uint64_t transits_through(const TransitPlan& plan, bsp::TileId tile) noexcept;

/**
 * Tiles of @p live with fewer than @p votes live mesh neighbours on @p map's
 * grid: no neighbour vote can fail their switch, so transits must judge it.
 */
std::uint64_t under_observed(const udn::FaultMap& map, std::uint64_t live, std::uint32_t votes) noexcept;

/** Targets (bit per tile) @p prober pings in @p plan. */
std::uint64_t transit_targets(const TransitPlan& plan, bsp::TileId prober) noexcept;

/** Index of transit (@p prober, @p target) in @p plan, or kMaxTransits. */
std::uint32_t transit_index(const TransitPlan& plan, bsp::TileId prober, bsp::TileId target) noexcept;

/** Transits of @p plan that cross a link of @p links (bit per plan index). */
std::uint64_t transits_across(const TransitPlan& plan, const udn::LinkSet& links) noexcept;

/**
 * The subject a failed switch explains the lost transits by, given the
 * transits reported lost (@p lost, bit per plan index), the tiles already
 * known failed (a transit touching one tells nothing new and is left out) and
 * the transits @p mute that tell nothing either (across a link known failed).
 * Candidates are subjects the plan tested with at least kTransitsPerSpare
 * transits that count, all lost, two of them independent (no end in common)
 * and no link crossed by all of them: one prober's reports, one target's
 * silence or one failed link never fail a switch. The answer is the one
 * candidate whose transits no other candidate's include.
 * @return the subject, or bsp::kNoTile when there is no such one.
 */
bsp::TileId transit_verdict(const TransitPlan& plan, std::uint64_t lost, std::uint64_t subjects,
                            std::uint64_t known_failed, std::uint64_t mute = 0U) noexcept;

/**
 * An end tile whose switch the lost transits point at although the plan
 * cannot test it (a subject of @p candidates, say plan.untested: one live
 * neighbour, nothing crosses it between two independent probers): some
 * planned transit targets it, so its software answers them, and every
 * transit to or through it that tells (nothing on the way in
 * @p known_failed, not in @p mute) is in @p lost, and either they come from
 * two probers or more with no link common to all, or a neighbour's probe
 * found it silent too (@p reported; the transit reports that cross a failed
 * end tile are lost with it, so often one prober is all that is heard). A
 * hung core loses the same transits; the
 * caller tells the two apart by time (a hung core is named by its watchdog,
 * reset and answers again well within it). @p transits_out: those
 * transits. @return the lowest such tile, or bsp::kNoTile.
 */
bsp::TileId end_tile_verdict(const TransitPlan& plan, std::uint64_t lost, std::uint64_t candidates,
                             std::uint64_t known_failed, std::uint64_t mute, std::uint64_t reported,
                             std::uint64_t& transits_out) noexcept;

/** A mesh link named by lost transits. */
struct LinkVerdict {
  bsp::TileId a = bsp::kNoTile;  ///< the link's west or north tile (kNoTile: no link named)
  bsp::TileId b = bsp::kNoTile;  ///< its east or south neighbour
  std::uint32_t transits = 0U;   ///< transits across it that count, all lost
  /**
   * Its ends (bit per tile) whose switch nothing heard crosses but over the
   * link: that switch failing would look the same from here.
   */
  std::uint64_t unsure = 0U;
  /**
   * Every link named: more than one when the links are a chain that every
   * transit crosses whole (through a spare that answers for itself on other
   * transits), so no transit tells which of them failed; all are taken out.
   * a and b are the first of them.
   */
  udn::LinkSet links{};
  std::uint32_t count = 0U;  ///< links named
};

/**
 * The two ways each prober's reports take to the health tile
 * (udn/endpoint.cpp): their route, if direct, and its twin
 * (udn::route_twin_via), as links. A prober whose route goes through
 * intermediates has neither: its reports are taken as heard.
 */
struct ReportWays {
  std::uint32_t version = 0xFFFF'FFFFU;  ///< map version they were found for
  std::uint64_t parked = 0U;             ///< and the tiles that were parked then
  std::array<udn::LinkSet, kMaxTransits> route{};
  std::array<udn::LinkSet, kMaxTransits> twin{};  ///< the route's again when there is no twin
};

/** The ways are emulated state through and through (bsp::ControlLayout). */
inline constexpr std::array kReportWaysFields{
    BSP_CONTROL_STATE(ReportWays, version),
    BSP_CONTROL_STATE(ReportWays, parked),
    BSP_CONTROL_NESTED(ReportWays, route, udn::kLinkSetLayout),
    BSP_CONTROL_NESTED(ReportWays, twin, udn::kLinkSetLayout),
};
inline constexpr bsp::ControlLayout kReportWaysLayout{kReportWaysFields, sizeof(ReportWays), alignof(ReportWays)};
static_assert(bsp::control_layout_ok(kReportWaysLayout), "every member of ReportWays");

/** The ways of the reports of @p plan's probers to @p health on @p map (@p parked forward nothing); counted in @p work. */
void report_ways(const TransitPlan& plan, const udn::FaultMap& map, bsp::TileId health, std::uint64_t parked,
                 ReportWays& out, bsp::Work& work) noexcept;

/**
 * The mesh link whose failure explains the lost transits, for a link no
 * neighbour vote can name (an end is a spare, or runs no probe), on a
 * @p cols x @p rows grid. A report both of whose @p ways cross the link never
 * comes, and is not waited for. The transits that count (nothing on the way
 * in @p known_failed, not in @p mute) and are lost must all be across the
 * link, and every one across it that can be heard must be lost: at least
 * kTransitsPerSpare, two with no end in common (one faulty prober or target
 * cannot lose them all), and no third switch on all of them, unless a heard
 * transit through it answers (its failure would lose the same ones). So
 * every other transit heard through the link's two switches answers: they
 * route. Links lost by the very same transits (a chain through spares that
 * every straight leg crosses whole) are named together; two links that
 * explain the losses differently name neither. The verdict on switches
 * (transit_verdict) goes first. Where nothing heard crosses an end's switch
 * but over a single named link, that switch failing would look the same from
 * here: the end is marked unsure.
 *
 * The lost transits may instead share one end, if it is an end of the link
 * and in @p heard_ends: a tile whose own reports of lost transits come (its
 * core runs and its switch forwards them), lost longer than a hung core
 * stays silent (the caller's to judge). Every way it has is then heard but
 * the one across the link: the link failed (a link out of the I/O tile to a
 * spare, which no neighbour vote and no two independent transits see). Such
 * an end is never unsure.
 */
LinkVerdict transit_link_verdict(const TransitPlan& plan, std::uint32_t cols, std::uint32_t rows,
                                 const ReportWays& ways, std::uint64_t lost, std::uint64_t known_failed,
                                 std::uint64_t mute, std::uint64_t heard_ends = 0U) noexcept;

}  // namespace fdir
