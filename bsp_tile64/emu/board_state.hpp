/**
 * @file board_state.hpp
 * @brief Board internals shared by the driver, the tile runtime, the context port and the injector.
 *
 * Not part of any public contract: only the board's own sources include it.
 */
#pragma once

#include "bsp_tile64/emu/board.hpp"
#include "bsp_tile64/emu/event_queue.hpp"
#include "bsp_tile64/api/port.hpp"
#include "bsp_tile64/emu/trace.hpp"

#include <array>
#include <cstddef>
#include <cstdint>

namespace bsp::detail {

/** Upper bound on the steps of one consume()/wait_for_interrupt() loop (a bounded-loop guard). */
inline constexpr std::uint64_t kMaxLoopSteps = 1ULL << 40U;
/** Interrupts dispatched by one dispatch call at most. */
inline constexpr std::uint32_t kMaxDispatch = 64U;

struct Tile {
  TileId id;
  Cycles time;
  Cycles boot_at;
  PowerState power;
  bool stopped;        ///< hang fault or returned context: contexts are not run
  bool reset_pending;  ///< a reset was requested while the tile was running
  ResetReason reset_reason;
  BootCause boot_cause;  ///< why the tile last booted (its reset-cause register)
  bool masked;
  std::uint32_t pending;  ///< bit per Irq
  IrqHandler handler;
  Cycles timer_period;  ///< 0: the timer is stopped
  Cycles timer_at;      ///< the timer's next expiry (while timer_period != 0)
  bool wd_armed;
  bool wd_reset;
  bool wd_failed;
  Cycles wd_timeout;
  Cycles wd_deadline;
  Context* current;  ///< the context the tile runs (nullptr: none)
  Context boot_ctx;
  std::byte* boot_stack;
  LocalEvents<kLocalEventCapacity> local;
  TileStats stats;
  /** Energy meter: cycles charged to each PowerState (index: the enum); they sum to time. */
  std::array<Cycles, kPowerStateCount> state_cycles;
  PowerState charged;  ///< energy meter: the state the tile's latest cycle was charged to
};

/**
 * Moves the tile's clock to @p to and charges the cycles it advances to
 * @p state for the energy meter. Every advance of a tile's time goes through
 * here, so the per-state cycles always sum to the tile's time. The meter only
 * observes: nothing on the board reads the counts back.
 */
inline void advance_to(Tile& t, PowerState state, Cycles to) noexcept {
  if (to > t.time) {
    t.state_cycles[static_cast<std::size_t>(state)] += to - t.time;
    t.charged = state;
  }
  t.time = to;
}

enum class Command : std::uint8_t { kPowerOn, kPowerOff, kReset, kHang, kMonitor };

struct DeferredCommand {
  Command cmd;
  TileId tile;
  ResetReason reason;
};

struct Board {
  BoardConfig config;
  TileId tiles;
  Cycles now;    ///< last barrier
  Cycles q_end;  ///< end of the running quantum
  TileId running = kNoTile;     ///< tile whose context runs (kNoTile: the driver, and before board_init)
  TileId processing = kNoTile;  ///< tile the driver is advancing in this quantum (kNoTile: none)
  bool in_barrier;
  bool stop_requested;
  std::uint64_t seq;
  std::uint64_t wd_expired;           ///< visible to watchdog_take_expired()
  std::uint64_t wd_expired_deferred;  ///< published at the next barrier
  std::array<std::uint32_t, kMaxTiles> irq_deferred;
  std::array<DeferredCommand, kMaxDeferredCommands> commands;
  std::size_t command_count;
  std::array<BarrierHook, kMaxBarrierHooks> hooks;
  std::size_t hook_count;
  EventHeap<kEventCapacity> queue;
  Context host_ctx;     ///< the driver's context
  Context scratch_ctx;  ///< where an abandoned context is "saved"
  std::array<Tile, kMaxTiles> tile;
};

/**
 * The one board, defined in board.cpp. Declared here so the accessors below
 * inline: the tile runtime asks for the running tile at every kernel call.
 */
extern Board g_board;

/** The one board. */
inline Board& board() noexcept { return g_board; }

/** The running tile, or nullptr on the host. */
inline Tile* running_tile() noexcept { return g_board.running == kNoTile ? nullptr : &g_board.tile[g_board.running]; }

/** True if @p tile is inside the profile's grid. */
inline bool valid_tile(TileId tile) noexcept { return tile < g_board.tiles; }

/** Time for trace events and now(): the running tile's time, else board time. */
inline Cycles current_time() noexcept {
  const Tile* t = running_tile();
  return t != nullptr ? t->time : g_board.now;
}

/** Board trace helper. */
void board_trace(Cycles time, TileId tile, BoardEvent kind, std::uint64_t a, std::uint64_t b) noexcept;

/** Delivers due events and the watchdog (tile runtime). Used by the driver for passive tiles too. */
void deliver_due(Tile& t) noexcept;

/** Queues an event: into the processed tile's list if due this quantum, else the global queue. */
bool push_event(const Event& e) noexcept;

/** Earliest cycle something happens on the tile by itself (event, watchdog, boot); UINT64_MAX if never. */
Cycles next_wake(const Tile& t) noexcept;

/** Raw switch with ASan fiber annotations; records nothing about tiles. */
void switch_raw(Context& from, Context& to) noexcept;

/** Leaves the running context for good (it is never resumed) and resumes @p to. */
[[noreturn]] void switch_abandon(Context& to) noexcept;

/** Marks ASan shadow of [p, p + bytes) clean (reused stacks); no-op without ASan. */
void unpoison(std::byte* p, std::size_t bytes) noexcept;

/** Hooks from the context port into the board. */
void on_context_start() noexcept;
[[noreturn]] void on_context_return() noexcept;

/** Fault injector hooks called by the board. */
void injector_reset(std::uint64_t seed) noexcept;
void injector_barrier(Cycles q_start, Cycles q_end) noexcept;

}  // namespace bsp::detail
