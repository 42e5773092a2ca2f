/**
 * @file memory_report.cpp
 * @brief Writes the memory map report used by `make size` and the images.
 */
#include "tools/common/mission/memory_report.hpp"

#include "bsp_tile64/api/memory.hpp"

#include <bit>
#include <iomanip>

namespace tools {
namespace {

/**
 * The host state of a control carve (bsp::ControlLayout), as "host N bits" of
 * its whole size in bits (bsp::control_live_bits over every byte), or "whole
 * carve host state" when its layout is not declared. Closes the parenthesis.
 */
void write_host_share(std::ostream& out, const bsp::CarveRecord& c) {
  if (c.layout == nullptr) {
    out << ": whole carve host state)";
    return;
  }
  std::size_t host_bits = 0U;
  for (std::size_t i = 0; i < c.bytes; ++i) {
    host_bits += 8U - static_cast<std::size_t>(std::popcount(bsp::control_live_bits(c.layout, i)));
  }
  out << ": host " << host_bits << " of " << c.bytes * 8U << " bits)";
}

void write_region(std::ostream& out, const char* label, bsp::Region r) {
  const std::size_t size = bsp::region_span(r).size();
  const std::size_t used = bsp::region_used(r);
  out << std::left << std::setw(10) << label << std::right << std::setw(12) << used << std::setw(12)
      << (size - used) << std::setw(12) << size << "\n";
  for (const bsp::CarveRecord& c : bsp::region_carves(r)) {
    out << "            " << std::setw(10) << c.bytes << "  " << c.what
        << (c.use == bsp::CarveUse::kStack ? " (stack)" : c.use == bsp::CarveUse::kControl ? " (control" : "");
    if (c.use == bsp::CarveUse::kControl) {
      write_host_share(out, c);
    }
    out << "\n";
  }
}

}  // namespace

void write_memory_report(std::ostream& out, std::uint32_t tiles) {
  out << std::left << std::setw(10) << "region" << std::right << std::setw(12) << "used" << std::setw(12) << "free"
      << std::setw(12) << "size" << "\n";
  for (std::uint32_t t = 0; t < tiles && t < bsp::kMaxTiles; ++t) {
    const std::string label = "tile" + std::to_string(t);
    write_region(out, label.c_str(), bsp::Region{t});
  }
  write_region(out, "ddr", bsp::Region{bsp::Region::kDdr});
  const bsp::SectionBounds tr = bsp::tile_ram_section();
  const bsp::SectionBounds dd = bsp::ddr_section();
  out << "link-time sections (bytes): .tile_ram " << (tr.end - tr.start) << " of budget " << tr.budget
      << ", .ddr " << (dd.end - dd.start) << " of budget " << dd.budget << "\n";
}

}  // namespace tools
