/**
 * @file pool.hpp
 * @brief Fixed-block pools: O(1) allocate and release from static storage.
 *
 * Pool<T, N> holds N blocks of T inside the object and is used through the
 * capacity-free PoolBase. Exhaustion is an error value, never a wait. Release
 * of a foreign pointer or a double release is detected and refused.
 */
#pragma once

#include "kernel/types.hpp"

#include <array>
#include <cstddef>
#include <cstdint>

namespace k {

class PoolBase {
 public:
  PoolBase(const PoolBase&) = delete;
  PoolBase& operator=(const PoolBase&) = delete;
  PoolBase(PoolBase&&) = delete;
  PoolBase& operator=(PoolBase&&) = delete;

  /** A free block in *out, or kExhausted (and *out = nullptr). O(1). [task|isr] */
  Status allocate(void** out) noexcept;
  /** Returns a block. kBadArg for a pointer not from this pool or already free. O(1). [task|isr] */
  Status release(void* block) noexcept;

  [[nodiscard]] std::uint32_t free_count() const noexcept { return free_; }
  [[nodiscard]] std::uint32_t capacity() const noexcept { return capacity_; }

 protected:
  PoolBase(std::byte* blocks, std::uint16_t* links, std::uint8_t* used, std::uint32_t block_bytes,
           std::uint32_t capacity) noexcept;
  ~PoolBase() = default;

 private:
  static constexpr std::uint16_t kEnd = 0xFFFF;
  std::byte* blocks_;
  std::uint16_t* links_;  ///< free-list successor of each block
  std::uint8_t* used_;    ///< 1 while allocated (double-release check)
  std::uint32_t block_bytes_;
  std::uint32_t capacity_;
  std::uint32_t free_;
  std::uint16_t head_;
};

namespace detail {
/** Storage first among the bases, so it exists before PoolBase takes its address. */
template <class T, std::uint32_t N>
struct PoolStorage {
  alignas(T) std::array<std::byte, sizeof(T) * N> block_storage{};
  std::array<std::uint16_t, N> link_storage{};
  std::array<std::uint8_t, N> used_storage{};
};
}  // namespace detail

template <class T, std::uint32_t N>
class Pool final : private detail::PoolStorage<T, N>, public PoolBase {
  static_assert(N > 0U && N < 0xFFFFU, "pool capacity 1..65534");

 public:
  Pool() noexcept : PoolBase(this->block_storage.data(), this->link_storage.data(), this->used_storage.data(), sizeof(T), N) {}
  /** Typed allocate: a block for one T (uninitialised storage), or nullptr. */
  T* allocate_block(Status* s) noexcept {
    void* p = nullptr;
    const Status r = allocate(&p);
    if (s != nullptr) {
      *s = r;
    }
    return static_cast<T*>(p);
  }
};

}  // namespace k
