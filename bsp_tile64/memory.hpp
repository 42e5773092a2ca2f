/**
 * @file memory.hpp
 * @brief The board's memory map: per-tile RAM regions and the shared DDR region.
 *
 * Both regions are static arrays placed by the linker fragment
 * (linker/host_memory.ld.S) in their own NOLOAD sections. Software obtains
 * memory from them only by carving at init: a carve is a bump allocation
 * inside one region, recorded by name for the size report. Nothing is ever
 * returned; a tile restart resets its own region and carves again.
 */
#pragma once

#include "linker/memory_config.h"

#include <cstddef>
#include <cstdint>
#include <span>

namespace bsp {

inline constexpr std::uint32_t kMaxTiles = MEM_MAX_TILES;
inline constexpr std::size_t kTileRamBytes = MEM_TILE_RAM_BYTES;
inline constexpr std::size_t kDdrBytes = MEM_DDR_BYTES;
inline constexpr std::size_t kRegionAlign = MEM_REGION_ALIGN;
/** Carve records kept per region for the size report. */
inline constexpr std::size_t kMaxCarvesPerRegion = 48;

static_assert(kTileRamBytes % kRegionAlign == 0, "tile RAM must be a whole number of pages");
static_assert(kDdrBytes % kRegionAlign == 0, "DDR must be a whole number of pages");

enum class MemError : std::uint8_t {
  kOk,
  kBadRegion,  ///< tile index out of range
  kBadAlign,   ///< alignment not a power of two, or larger than a page
  kExhausted,  ///< the region has not enough free bytes left
  kTooMany,    ///< more carves than kMaxCarvesPerRegion
};

/** Result of a carve: a pointer into the region, or an error and nullptr. */
struct Carve {
  std::byte* ptr;
  MemError error;
};

/**
 * What a carve holds, as far as an upset of it can be modelled. The emulator
 * runs on the contexts' stacks and follows the host addresses kept in control
 * data (task control blocks, the messaging endpoint, a role's state with
 * pointers): a flipped bit there would crash the emulator, not model the tile.
 */
enum class CarveUse : std::uint8_t {
  kData,     ///< values only: an upset flips the bit
  kStack,    ///< a context's stack: random upsets leave it alone
  kControl,  ///< holds host addresses: an upset there is modelled as a crash of the tile
};

/** One named carve, for the size report and the fault injector. */
struct CarveRecord {
  const char* what;  ///< static string naming the user
  std::size_t offset;
  std::size_t bytes;
  CarveUse use = CarveUse::kData;
};

/** Identifies a region: a tile's RAM, or the shared DDR. */
struct Region {
  static constexpr std::uint32_t kDdr = 0xFFFF'FFFFU;
  std::uint32_t id;  ///< tile index, or kDdr
};

/** Whole span of a region (carved or not). Empty span for a bad id. */
std::span<std::byte> region_span(Region r) noexcept;

/** Bytes carved so far in a region (0 for a bad id). */
std::size_t region_used(Region r) noexcept;

/**
 * Carves @p bytes aligned to @p align from region @p r.
 * @param what static string naming the user (kept by pointer for reports).
 * @return the pointer, or nullptr with the reason; the region is unchanged on error.
 * Memory is zeroed: a carve always starts from a known state.
 */
Carve carve(Region r, std::size_t bytes, std::size_t align, const char* what) noexcept;

/** carve() of a context's stack: recorded as one (CarveUse::kStack). */
Carve carve_stack(Region r, std::size_t bytes, std::size_t align, const char* what) noexcept;

/** carve() of control data that holds host addresses (CarveUse::kControl). */
Carve carve_control(Region r, std::size_t bytes, std::size_t align, const char* what) noexcept;

/** Resets a region to empty (tile restart). The memory is zeroed. */
MemError region_reset(Region r) noexcept;

/** The carve records of a region; empty for a bad id. */
std::span<const CarveRecord> region_carves(Region r) noexcept;

/** Typed convenience over carve(): storage for @p count objects of T. */
template <class T>
T* carve_array(Region r, std::size_t count, const char* what, MemError* err) noexcept {
  const Carve c = carve(r, sizeof(T) * count, alignof(T), what);
  if (err != nullptr) {
    *err = c.error;
  }
  return reinterpret_cast<T*>(c.ptr);  // NOLINT(cppcoreguidelines-pro-type-reinterpret-cast): raw region storage
}

/** carve_array() of control data that holds host addresses (CarveUse::kControl). */
template <class T>
T* carve_control_array(Region r, std::size_t count, const char* what, MemError* err) noexcept {
  const Carve c = carve_control(r, sizeof(T) * count, alignof(T), what);
  if (err != nullptr) {
    *err = c.error;
  }
  return reinterpret_cast<T*>(c.ptr);  // NOLINT(cppcoreguidelines-pro-type-reinterpret-cast): raw region storage
}

/** Link-time bounds of the sections, from the linker fragment's symbols. */
struct SectionBounds {
  std::uintptr_t start;
  std::uintptr_t end;
  std::uintptr_t budget;
};
SectionBounds tile_ram_section() noexcept;
SectionBounds ddr_section() noexcept;

}  // namespace bsp
