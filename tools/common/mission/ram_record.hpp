/**
 * @file ram_record.hpp
 * @brief The host's read of a task's declared record (bsp::RamRecord) out of its tile's RAM.
 *
 * What the host reports about the flight's state (summary.json, tests) it
 * reads as the flight left it in the tile's memory: the record is found by
 * its name among the tile's carves and copied out. A tile that holds no such
 * record (the task never started there, or the tile restarted and has not
 * carved it again) or one of another size is refused with the reason.
 */
#pragma once

#include "bsp_tile64/api/memory.hpp"
#include "bsp_tile64/api/port.hpp"

#include <cstddef>
#include <cstdint>
#include <span>
#include <string>

namespace tools {

/** What a read of a record found. */
enum class RecordRead : std::uint8_t {
  kOk,
  kNoTile,     ///< the tile is not on the chip
  kNoRecord,   ///< the tile holds no carve by that name (stacks are not records)
  kWrongSize,  ///< the carve is not the reader's size: another type
};

/**
 * Copies the bytes of the carve named @p name on @p tile into @p out, which
 * is left alone unless kOk. Allocates nothing: the flight loop reads with the heap sealed.
 */
RecordRead copy_ram_record(bsp::TileId tile, const char* name, std::span<std::byte> out) noexcept;

/** copy_ram_record() with the reason in @p error (naming the tile and the record) when it is not kOk. */
bool read_ram_record(bsp::TileId tile, const char* name, std::span<std::byte> out, std::string& error);

/** Reads record @p rec of @p tile into @p out (copy_ram_record); @p out is left alone unless kOk. */
template <class T>
RecordRead try_read_record(bsp::TileId tile, const bsp::RamRecord<T>& rec, T& out) noexcept {
  return copy_ram_record(tile, rec.name, std::as_writable_bytes(std::span<T, 1>(&out, 1U)));
}

/** Reads record @p rec of @p tile into @p out (read_ram_record); false with the reason in @p error. */
template <class T>
bool read_record(bsp::TileId tile, const bsp::RamRecord<T>& rec, T& out, std::string& error) {
  return read_ram_record(tile, rec.name, std::as_writable_bytes(std::span<T, 1>(&out, 1U)), error);
}

}  // namespace tools
