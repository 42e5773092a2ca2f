/**
 * @file heap_guard.cpp
 * @brief Replacement allocation functions that count and, after the seal, police allocations.
 *
 * Host-side infrastructure (not a hardware model): it defines the global
 * allocation functions of the process. The C malloc family forwards to glibc's
 * __libc_* entry points; operator new forwards to malloc.
 */
#include "bsp_tile64/emu/host/heap_guard.hpp"

#include "bsp_tile64/api/port.hpp"  // BSP_ASAN

#include <atomic>
#include <cstddef>
#include <cstdio>
#include <cstdlib>
#include <malloc.h>
#include <new>
#include <unistd.h>

#if BSP_ASAN
#define HEAP_GUARD_COUNTS_MALLOC 0
#else
#define HEAP_GUARD_COUNTS_MALLOC 1
#endif

// Relaxed atomics: counts must be exact even if a host tool uses threads,
// and ordering with other memory does not matter.
namespace {
using bsp::heap::SealMode;
std::atomic<std::uint64_t> g_total{0};
std::atomic<std::uint64_t> g_after_seal{0};
std::atomic<bool> g_sealed{false};
std::atomic<SealMode> g_mode{SealMode::kCount};

void write_all(const char* s, std::size_t n) noexcept {
  while (n > 0U) {
    const ssize_t w = ::write(STDERR_FILENO, s, n);
    if (w <= 0) {
      return;
    }
    s += w;
    n -= static_cast<std::size_t>(w);
  }
}

[[noreturn]] void violation(std::size_t bytes, std::uint64_t count) noexcept {
  // No stdio, no allocation: format into a local buffer and write(2) it.
  char msg[192];
  const int n = std::snprintf(msg, sizeof msg,
                              "fatal: heap allocation of %zu bytes after init (allocation #%llu after the "
                              "seal); flight code must not allocate after init\n",
                              bytes, static_cast<unsigned long long>(count));
  if (n > 0) {
    write_all(msg, static_cast<std::size_t>(n) < sizeof msg ? static_cast<std::size_t>(n) : sizeof msg - 1U);
  }
  ::_exit(bsp::heap::kSealViolationExit);
}

}  // namespace

namespace bsp::heap {

void seal(SealMode mode) noexcept {
  g_mode.store(mode, std::memory_order_relaxed);
  g_after_seal.store(0, std::memory_order_relaxed);
  g_sealed.store(true, std::memory_order_release);
}

void unseal() noexcept { g_sealed.store(false, std::memory_order_release); }

bool is_sealed() noexcept { return g_sealed.load(std::memory_order_acquire); }

std::uint64_t allocs_after_seal() noexcept { return g_after_seal.load(std::memory_order_relaxed); }

std::uint64_t allocs_total() noexcept { return g_total.load(std::memory_order_relaxed); }

bool counts_malloc() noexcept { return HEAP_GUARD_COUNTS_MALLOC != 0; }

}  // namespace bsp::heap

namespace {
/** Called on every allocation, before it is made. */
void note_alloc(std::size_t bytes) noexcept {
  g_total.fetch_add(1, std::memory_order_relaxed);
  if (g_sealed.load(std::memory_order_acquire)) {
    const std::uint64_t n = g_after_seal.fetch_add(1, std::memory_order_relaxed) + 1U;
    if (g_mode.load(std::memory_order_relaxed) == SealMode::kFatal) {
      violation(bytes, n);
    }
  }
}
}  // namespace

#if HEAP_GUARD_COUNTS_MALLOC
extern "C" {
void* __libc_malloc(std::size_t);                   // NOLINT(bugprone-reserved-identifier)
void* __libc_calloc(std::size_t, std::size_t);      // NOLINT(bugprone-reserved-identifier)
void* __libc_realloc(void*, std::size_t);           // NOLINT(bugprone-reserved-identifier)
void* __libc_memalign(std::size_t, std::size_t);    // NOLINT(bugprone-reserved-identifier)
void __libc_free(void*);                            // NOLINT(bugprone-reserved-identifier)

void* malloc(std::size_t n) {
  note_alloc(n);
  return __libc_malloc(n);
}
void* calloc(std::size_t c, std::size_t n) {
  note_alloc(c * n);
  return __libc_calloc(c, n);
}
void* realloc(void* p, std::size_t n) {
  note_alloc(n);
  return __libc_realloc(p, n);
}
void* memalign(std::size_t a, std::size_t n) {
  note_alloc(n);
  return __libc_memalign(a, n);
}
void* aligned_alloc(std::size_t a, std::size_t n) {
  note_alloc(n);
  return __libc_memalign(a, n);
}
int posix_memalign(void** out, std::size_t a, std::size_t n) {
  note_alloc(n);
  void* p = __libc_memalign(a, n);
  if (p == nullptr) {
    return 12;  // ENOMEM
  }
  *out = p;
  return 0;
}
void free(void* p) { __libc_free(p); }
}
#endif

namespace {
void* checked_new(std::size_t n) {
  void* p = std::malloc(n == 0U ? 1U : n);
  if (p == nullptr) {
    std::abort();  // out of host memory: nothing sensible to do without exceptions
  }
  return p;
}
void* checked_new_aligned(std::size_t n, std::align_val_t a) {
  void* p = std::aligned_alloc(static_cast<std::size_t>(a), ((n + static_cast<std::size_t>(a) - 1U) / static_cast<std::size_t>(a)) * static_cast<std::size_t>(a));
  if (p == nullptr) {
    std::abort();
  }
  return p;
}
}  // namespace

// Under AddressSanitizer malloc is not ours, so operator new counts by itself.
#if HEAP_GUARD_COUNTS_MALLOC
#define HEAP_GUARD_NOTE(n) (void)(n)
#else
#define HEAP_GUARD_NOTE(n) note_alloc(n)
#endif

void* operator new(std::size_t n) { HEAP_GUARD_NOTE(n); return checked_new(n); }
void* operator new[](std::size_t n) { HEAP_GUARD_NOTE(n); return checked_new(n); }
void* operator new(std::size_t n, const std::nothrow_t&) noexcept { HEAP_GUARD_NOTE(n); return std::malloc(n == 0U ? 1U : n); }
void* operator new[](std::size_t n, const std::nothrow_t&) noexcept { HEAP_GUARD_NOTE(n); return std::malloc(n == 0U ? 1U : n); }
void* operator new(std::size_t n, std::align_val_t a) { HEAP_GUARD_NOTE(n); return checked_new_aligned(n, a); }
void* operator new[](std::size_t n, std::align_val_t a) { HEAP_GUARD_NOTE(n); return checked_new_aligned(n, a); }
void operator delete(void* p) noexcept { std::free(p); }
void operator delete[](void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }
void operator delete[](void* p, std::size_t) noexcept { std::free(p); }
void operator delete(void* p, std::align_val_t) noexcept { std::free(p); }
void operator delete[](void* p, std::align_val_t) noexcept { std::free(p); }
void operator delete(void* p, std::size_t, std::align_val_t) noexcept { std::free(p); }
void operator delete[](void* p, std::size_t, std::align_val_t) noexcept { std::free(p); }
