/**
 * @file huge_pages.hpp
 * @brief Asks the host kernel for huge pages under the emulator's large static arrays.
 */
#pragma once

namespace tools {

/**
 * Advises transparent huge pages (madvise MADV_HUGEPAGE) for the board's tile RAM
 * and DDR and the world's terrain grid: some 230 MB that every run first touches
 * (a cached terrain copied in, carves zeroed). With 4 KiB pages that is some
 * 60 000 page faults per run, most of a short flight's host time. Only the host's
 * time changes: the bytes, and so every trace hash, are the same either way, and
 * a host without huge pages (or with them switched off) ignores the advice. Once
 * per process; later calls do nothing.
 */
void prefer_huge_pages() noexcept;

}  // namespace tools
