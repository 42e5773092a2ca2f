/**
 * @file ram_record.cpp
 * @brief The host's read of a declared record out of a tile's RAM (see ram_record.hpp).
 */
#include "tools/common/mission/ram_record.hpp"

#include <algorithm>
#include <cstring>

namespace tools {
namespace {

/** The carve of @p tile named @p name that is not a stack (a task may carve its state under its own name). */
const bsp::CarveRecord* find_record(bsp::TileId tile, const char* name) noexcept {
  for (const bsp::CarveRecord& c : bsp::region_carves(bsp::Region{tile})) {
    if (c.what != nullptr && c.use != bsp::CarveUse::kStack && std::strcmp(c.what, name) == 0) {
      return &c;
    }
  }
  return nullptr;
}

}  // namespace

RecordRead copy_ram_record(bsp::TileId tile, const char* name, std::span<std::byte> out) noexcept {
  if (tile >= bsp::tile_count()) {
    return RecordRead::kNoTile;
  }
  const bsp::CarveRecord* c = name != nullptr ? find_record(tile, name) : nullptr;
  if (c == nullptr) {
    return RecordRead::kNoRecord;
  }
  if (c->bytes != out.size()) {
    return RecordRead::kWrongSize;
  }
  const std::span<const std::byte> ram = bsp::region_span(bsp::Region{tile});
  std::copy_n(ram.begin() + static_cast<std::ptrdiff_t>(c->offset), out.size(), out.begin());
  return RecordRead::kOk;
}

bool read_ram_record(bsp::TileId tile, const char* name, std::span<std::byte> out, std::string& error) {
  const RecordRead r = copy_ram_record(tile, name, out);
  if (r == RecordRead::kOk) {
    return true;  // nothing allocated: a read with the heap sealed is fine
  }
  const std::string what = "record '" + std::string(name != nullptr ? name : "") + "'";
  const std::string on = " on tile " + std::to_string(tile);
  switch (r) {
    case RecordRead::kNoTile:
      error = what + ": tile " + std::to_string(tile) + " is not on the chip (" + std::to_string(bsp::tile_count()) +
              " tiles)";
      break;
    case RecordRead::kNoRecord:
      error = "no " + what + on + " (no carve of that name: not a record, or its task has not carved it)";
      break;
    case RecordRead::kWrongSize:
      error = what + on + " is " + std::to_string(find_record(tile, name)->bytes) + " bytes, the reader's type " +
              std::to_string(out.size());
      break;
    case RecordRead::kOk:
      break;
  }
  return false;
}

}  // namespace tools
