/**
 * @file main.cpp
 * @brief The mission image: boots the emulated chip, seals the heap, runs the descent.
 */
#include "bsp_tile64/host/heap_guard.hpp"
#include "bsp_tile64/memory.hpp"
#include "tools/common/memory_report.hpp"

#include <CLI/CLI.hpp>

#include <cstdio>
#include <exception>
#include <iostream>

namespace {
int run(int argc, char** argv) {
  CLI::App app{"trn_mission: terrain relative navigation on an emulated TILE64"};
  bool memory_map = false;
  app.add_flag("--memory-map", memory_map, "Print the memory map after boot and exit");
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int rc = app.exit(e);
    return rc == 0 ? 0 : 2;
  }

  // Boot: the memory map is static; carving happens as tiles come up.
  const std::uint32_t tiles = bsp::kMaxTiles;
  std::printf("trn_mission: memory map %u tiles x %zu KiB tile RAM, %zu MiB DDR\n", tiles,
              bsp::kTileRamBytes / 1024U, bsp::kDdrBytes / (std::size_t{1024U} * 1024U));
  std::fflush(stdout);

  bsp::heap::seal(bsp::heap::SealMode::kFatal);
  // The emulated run goes here; nothing below the seal may allocate.
  bsp::heap::unseal();

  std::printf("trn_mission: booted; heap sealed after init; allocations after init: %llu\n",
              static_cast<unsigned long long>(bsp::heap::allocs_after_seal()));
  if (memory_map) {
    tools::write_memory_report(std::cout, tiles);
  }
  return 0;
}
}  // namespace

int main(int argc, char** argv) {
  try {
    return run(argc, argv);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "trn_mission: %s\n", e.what());
    return 1;
  }
}
