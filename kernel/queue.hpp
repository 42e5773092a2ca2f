/**
 * @file queue.hpp
 * @brief Bounded message queues: copy-in, copy-out, static storage, blocking with timeouts.
 *
 * Queue<T, N> holds N items of a trivially copyable T inside the object; code
 * uses it through the capacity-free QueueBase. Receivers wait when it is empty,
 * senders when it is full; both in priority order, FIFO among equals.
 */
#pragma once

#include "kernel/detail/core.hpp"
#include "kernel/types.hpp"

#include <array>
#include <cstddef>
#include <cstdint>
#include <type_traits>

namespace k {

class QueueBase {
 public:
  QueueBase(const QueueBase&) = delete;
  QueueBase& operator=(const QueueBase&) = delete;
  QueueBase(QueueBase&&) = delete;
  QueueBase& operator=(QueueBase&&) = delete;

  /** Copies @p item in, waiting up to @p to for room. [task] */
  Status send(const void* item, Timeout to) noexcept;
  /** Non-blocking send for interrupt hooks; kExhausted when full. [isr] */
  Status send_from_isr(const void* item) noexcept;
  /** Copies the oldest item out, waiting up to @p to for one. [task] */
  Status receive(void* item, Timeout to) noexcept;
  /** Non-blocking receive for interrupt hooks; kWouldBlock when empty. [isr] */
  Status receive_from_isr(void* item) noexcept;

  [[nodiscard]] std::uint32_t size() const noexcept { return count_; }
  [[nodiscard]] std::uint32_t capacity() const noexcept { return capacity_; }

 protected:
  QueueBase(std::byte* storage, std::uint32_t item_bytes, std::uint32_t capacity) noexcept
      : storage_(storage), item_bytes_(item_bytes), capacity_(capacity) {}
  ~QueueBase() = default;

 private:
  void push(const void* item) noexcept;
  void pop(void* item) noexcept;
  Status send_masked(const void* item, Timeout to) noexcept;
  Status receive_masked(void* item, Timeout to) noexcept;
  std::byte* storage_;
  std::uint32_t item_bytes_;
  std::uint32_t capacity_;
  std::uint32_t head_ = 0;
  std::uint32_t count_ = 0;
  detail::WaitList receivers_{};
  detail::WaitList senders_{};
};

namespace detail {
/** Storage first among the bases, so it exists before QueueBase takes its address. */
template <class T, std::uint32_t N>
struct QueueStorage {
  alignas(T) std::array<std::byte, sizeof(T) * N> ring_storage{};
};
}  // namespace detail

template <class T, std::uint32_t N>
class Queue final : private detail::QueueStorage<T, N>, public QueueBase {
  static_assert(std::is_trivially_copyable_v<T>, "queue items are copied bytewise");
  static_assert(N > 0U, "a queue holds at least one item");

 public:
  Queue() noexcept : QueueBase(this->ring_storage.data(), sizeof(T), N) {}
  Status send(const T& item, Timeout to) noexcept { return QueueBase::send(&item, to); }
  Status send_from_isr(const T& item) noexcept { return QueueBase::send_from_isr(&item); }
  Status receive(T& item, Timeout to) noexcept { return QueueBase::receive(&item, to); }
  Status receive_from_isr(T& item) noexcept { return QueueBase::receive_from_isr(&item); }
};

}  // namespace k
