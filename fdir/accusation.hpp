/**
 * @file accusation.hpp
 * @brief Whom a flight event accuses, and of what: the table's class (fdir/event_ids.hpp), refined
 *        by the event's own fields where one id can say two things.
 *
 * The host's join reads every event through accusation_of(): a detection is
 * credited only to an accusation of the fault's tile with a class its kind
 * allows (docs/FDIR.md, "The join"). The refinements, each from a field the
 * event's row in event_ids.hpp documents:
 *   - tmr_outvoted with b = 2 (the replica's output missing) accuses its core of
 *     silence, with b = 1 (different) of a wrong result;
 *   - coarse_band_redone accuses the band's tile of a wrong result for causes 3
 *     (its own checks failed) and 4 (its copy differs from its digest), suspects
 *     it for cause 2 (no answer in time) and accuses nobody for cause 1 (not sent);
 *   - tile_rebooted accuses a crash for a boot nobody commanded, the core's
 *     silence for a boot by its own watchdog, and nobody for a commanded reset;
 *   - tmr_no_majority accuses each replica its mask names as different.
 * A field that does not name a tile (kUnknown, a tile beyond the chip) accuses nobody.
 */
#pragma once

#include "bsp_tile64/memory.hpp"
#include "bsp_tile64/port.hpp"
#include "fdir/event_ids.hpp"
#include "fdir/event_log.hpp"

#include <array>
#include <cstdint>

namespace fdir {

/** What an event accuses: a class and up to three tiles. */
struct Accusation {
  Diagnosis diagnosis = Diagnosis::kNone;
  std::array<bsp::TileId, 3> tiles{bsp::kNoTile, bsp::kNoTile, bsp::kNoTile};
  std::uint8_t count = 0U;  ///< tiles named (0: the event accuses nobody)

  [[nodiscard]] constexpr bool names(bsp::TileId t) const noexcept {
    for (std::uint32_t i = 0; i < count; ++i) {
      if (tiles[i] == t) {
        return true;
      }
    }
    return false;
  }
};

/** Whether @p diagnosis is a diagnosis (an accusation can be credited, wrong, or a false alarm), not a suspicion or nothing. */
constexpr bool is_diagnosis(Diagnosis diagnosis) noexcept {
  return diagnosis != Diagnosis::kNone && diagnosis != Diagnosis::kSuspicion;
}

namespace detail {
constexpr void add_tile(Accusation& acc, std::uint32_t field) noexcept {
  if (field < bsp::kMaxTiles && acc.count < acc.tiles.size() && !acc.names(static_cast<bsp::TileId>(field))) {
    acc.tiles[acc.count] = static_cast<bsp::TileId>(field);
    ++acc.count;
  }
}

constexpr Diagnosis refined(const Event& e, Diagnosis table) noexcept {
  switch (e.id) {
    case EventId::kTmrOutvoted:
      return e.b == 2U ? Diagnosis::kCoreSilent : Diagnosis::kWrongResult;
    case EventId::kCoarseBandRedone:
      return e.cause == 3U || e.cause == 4U ? Diagnosis::kWrongResult
             : e.cause == 2U                ? Diagnosis::kSuspicion
                                            : Diagnosis::kNone;
    case EventId::kTileRebooted:
      return e.cause == static_cast<std::uint32_t>(bsp::BootCause::kCommand)    ? Diagnosis::kNone
             : e.cause == static_cast<std::uint32_t>(bsp::BootCause::kWatchdog) ? Diagnosis::kCoreSilent
                                                                                 : Diagnosis::kCoreCrashed;
    default:
      return table;
  }
}
}  // namespace detail

/** Whom @p e accuses, and of what. */
constexpr Accusation accusation_of(const Event& e) noexcept {
  Accusation acc;
  const EventInfo* info = event_info(e.id);
  if (info == nullptr) {
    return acc;
  }
  acc.diagnosis = detail::refined(e, info->diagnosis);
  if (acc.diagnosis == Diagnosis::kNone) {
    return acc;
  }
  switch (info->accused) {
    case Accused::kNobody: break;
    case Accused::kSubject: detail::add_tile(acc, e.subject); break;
    case Accused::kCause: detail::add_tile(acc, e.cause); break;
    case Accused::kWriter: detail::add_tile(acc, e.tile); break;
    case Accused::kSubjectAndCause:
      detail::add_tile(acc, e.subject);
      detail::add_tile(acc, e.cause);
      break;
    case Accused::kReplicas:
      for (std::uint32_t i = 0; i < 3U; ++i) {
        if (((e.a >> i) & 1U) != 0U) {
          detail::add_tile(acc, (e.b >> (8U * (i + 1U))) & 0xFFU);
        }
      }
      break;
  }
  return acc;
}

/** "none", "suspicion", "core_silent", "core_crashed", "wrong_result", "memory_upset", "switch", "link", "switch_or_link", "packet". */
constexpr const char* diagnosis_name(Diagnosis d) noexcept {
  switch (d) {
    case Diagnosis::kNone: return "none";
    case Diagnosis::kSuspicion: return "suspicion";
    case Diagnosis::kCoreSilent: return "core_silent";
    case Diagnosis::kCoreCrashed: return "core_crashed";
    case Diagnosis::kWrongResult: return "wrong_result";
    case Diagnosis::kMemoryUpset: return "memory_upset";
    case Diagnosis::kSwitch: return "switch";
    case Diagnosis::kLink: return "link";
    case Diagnosis::kSwitchOrLink: return "switch_or_link";
    case Diagnosis::kPacket: return "packet";
  }
  return "?";
}

}  // namespace fdir
