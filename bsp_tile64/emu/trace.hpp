/**
 * @file trace.hpp
 * @brief The board trace: every event folded into a running 64-bit hash, a ring of recent events.
 *
 * The final hash identifies a run bit for bit: two runs with the same
 * configuration and seed produce the same sequence of (time, tile, kind, a, b)
 * and so the same hash. Upper layers add their events through bsp::trace()
 * (port.hpp) with kinds from their own range.
 */
#pragma once

#include "bsp_tile64/api/port.hpp"

#include <cstddef>
#include <cstdint>
#include <span>

namespace bsp {

/** Board trace kinds (range 0x0000-0x0FFF). Append only: values are part of every hash. */
enum class BoardEvent : std::uint16_t {
  kInit = 0x001,            ///< a = seed, b = tile count
  kPowerOn = 0x002,         ///< a = boot cycle
  kPowerOff = 0x003,
  kBoot = 0x004,            ///< a = boot count of the tile
  kReset = 0x005,           ///< a = ResetReason
  kIrqTaken = 0x006,        ///< a = Irq
  kIrqDropped = 0x007,      ///< a = Irq (no handler installed)
  kWatchdogExpired = 0x008, ///< a = monitor tile, b = reset on expiry
  kHang = 0x009,
  kHalt = 0x00A,            ///< a context's entry returned: the tile stops
  kEventLate = 0x00B,       ///< a = event cycle (a fixed-capacity list overflowed)
  kFault = 0x00C,           ///< a = FaultKind, b = fault log index
  kSdcApplied = 0x00D,      ///< a = fault log index, b = bit index in the published value
  kQueueFull = 0x00E,       ///< a = event cycle (the global event queue is full; event lost)
  kBootFailed = 0x00F,      ///< a = MemError of the boot stack carve
  kDeviceSelect = 0x010,    ///< the cross-strap moved the devices to this tile: a = the tile before, b = IMU samples stranded
  kMonitorSelect = 0x011,   ///< the watchdog interrupt line goes to this tile from now: a = the tile before
};

/** One trace event. */
struct TraceEvent {
  Cycles time;
  TileId tile;
  std::uint16_t kind;
  std::uint64_t a;
  std::uint64_t b;
};

/** Events kept in the debugging ring. */
inline constexpr std::size_t kTraceRingSize = 256U;

/** Optional observer of every trace event (tools: event logs). Called synchronously. */
using TraceSink = void (*)(const TraceEvent& ev);

/** Records an event with explicit time and tile (board internals and tools). [host|task|isr] */
void trace_record(Cycles time, TileId tile, std::uint16_t kind, std::uint64_t a, std::uint64_t b) noexcept;

/** Resets the hash, the count and the ring (board init does this). [host] */
void trace_reset() noexcept;

/** The running hash of every event so far. [host] */
std::uint64_t trace_hash() noexcept;

/** Number of events recorded since the last reset. [host] */
std::uint64_t trace_count() noexcept;

/**
 * Copies the most recent events, oldest first, into @p out.
 * @return the number copied: min(out.size(), events in the ring).
 */
std::size_t trace_recent(std::span<TraceEvent> out) noexcept;

/** Installs (or with nullptr removes) the trace sink. Survives trace_reset(). [host] */
void set_trace_sink(TraceSink sink) noexcept;

/** The hash before any event (what trace_reset() starts from): tools fold a dumped trace from it. */
std::uint64_t trace_initial_hash() noexcept;

/** The hash step, exposed for tests: folds one event into @p h. */
std::uint64_t trace_fold(std::uint64_t h, const TraceEvent& ev) noexcept;

}  // namespace bsp
