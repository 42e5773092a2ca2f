/**
 * @file assert.hpp
 * @brief Flight assertions: a failed check writes an event and asks for the tile's recovery; it
 *        never aborts and never continues silently.
 *
 * Use as `if (!fdir::check(cond, kMyCheckId)) { return Error::kX; }`: the
 * caller takes its error path, the event log has kAssertFailed with the check's
 * id and line, and the tile's recovery request is raised for the health layer
 * (recovery_requested()). Ids are per module, documented with the check.
 */
#pragma once

#include "bsp_tile64/api/port.hpp"

#include <cstdint>

namespace fdir {

/** Records a failed check of @p id at @p line on the current tile and raises its recovery request. [task|isr] */
void assert_failed(std::uint32_t id, std::uint32_t line) noexcept;

/** @return @p cond; when false, assert_failed(id, line of the call). [task|isr] */
[[nodiscard]] inline bool check(bool cond, std::uint32_t id,
                                std::uint32_t line = static_cast<std::uint32_t>(__builtin_LINE())) noexcept {
  if (!cond) {
    assert_failed(id, line);
  }
  return cond;
}

/** Failed checks on @p tile since boot, and whether it asked for recovery. [task|host] */
std::uint32_t recovery_requested(bsp::TileId tile) noexcept;

/** The tile's recovery was taken care of (the health layer restarted it). [task|host] */
void recovery_clear(bsp::TileId tile) noexcept;

}  // namespace fdir
