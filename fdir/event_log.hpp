/**
 * @file event_log.hpp
 * @brief The flight event log: a fixed ring per tile of events with id, severity, emulated time,
 *        tile, subject and cause, in shared DDR where the mission log collector reads them.
 *
 * Every detection, isolation and recovery step of every layer is written here
 * by the code that knows it (fdir::report). Layers below fdir (the messaging
 * endpoint) report through a sink they are configured with (fdir::ft_event_sink
 * in udn terms), never by including this header.
 *
 * Storage: one carve in the shared DDR region holds a ring of kRingEvents per
 * tile (event_log_init, before boot). A tile that restarts keeps its ring: the
 * log is the mission's, like a telemetry buffer. When a ring is full the
 * oldest event is overwritten and counted, so nothing vanishes without a
 * trace. Each event also goes into the board trace (and so the trace hash).
 * The host reads the rings ([host] calls) to write events.log and the summary.
 */
#pragma once

#include "bsp_tile64/api/port.hpp"
#include "fdir/event_ids.hpp"

#include <cstdint>

namespace fdir {

/** Events each tile's ring holds. The host collects every 0.1 s; a tile writes far fewer per collection. */
inline constexpr std::uint32_t kRingEvents = 256U;

/** One flight event (32 bytes). */
struct Event {
  bsp::Cycles cycle;       ///< the writing tile's time
  EventId id;
  Severity severity;
  std::uint8_t steps;      ///< Step bits, from the table
  bsp::TileId tile;        ///< the tile that wrote it
  std::uint32_t subject;   ///< what it is about (a tile, a version, a monitor); see the id
  std::uint32_t cause;     ///< why, or a second party; see the id
  std::uint32_t a;
  std::uint32_t b;
};

enum class LogError : std::uint8_t { kOk, kNoRoom, kNotInit, kBadTile };

/** Carves the rings in DDR and empties them (after bsp::board_init). [host] */
[[nodiscard]] LogError event_log_init() noexcept;

/**
 * Writes an event declared by @p info (a layer's own table: fdir's, or the application's,
 * trn/events.hpp) of the current tile at its current time. [task|isr]
 */
void report(const EventInfo& info, std::uint32_t subject, std::uint32_t cause, std::uint32_t a = 0U,
            std::uint32_t b = 0U) noexcept;

/** An event id no table declares, written as kAssertFailed about that id (cause), never dropped. [task|isr] */
void report_unknown(EventId id, std::uint32_t subject, std::uint32_t a = 0U, std::uint32_t b = 0U) noexcept;

/**
 * Writes an event of the current tile at its current time. An id missing from
 * the table is written as kAssertFailed about that id (never dropped). [task|isr]
 */
void report(EventId id, std::uint32_t subject, std::uint32_t cause, std::uint32_t a = 0U,
            std::uint32_t b = 0U) noexcept;

/** Events written by @p tile since init (including overwritten ones). [host] */
std::uint64_t event_log_written(bsp::TileId tile) noexcept;

/**
 * Event number @p index (0-based, in write order) of @p tile.
 * @return false if not written yet or already overwritten. [host]
 */
bool event_log_read(bsp::TileId tile, std::uint64_t index, Event* out) noexcept;

}  // namespace fdir
