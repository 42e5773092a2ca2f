/**
 * @file fdir_join.hpp
 * @brief The host side of fault management: collects the flight event rings into the run's
 *        event log and tells each event as text (the join to the injector's ground truth:
 *        tools/common/accounting/fault_account.hpp).
 *
 * The host decides nothing for the flight code: a fault counts as detected or
 * recovered only through an event a flight layer wrote. The collector reads
 * every tile's ring during the run (no allocation: its buffer is taken at
 * construction) and keeps the tile states the live view shows.
 */
#pragma once

#include "bsp_tile64/faults/fault_injector.hpp"
#include "bsp_tile64/api/memory.hpp"
#include "fdir/event_log.hpp"
#include "tools/common/mission/run_folder.hpp"

#include <array>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

namespace tools {

/** Health of a tile as the flight events tell it (the live view and tile_map.csv). */
enum class TileHealth : std::uint8_t { kOk = 0, kSuspect = 1, kRecovered = 2, kFailed = 3 };

/** "ok", "suspect", "recovered", "failed". */
const char* tile_health_name(TileHealth h) noexcept;

/**
 * One-line text of a flight event (no newline) into @p out, NUL-terminated, cut to fit; no allocation.
 * E.g. "switch_failed: switch of tile 44 declared failed (2 neighbours agree): map version 2". @return its length.
 */
std::size_t describe_flight_event(const fdir::Event& e, std::span<char> out) noexcept;
/** The same as a string. */
std::string describe_flight_event(const fdir::Event& e);

class FlightEventCollector {
 public:
  /** Takes room for @p capacity events now, so poll() never allocates. */
  explicit FlightEventCollector(std::size_t capacity = std::size_t{1} << 17U);

  /** Reads every tile's new events (in tile order, then write order) into the list and @p log. */
  void poll(double clock_hz, EventLog& log) noexcept;

  [[nodiscard]] std::span<const fdir::Event> events() const noexcept { return {events_.data(), events_.size()}; }
  /** Events overwritten in a ring before they were read, or beyond the collector's room. */
  [[nodiscard]] std::uint64_t lost() const noexcept { return lost_; }
  [[nodiscard]] std::uint32_t frames() const noexcept { return frames_; }
  [[nodiscard]] std::uint64_t matches() const noexcept { return matches_; }
  [[nodiscard]] const std::array<TileHealth, bsp::kMaxTiles>& tile_health() const noexcept { return health_; }

 private:
  void take(const fdir::Event& e) noexcept;

  std::vector<fdir::Event> events_;
  std::array<std::uint64_t, bsp::kMaxTiles> next_{};
  std::array<TileHealth, bsp::kMaxTiles> health_{};
  std::uint64_t lost_ = 0U;
  std::uint32_t frames_ = 0U;
  std::uint64_t matches_ = 0U;
};

}  // namespace tools
