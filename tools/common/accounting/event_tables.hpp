/**
 * @file event_tables.hpp
 * @brief Every declared flight event, for the host: fdir's table (fdir/event_ids.hpp) and the
 *        application's (trn/events.hpp), each id in one of them.
 */
#pragma once

#include "fdir/event_ids.hpp"
#include "trn/events.hpp"

#include <array>
#include <cstdint>
#include <span>
#include <vector>

namespace tools {

/** The row of @p id in fdir's table or the application's; nullptr for an id neither declares. */
constexpr const fdir::EventInfo* event_info(fdir::EventId id) noexcept {
  const fdir::EventInfo* info = fdir::event_info(id);
  return info != nullptr ? info : trn::event_info(id);
}

/** Both tables, to go through every declared event. */
inline constexpr std::array<std::span<const fdir::EventInfo>, 2> kEventTables{
    std::span<const fdir::EventInfo>(fdir::kEventTable), std::span<const fdir::EventInfo>(trn::kEventTable)};

/**
 * An id as a number, for a switch over the ids of both tables (fdir's enum does not
 * list the application's ids, so a switch over the enum would take them for strays).
 */
constexpr std::uint16_t event_code(fdir::EventId id) noexcept { return static_cast<std::uint16_t>(id); }

/** Every declared event, fdir's table then the application's, in one list. */
inline std::vector<fdir::EventInfo> all_events() {
  std::vector<fdir::EventInfo> v;
  for (const std::span<const fdir::EventInfo> t : kEventTables) {
    v.insert(v.end(), t.begin(), t.end());
  }
  return v;
}

/** How many events the two tables declare. */
constexpr std::size_t event_count() noexcept { return fdir::kEventTable.size() + trn::kEventTable.size(); }

}  // namespace tools
