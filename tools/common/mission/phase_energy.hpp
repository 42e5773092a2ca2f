/**
 * @file phase_energy.hpp
 * @brief Energy per mission phase: the board's meter snapshotted at each phase boundary, exactly.
 *
 * The phases are a plain list of windows (a name and a start time; the first
 * starts at 0 s, each lasts until the next starts, the last until the end of
 * the flight). Each boundary is rounded to the board's quantum (1 ms in the
 * mission): the flight loop asks next_boundary() and runs the board no
 * further than it in that step, so the snapshot is taken at the boundary's
 * cycle exactly (runs cut at quantum multiples keep their barriers: the
 * emulation, and its trace hash, are those of an uncut run). A caller that
 * steps over a boundary gets its snapshot at the end of that step instead
 * (taken_cycle() says when). Phase figures are differences of integer cycle
 * counts per tile and state, turned into joules only when read, so the phases'
 * cycles add up to the flight's exactly and their joules to its joules up to
 * the rounding of a sum of doubles.
 *
 * init() takes all the memory; step() and finish() allocate nothing (the
 * image calls step() with the heap sealed).
 */
#pragma once

#include "bsp_tile64/emu/board.hpp"
#include "bsp_tile64/emu/energy.hpp"
#include "bsp_tile64/api/port.hpp"
#include "tools/common/mission/run_folder.hpp"

#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace tools {

/** One phase as the energy accounting sees it. */
struct PhaseWindow {
  std::string name;
  double start_s = 0.0;  ///< emulated seconds from the start of the flight
};

class PhaseEnergy {
 public:
  /**
   * Checks @p windows and takes the memory of every snapshot. The windows must
   * be non-empty, the first start at 0 s, the names be non-empty and differ, and
   * the starts, rounded to the nearest multiple of @p quantum_cycles at
   * @p clock_hz, increase. The meter reads the first @p tiles tiles (at most
   * bsp::kMaxTiles) with the model @p model. Call it at board time 0.
   * @return false with the reason in @p error.
   */
  bool init(std::vector<PhaseWindow> windows, const bsp::PowerModel& model, bsp::Cycles quantum_cycles,
            std::uint32_t tiles, std::string& error);

  /** The first boundary after @p now, in cycles; UINT64_MAX when none is left. */
  [[nodiscard]] bsp::Cycles next_boundary(bsp::Cycles now) const noexcept;

  /** Takes the snapshot of every boundary reached at board time @p now (between runs). Allocates nothing. */
  void step(bsp::Cycles now) noexcept;

  /** Closes the flight at board time @p now: phases that had not started end up empty. Allocates nothing. */
  void finish(bsp::Cycles now) noexcept;

  [[nodiscard]] std::size_t phases() const noexcept { return windows_.size(); }
  [[nodiscard]] const PhaseWindow& window(std::size_t phase) const { return windows_.at(phase); }
  /** The boundary's cycle: the phase's start rounded to the quantum. */
  [[nodiscard]] bsp::Cycles start_cycle(std::size_t phase) const { return starts_.at(phase); }
  /** The board time at which the phase's start was snapshotted (start_cycle() when the loop cut its step there). */
  [[nodiscard]] bsp::Cycles taken_cycle(std::size_t phase) const { return taken_at_.at(phase); }
  [[nodiscard]] bool finished() const noexcept { return finished_; }

  /** Cycles per state of @p tile in @p phase (after finish(); before, what has been closed). */
  [[nodiscard]] bsp::StateCycles tile_cycles(std::size_t phase, bsp::TileId tile) const;
  /** Joules of @p tile in @p phase. */
  [[nodiscard]] double tile_j(std::size_t phase, bsp::TileId tile) const;
  /** Joules of the whole chip in @p phase, summed in tile order. */
  [[nodiscard]] double phase_j(std::size_t phase) const;

 private:
  using Snapshot = std::array<bsp::StateCycles, bsp::kMaxTiles>;
  void take(std::size_t index, bsp::Cycles now) noexcept;

  std::vector<PhaseWindow> windows_;
  std::vector<bsp::Cycles> starts_;
  std::vector<bsp::Cycles> taken_at_;  ///< per snapshot: board time it was taken
  std::vector<Snapshot> snaps_;        ///< one per phase start, then the end
  std::size_t taken_ = 0U;             ///< snapshots taken so far
  std::uint32_t tiles_ = 0U;
  bsp::PowerModel model_{};
  bool finished_ = false;
};

/**
 * Runs the board to @p target, stopping at each of @p energy's boundaries on
 * the way to snapshot the meter there (PhaseEnergy::step after every run).
 * The cuts are quantum multiples, so the emulation is that of one run_for().
 * @return the last run's result (a run stopped early ends the step there).
 */
bsp::RunResult run_with_phases(bsp::Cycles target, PhaseEnergy& energy) noexcept;

/**
 * Adds the flight's energy figures to @p s (after finish()): energy_j (the
 * whole chip, whole flight, from the board's meter), mean_power_w (over
 * @p emulated_s), and the objects energy_j_by_phase (phase name -> J),
 * energy_j_by_role (role -> J over the tiles @p tile_roles names, in order of
 * first appearance) and energy_j_by_state (off, booting, idle, active -> J).
 */
void add_energy_summary(const PhaseEnergy& phases, const std::vector<std::string>& tile_roles, double emulated_s,
                        Summary& s);

}  // namespace tools
