/**
 * @file heap_guard.hpp
 * @brief Process-wide allocation guard: counts heap allocations and seals the heap after init.
 *
 * Every program links heap_guard.o (not through an archive), which replaces the
 * global operator new/delete family and, outside AddressSanitizer builds, the C
 * malloc family. After seal(), each allocation is counted; in kFatal mode the
 * first one stops the process with a message naming the count (exit status 3).
 *
 * Under AddressSanitizer the sanitizer owns malloc, so only operator new is
 * counted there (all C++ containers and strings allocate through it).
 */
#pragma once

#include <cstdint>

namespace bsp::heap {

enum class SealMode : std::uint8_t {
  kFatal,  ///< images: the first allocation after the seal ends the run
  kCount,  ///< tests: allocations are counted, the test asserts the count
};

/** Exit status of a process stopped by an allocation after a fatal seal. */
inline constexpr int kSealViolationExit = 3;

/** Seals the heap; resets the after-seal counter. */
void seal(SealMode mode) noexcept;

/** Ends the sealed phase (host front end writing its outputs). Keeps the count. */
void unseal() noexcept;

[[nodiscard]] bool is_sealed() noexcept;

/** Allocations since the last seal() (kept after unseal()). */
[[nodiscard]] std::uint64_t allocs_after_seal() noexcept;

/** Allocations since the process started. */
[[nodiscard]] std::uint64_t allocs_total() noexcept;

/** True when the C malloc family is counted too (false under AddressSanitizer). */
[[nodiscard]] bool counts_malloc() noexcept;

}  // namespace bsp::heap
