/**
 * @file heap_probe.hpp
 * @brief Test helper: counts heap allocations made by a piece of code.
 */
#pragma once

#include "bsp_tile64/emu/host/heap_guard.hpp"

#include <cstdint>

namespace test_support {

/**
 * Runs @p fn with the heap sealed in counting mode and returns the number of
 * allocations it made. The seal is lifted before returning, so the caller's
 * assertions (which may allocate on failure) are not counted.
 */
/** Keeps the compiler from eliding an allocation whose result is otherwise unused. */
inline void escape(void* p) { asm volatile("" : : "g"(p) : "memory"); }

template <class Fn>
std::uint64_t count_allocs(Fn&& fn) {
  bsp::heap::seal(bsp::heap::SealMode::kCount);
  fn();
  const std::uint64_t n = bsp::heap::allocs_after_seal();
  bsp::heap::unseal();
  return n;
}

}  // namespace test_support
