/**
 * @file memory_config.h
 * @brief The memory map of host images: per-tile RAM and shared DDR budgets.
 *
 * One source of truth for both the linker fragment (preprocessed into
 * build/gen/host_memory.ld) and the C++ code (bsp_tile64/api/memory.hpp), so the
 * link-time assertions and the compile-time checks can never drift apart.
 * Plain preprocessor constants only: this file is also read as a linker script.
 */
#ifndef LINKER_MEMORY_CONFIG_H
#define LINKER_MEMORY_CONFIG_H

/* Largest grid any chip profile uses (TILE64: 8x8; Maestro: 7x7). */
#define MEM_MAX_TILES 64

/* RAM region of one tile, bytes. TILE64 has 64 KiB of L2 per tile backed by
 * DDR; the emulated region holds the tile's kernel, task stacks and static
 * working buffers (correlation windows, filter state), so it is larger. */
#define MEM_TILE_RAM_BYTES 0x80000 /* 512 KiB */

/* Shared DDR visible to every tile: camera frames, reference map, mailboxes. */
#define MEM_DDR_BYTES 0x8000000 /* 128 MiB */

/* Alignment of every region start (a page, so a region can be protected). */
#define MEM_REGION_ALIGN 4096

#endif
