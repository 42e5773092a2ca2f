/*
 * @file host_memory.ld.S
 * @brief Linker fragment for host images: the tile RAM and shared DDR regions.
 *
 * Preprocessed with memory_config.h into build/gen/host_memory.ld and given to
 * the linker with -T; INSERT keeps the default host script and adds these
 * NOLOAD sections after .bss. Each region exports its bounds as symbols and is
 * checked against its budget: an over-budget region fails the link.
 */
#include "linker/memory_config.h"

SECTIONS
{
  .tile_ram (NOLOAD) : ALIGN(MEM_REGION_ALIGN)
  {
    mem_tile_ram_start = .;
    KEEP(*(.bss.tile_ram .bss.tile_ram.*))
    mem_tile_ram_end = .;
  }
  .ddr (NOLOAD) : ALIGN(MEM_REGION_ALIGN)
  {
    mem_ddr_start = .;
    KEEP(*(.bss.ddr .bss.ddr.*))
    mem_ddr_end = .;
  }
}
INSERT AFTER .bss;

/* Budget limits as addresses (start + budget), so they relocate with the
 * image like the region bounds do; the budget in bytes is limit - start. */
mem_tile_ram_limit = mem_tile_ram_start + MEM_MAX_TILES * MEM_TILE_RAM_BYTES;
mem_ddr_limit = mem_ddr_start + MEM_DDR_BYTES;
ASSERT(mem_tile_ram_end <= mem_tile_ram_limit,
       "memory map: .tile_ram is over budget (MEM_MAX_TILES * MEM_TILE_RAM_BYTES)");
ASSERT(mem_ddr_end <= mem_ddr_limit,
       "memory map: .ddr is over budget (MEM_DDR_BYTES)");
/*
 * Input sections are named .bss.tile_ram / .bss.ddr so the compiler emits them
 * as NOBITS (no 160 MiB of zeros in object files). Statements of a -T script
 * are matched before the default script's, so .bss does not take them.
 */
