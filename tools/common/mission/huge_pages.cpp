/**
 * @file huge_pages.cpp
 * @brief Transparent huge pages for the emulator's large static arrays.
 */
#include "tools/common/mission/huge_pages.hpp"

#include "bsp_tile64/api/memory.hpp"
#include "bsp_tile64/world/terrain.hpp"

#include <sys/mman.h>

#include <cstddef>
#include <cstdint>

namespace tools {

namespace {

/** Advises the whole 2 MiB pages inside [p, p + n). */
void advise(const void* p, std::size_t n) noexcept {
  constexpr std::uintptr_t kHuge = std::uintptr_t{2} << 20U;
  const auto a = reinterpret_cast<std::uintptr_t>(p);  // NOLINT(cppcoreguidelines-pro-type-reinterpret-cast): page arithmetic
  const std::uintptr_t lo = (a + kHuge - 1U) & ~(kHuge - 1U);
  const std::uintptr_t hi = (a + n) & ~(kHuge - 1U);
  if (hi > lo) {
    // Advice only: a kernel without transparent huge pages refuses it and nothing else changes.
    (void)::madvise(reinterpret_cast<void*>(lo), hi - lo, MADV_HUGEPAGE);  // NOLINT(cppcoreguidelines-pro-type-reinterpret-cast,performance-no-int-to-ptr): page arithmetic
  }
}

}  // namespace

void prefer_huge_pages() noexcept {
  static bool done = false;
  if (done) {
    return;
  }
  done = true;
  // Tile RAM is one array, tile 0's region first.
  advise(bsp::region_span(bsp::Region{0}).data(), bsp::kMaxTiles * bsp::kTileRamBytes);
  advise(bsp::region_span(bsp::Region{bsp::Region::kDdr}).data(), bsp::kDdrBytes);
  advise(bsp::world::detail::cell_data(),
         std::size_t{bsp::world::kMaxTerrainPx} * bsp::world::kMaxTerrainPx * sizeof(bsp::world::detail::Cell));
}

}  // namespace tools
