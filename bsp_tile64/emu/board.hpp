/**
 * @file board.hpp
 * @brief The emulated board's host-side API: configuration, the deterministic driver, power, events.
 *
 * One static board instance exists (no heap). An image fills a BoardConfig
 * (the single registration point of per-tile boot entries), calls board_init(),
 * then run_for()/run_until(). Flight code talks to the board only through
 * port.hpp; this header is for images, tools, tests, the network model and the
 * fault-management layer (power control).
 *
 * Execution model (see docs/BOARD.md): time advances in quanta; at every
 * quantum barrier the board applies deferred cross-tile effects, runs the fault
 * injector and the registered barrier hooks, and hands each tile the events due
 * in the quantum; then tiles run one after the other, in id order, until their
 * local time reaches the quantum end.
 */
#pragma once

#include "bsp_tile64/emu/event_queue.hpp"
#include "bsp_tile64/api/memory.hpp"
#include "bsp_tile64/api/port.hpp"
#include "bsp_tile64/api/power.hpp"
#include "bsp_tile64/emu/profile.hpp"

#include <array>
#include <cstddef>
#include <cstdint>

namespace bsp {

/** Capacity of the global event queue. */
inline constexpr std::size_t kEventCapacity = 2048U;
/** Events one tile can hold for the current quantum (more are delivered a quantum late, traced). */
inline constexpr std::size_t kLocalEventCapacity = 32U;
/** Barrier hooks (network model, monitors). */
inline constexpr std::size_t kMaxBarrierHooks = 8U;
/** Power commands issued from tiles, applied at the next barrier. */
inline constexpr std::size_t kMaxDeferredCommands = 64U;

struct BoardConfig {
  ChipProfile profile = kTile64;
  Cycles tick_cycles = kTile64.cycles_per_ms();     ///< kernel tick period (1 ms)
  Cycles quantum_cycles = kTile64.cycles_per_ms();  ///< 1 <= quantum <= tick
  Cycles boot_delay_cycles = kTile64.cycles_per_ms();  ///< power-on or reset to boot entry
  std::uint64_t seed = 1U;
  TileId monitor_tile = 0U;  ///< receives Irq::kWatchdog; kNoTile for none
  std::size_t boot_stack_bytes = std::size_t{32U} * 1024U;  ///< carved from the tile's RAM at every boot
  std::uint64_t powered_at_start = ~0ULL;      ///< bit t: tile t is switched on by board_init()
  std::array<BootEntry, kMaxTiles> boot{};     ///< per-tile boot entry; nullptr: the tile idles
};

/** A configuration for @p profile with a 1 ms tick and quantum and a 1 ms boot delay. */
BoardConfig default_config(const ChipProfile& profile) noexcept;

/**
 * Initializes the one board: resets every tile (state, time 0, RAM region emptied
 * with region_reset), the event queue, barrier hooks, the trace and the fault
 * injector (seeded from config.seed); switches on the tiles of powered_at_start.
 * Any contexts of a previous board are abandoned.
 * @return kBadConfig if tiles() > kMaxTiles or is 0, quantum is 0 or > tick,
 *         boot_stack_bytes < kMinStackBytes or not a multiple of 16, or the
 *         monitor tile is outside the grid (and not kNoTile). [host]
 */
BoardError board_init(const BoardConfig& config) noexcept;

/** The active configuration. [host|task] */
const BoardConfig& board_config() noexcept;

enum class StopReason : std::uint8_t {
  kTimeReached,  ///< the requested duration ran out
  kPredicate,    ///< the stop predicate returned true at a barrier
  kRequested,    ///< request_stop() was called
};

struct RunResult {
  Cycles end_cycle;  ///< board time at return (always a barrier)
  StopReason reason;
};

/** Runs the board for @p cycles cycles from its current time. [host] */
RunResult run_for(Cycles cycles) noexcept;

/** Checked at every barrier; true stops the run there. */
using StopPredicate = bool (*)(void* arg);

/** Runs until @p stop (may be nullptr) returns true, request_stop(), or @p max_cycles elapsed. [host] */
RunResult run_until(StopPredicate stop, void* arg, Cycles max_cycles) noexcept;

/** Asks the driver to stop at the next barrier. [host|task|isr] */
void request_stop() noexcept;

/** Board time: the last barrier (between runs: the end of the last run). [host] */
Cycles board_time() noexcept;

/** A tile's local time. 0 for a bad id. [host] */
Cycles tile_time(TileId tile) noexcept;

enum class PowerState : std::uint8_t {
  kOff,      ///< not clocked; no contexts, no timer, no watchdog
  kBooting,  ///< switched on or reset, waiting for its boot delay
  kActive,   ///< running a context
  kIdle,     ///< in wait_for_interrupt()
};
/** Number of PowerState values (the energy meter keeps a cycle count per state: energy.hpp). */
inline constexpr std::size_t kPowerStateCount = 4U;
static_assert(static_cast<std::size_t>(PowerState::kIdle) + 1U == kPowerStateCount, "one count per state");

/** Power state of a tile (kOff for a bad id). [host] */
PowerState power_state(TileId tile) noexcept;

/** True if the tile is stopped by a hang fault or a returned context. [host] */
bool tile_stopped(TileId tile) noexcept;

/** Counters of one tile (for tests and reports; the energy meter is in energy.hpp). */
struct TileStats {
  std::uint32_t boots;
  std::uint32_t resets;
  std::uint32_t watchdog_expiries;
  std::uint64_t irqs_taken;
  Cycles active_cycles;  ///< cycles charged by consume() (not idle, not booting; the meter's split: energy.hpp)
};
TileStats tile_stats(TileId tile) noexcept;

/**
 * Schedules an event at exactly @p cycle on @p tile: @p callback (may be nullptr)
 * runs with @p arg, then @p irq (Irq::kCount for none) becomes pending.
 * An event in the past, or for another tile within the running quantum, is
 * delivered at the tile's next barrier. [host|task|isr]
 * @return kBadTile, kFull (queue full), kOk.
 */
BoardError schedule_event(Cycles cycle, TileId tile, Irq irq, EventCallback callback, std::uint64_t arg) noexcept;

/** Called at every barrier, in registration order, with the barrier cycle. */
using BarrierHook = void (*)(Cycles barrier_cycle);

/** Registers a barrier hook (cleared by board_init). @return kFull when all slots are used. [host] */
BoardError add_barrier_hook(BarrierHook hook) noexcept;

/** Deepest use of the tile's boot stack since its last boot, from stack painting. [host] */
std::size_t boot_stack_high_water(TileId tile) noexcept;

/** Why a tile was reset (trace argument of BoardEvent::kReset). */
enum class ResetReason : std::uint8_t { kCommand = 1, kWatchdog = 2, kFault = 3 };

/** Stops a tile's progress (hang fault): its contexts are not run; timer and watchdog go on. [host|isr] */
BoardError hang_tile(TileId tile) noexcept;

/** Watchdog failure fault: while @p failed, the tile's watchdog never expires. [host|isr] */
BoardError set_watchdog_failed(TileId tile, bool failed) noexcept;

/** Resets a tile for a given reason (fault injector, watchdog). [host|isr] */
BoardError reset_tile_for(TileId tile, ResetReason reason) noexcept;

}  // namespace bsp
