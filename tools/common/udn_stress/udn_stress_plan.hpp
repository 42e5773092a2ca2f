/**
 * @file udn_stress_plan.hpp
 * @brief What both udn_stress runs share: which tiles send and are sent to, destinations, the board, faults at t=0.
 *
 * The raw run and the --ft on run differ in how a packet travels, not in the
 * traffic: both draw destinations here, boot the board here and apply the
 * same bit errors and failures here, so their reports compare key for key.
 * Internal to tools/common/udn_stress*.cpp.
 */
#pragma once

#include "bsp_tile64/emu/board.hpp"
#include "bsp_tile64/emu/rng.hpp"
#include "kernel/task_table.hpp"
#include "tools/common/udn_stress/udn_stress.hpp"

#include <array>
#include <cstdint>

namespace tools::detail {

/** Which tiles take part in a run and how many packets each sends; fixed before the board boots. */
struct TrafficPlan {
  bsp::ChipProfile profile = bsp::kTile64;
  TrafficPattern pattern = TrafficPattern::kUniform;
  std::array<bool, bsp::kMaxTiles> sends{};        ///< runs the traffic tasks
  std::array<bool, bsp::kMaxTiles> addressed{};    ///< may be drawn as a destination
  std::array<bsp::TileId, bsp::kMaxTiles> targets{};  ///< the addressed tiles, in id order
  std::uint32_t target_count = 0U;
  std::uint32_t sender_count = 0U;
  std::array<std::uint64_t, bsp::kMaxTiles> quota{};  ///< packets per sending tile; they sum to opts.packets
};

/** The chip profile named by --profile. */
const bsp::ChipProfile& profile_named(const std::string& name);

/**
 * The plan of a run. Failed tiles run nothing and are never addressed. Failed
 * switches: a raw tile does not know its switch failed, so it runs and is
 * addressed as usual (its packets are lost); with --ft on the fault map knows,
 * so those tiles run nothing and are not addressed.
 */
TrafficPlan make_plan(const StressOptions& opts);

/**
 * A destination for the next packet of @p self, from the pattern; a pattern
 * destination that is not addressed is replaced by a uniform draw. Uniform:
 * the addressed tiles other than self (self only when it is the only one).
 */
bsp::TileId pick_destination(const TrafficPlan& plan, bsp::Rng& rng, bsp::TileId self);

/**
 * Boots the board with @p tasks on every sending tile, initialises the
 * network with @p net and applies the faults of @p opts at t=0: the bit
 * error rate, the switches of failed tiles and failed switches, the failed links.
 * @return false if any step fails.
 */
bool boot_stress_board(const StressOptions& opts, const TrafficPlan& plan, k::TaskTable tasks,
                       const bsp::NetConfig& net);

/**
 * Runs the booted board until @p done or the bound, with the heap sealed as
 * @p seal, and fills the fields of @p r both runs share (end, bound, times,
 * network statistics, link utilisation, heap use).
 */
void run_stress_board(const StressOptions& opts, const TrafficPlan& plan, bsp::StopPredicate done,
                      bsp::heap::SealMode seal, StressResult& r);

}  // namespace tools::detail
