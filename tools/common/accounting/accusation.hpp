/**
 * @file accusation.hpp
 * @brief Whom a flight event accuses, and of what: its table's class (fdir/event_ids.hpp,
 *        trn/events.hpp), refined by the event's own fields where one id can say two things.
 *
 * The host's join reads every event through accusation_of(): a detection is
 * credited only to an accusation of the fault's tile with a class its kind
 * allows (docs/FDIR.md, "The join"). The refinements, each from a field the
 * event's row documents:
 *   - tmr_outvoted with b = 2 (the replica's output missing) accuses its core of
 *     silence; with b = 1 (different), 3 (its solution fails its CRC) or 4 (missing
 *     because it refused its own state and said so) of a wrong result;
 *   - coarse_band_redone accuses the band's tile of a wrong result for causes 3
 *     (its own checks failed) and 4 (its copy differs from its digest), suspects
 *     it for cause 2 (no answer in time) and accuses nobody for cause 1 (not sent);
 *   - tile_rebooted accuses a crash for a boot nobody commanded, the core's
 *     silence for a boot by its own watchdog, and nobody for a commanded reset;
 *   - tmr_no_majority accuses each replica its mask names as different.
 * A field that does not name a tile (kUnknown, a tile beyond the chip) accuses nobody.
 */
#pragma once

#include "bsp_tile64/api/memory.hpp"
#include "bsp_tile64/api/port.hpp"
#include "fdir/event_ids.hpp"
#include "fdir/event_log.hpp"
#include "tools/common/accounting/event_tables.hpp"
#include "trn/events.hpp"

#include <array>
#include <cstdint>

namespace tools {

/** What an event accuses: a class and up to three tiles. */
struct Accusation {
  fdir::Diagnosis diagnosis = fdir::Diagnosis::kNone;
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
constexpr bool is_diagnosis(fdir::Diagnosis diagnosis) noexcept {
  return diagnosis != fdir::Diagnosis::kNone && diagnosis != fdir::Diagnosis::kSuspicion;
}

namespace detail {
constexpr void add_tile(Accusation& acc, std::uint32_t field) noexcept {
  if (field < bsp::kMaxTiles && acc.count < acc.tiles.size() && !acc.names(static_cast<bsp::TileId>(field))) {
    acc.tiles[acc.count] = static_cast<bsp::TileId>(field);
    ++acc.count;
  }
}

constexpr fdir::Diagnosis refined(const fdir::Event& e, fdir::Diagnosis table) noexcept {
  switch (event_code(e.id)) {
    case event_code(trn::ev::kTmrOutvoted):
      return e.b == 2U ? fdir::Diagnosis::kCoreSilent : fdir::Diagnosis::kWrongResult;
    case event_code(trn::ev::kCoarseBandRedone):
      return e.cause == 3U || e.cause == 4U ? fdir::Diagnosis::kWrongResult
             : e.cause == 2U                ? fdir::Diagnosis::kSuspicion
                                            : fdir::Diagnosis::kNone;
    case event_code(fdir::EventId::kTileRebooted):
      return e.cause == static_cast<std::uint32_t>(bsp::BootCause::kCommand)    ? fdir::Diagnosis::kNone
             : e.cause == static_cast<std::uint32_t>(bsp::BootCause::kWatchdog) ? fdir::Diagnosis::kCoreSilent
                                                                                 : fdir::Diagnosis::kCoreCrashed;
    default:
      return table;
  }
}
}  // namespace detail

/** Whom @p e accuses, and of what. */
constexpr Accusation accusation_of(const fdir::Event& e) noexcept {
  Accusation acc;
  const fdir::EventInfo* info = tools::event_info(e.id);
  if (info == nullptr) {
    return acc;
  }
  acc.diagnosis = detail::refined(e, info->diagnosis);
  if (acc.diagnosis == fdir::Diagnosis::kNone) {
    return acc;
  }
  switch (info->accused) {
    case fdir::Accused::kNobody: break;
    case fdir::Accused::kSubject: detail::add_tile(acc, e.subject); break;
    case fdir::Accused::kCause: detail::add_tile(acc, e.cause); break;
    case fdir::Accused::kWriter: detail::add_tile(acc, e.tile); break;
    case fdir::Accused::kSubjectAndCause:
      detail::add_tile(acc, e.subject);
      detail::add_tile(acc, e.cause);
      break;
    case fdir::Accused::kReplicas:
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
constexpr const char* diagnosis_name(fdir::Diagnosis d) noexcept {
  switch (d) {
    case fdir::Diagnosis::kNone: return "none";
    case fdir::Diagnosis::kSuspicion: return "suspicion";
    case fdir::Diagnosis::kCoreSilent: return "core_silent";
    case fdir::Diagnosis::kCoreCrashed: return "core_crashed";
    case fdir::Diagnosis::kWrongResult: return "wrong_result";
    case fdir::Diagnosis::kMemoryUpset: return "memory_upset";
    case fdir::Diagnosis::kSwitch: return "switch";
    case fdir::Diagnosis::kLink: return "link";
    case fdir::Diagnosis::kSwitchOrLink: return "switch_or_link";
    case fdir::Diagnosis::kPacket: return "packet";
  }
  return "?";
}

}  // namespace tools
