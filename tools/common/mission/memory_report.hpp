/**
 * @file memory_report.hpp
 * @brief Host-side report of the memory map: regions, link-time sections, carves per tile.
 */
#pragma once

#include <cstdint>
#include <ostream>

namespace tools {

/**
 * Writes, per region (each tile's RAM, then DDR), the used and free bytes and
 * what was carved, followed by the link-time section bounds and budgets.
 * @param tiles number of tiles to list (the chip profile's tile count).
 */
void write_memory_report(std::ostream& out, std::uint32_t tiles);

}  // namespace tools
