/**
 * @file memory.cpp
 * @brief Static tile RAM and DDR regions and the init-time carve allocator.
 */
#include "bsp_tile64/api/memory.hpp"

#include <array>
#include <cstring>

// Symbols defined by linker/host_memory.ld.S. Only their addresses matter.
extern "C" {
extern std::byte mem_tile_ram_start[];
extern std::byte mem_tile_ram_end[];
extern std::byte mem_ddr_start[];
extern std::byte mem_ddr_end[];
extern std::byte mem_tile_ram_limit[];
extern std::byte mem_ddr_limit[];
}

namespace bsp {
namespace {

// Section names start with ".bss." so the compiler emits NOBITS sections; the
// linker fragment collects them into the NOLOAD .tile_ram and .ddr regions.
alignas(kRegionAlign) [[gnu::section(".bss.tile_ram")]] std::byte g_tile_ram[kMaxTiles * kTileRamBytes];
alignas(kRegionAlign) [[gnu::section(".bss.ddr")]] std::byte g_ddr[kDdrBytes];

struct RegionState {
  std::size_t used;
  std::size_t carves;
  std::array<CarveRecord, kMaxCarvesPerRegion> records;
};

std::array<RegionState, kMaxTiles> g_tile_state{};
RegionState g_ddr_state{};

RegionState* state_of(Region r) noexcept {
  if (r.id == Region::kDdr) {
    return &g_ddr_state;
  }
  if (r.id < kMaxTiles) {
    return &g_tile_state[r.id];
  }
  return nullptr;
}

}  // namespace

std::span<std::byte> region_span(Region r) noexcept {
  if (r.id == Region::kDdr) {
    return {g_ddr, kDdrBytes};
  }
  if (r.id < kMaxTiles) {
    return {&g_tile_ram[static_cast<std::size_t>(r.id) * kTileRamBytes], kTileRamBytes};
  }
  return {};
}

std::size_t region_used(Region r) noexcept {
  const RegionState* s = state_of(r);
  return (s == nullptr) ? 0U : s->used;
}

namespace {

Carve carve_as(Region r, std::size_t bytes, std::size_t align, const char* what, CarveUse use,
               const ControlLayout* layout) noexcept {
  RegionState* s = state_of(r);
  if (s == nullptr) {
    return {nullptr, MemError::kBadRegion};
  }
  if (align == 0U || (align & (align - 1U)) != 0U || align > kRegionAlign) {
    return {nullptr, MemError::kBadAlign};
  }
  if (s->carves >= kMaxCarvesPerRegion) {
    return {nullptr, MemError::kTooMany};
  }
  const std::span<std::byte> whole = region_span(r);
  // Regions start page-aligned, so aligning the offset aligns the address.
  const std::size_t offset = (s->used + align - 1U) & ~(align - 1U);
  if (offset > whole.size() || bytes > whole.size() - offset) {
    return {nullptr, MemError::kExhausted};
  }
  std::byte* p = whole.data() + offset;
  std::memset(p, 0, bytes);
  s->records[s->carves] = CarveRecord{what, offset, bytes, use, layout};
  ++s->carves;
  s->used = offset + bytes;
  return {p, MemError::kOk};
}

}  // namespace

Carve carve(Region r, std::size_t bytes, std::size_t align, const char* what) noexcept {
  return carve_as(r, bytes, align, what, CarveUse::kData, nullptr);
}

Carve carve_stack(Region r, std::size_t bytes, std::size_t align, const char* what) noexcept {
  return carve_as(r, bytes, align, what, CarveUse::kStack, nullptr);
}

Carve carve_control(Region r, std::size_t bytes, std::size_t align, const char* what,
                    const ControlLayout* layout) noexcept {
  return carve_as(r, bytes, align, what, CarveUse::kControl, layout);
}

MemError region_reset(Region r) noexcept {
  RegionState* s = state_of(r);
  if (s == nullptr) {
    return MemError::kBadRegion;
  }
  const std::span<std::byte> whole = region_span(r);
  std::memset(whole.data(), 0, s->used);
  s->used = 0;
  s->carves = 0;
  return MemError::kOk;
}

std::span<const CarveRecord> region_carves(Region r) noexcept {
  const RegionState* s = state_of(r);
  if (s == nullptr) {
    return {};
  }
  return {s->records.data(), s->carves};
}

namespace {
std::uintptr_t addr(const std::byte* p) noexcept { return reinterpret_cast<std::uintptr_t>(p); }  // NOLINT(cppcoreguidelines-pro-type-reinterpret-cast): linker symbols
}  // namespace

SectionBounds tile_ram_section() noexcept {
  return {addr(mem_tile_ram_start), addr(mem_tile_ram_end), addr(mem_tile_ram_limit) - addr(mem_tile_ram_start)};
}

SectionBounds ddr_section() noexcept {
  return {addr(mem_ddr_start), addr(mem_ddr_end), addr(mem_ddr_limit) - addr(mem_ddr_start)};
}

}  // namespace bsp
