/**
 * @file event_queue.hpp
 * @brief The board's ordered event queue: a fixed-capacity binary heap on (cycle, tile, sequence).
 *
 * The sequence number is unique per scheduled event, so the order is total and
 * independent of heap layout: two runs that schedule the same events pop them
 * in the same order.
 */
#pragma once

#include "bsp_tile64/api/port.hpp"

#include <array>
#include <cstddef>
#include <cstdint>

namespace bsp {

/** Called when a scheduled event is delivered, on the target tile at the event's cycle. */
using EventCallback = void (*)(TileId tile, Cycles cycle, std::uint64_t arg);

/** What an event does when it is delivered. */
enum class EventKind : std::uint8_t {
  kDevice,  ///< a device or fault event: callback (if any), then irq (if not Irq::kCount)
};

struct Event {
  Cycles cycle;
  TileId tile;
  EventKind kind;
  Irq irq;  ///< Irq::kCount: raise nothing
  std::uint64_t seq;
  EventCallback callback;
  std::uint64_t arg;
};

/** Strict (cycle, tile, seq) order. */
constexpr bool event_before(const Event& x, const Event& y) noexcept {
  if (x.cycle != y.cycle) {
    return x.cycle < y.cycle;
  }
  if (x.tile != y.tile) {
    return x.tile < y.tile;
  }
  return x.seq < y.seq;
}

/** Min-heap of events with capacity N. All operations O(log N), no allocation. */
template <std::size_t N>
class EventHeap {
 public:
  [[nodiscard]] bool empty() const noexcept { return size_ == 0U; }
  [[nodiscard]] bool full() const noexcept { return size_ == N; }
  [[nodiscard]] std::size_t size() const noexcept { return size_; }
  void clear() noexcept { size_ = 0U; }

  /** The earliest event. Precondition: !empty(). */
  [[nodiscard]] const Event& top() const noexcept { return items_[0]; }

  /** @return false (and changes nothing) when full. */
  bool push(const Event& e) noexcept {
    if (full()) {
      return false;
    }
    std::size_t i = size_++;
    // The new event rises through a hole: each parent it passes moves down once, and it is written once.
    while (i > 0U) {  // bounded: i halves every step
      const std::size_t parent = (i - 1U) / 2U;
      if (!event_before(e, items_[parent])) {
        break;
      }
      items_[i] = items_[parent];
      i = parent;
    }
    items_[i] = e;
    return true;
  }

  /** Removes the earliest event. Precondition: !empty(). */
  void pop() noexcept {
    --size_;
    // The last event sinks from the root through a hole: the earlier child moves up, and it is written once.
    const Event last = items_[size_];
    std::size_t i = 0U;
    while (true) {  // bounded: i at least doubles every step and stops at size_
      const std::size_t l = 2U * i + 1U;
      if (l >= size_) {
        break;
      }
      const std::size_t r = l + 1U;
      const std::size_t c = (r < size_ && event_before(items_[r], items_[l])) ? r : l;
      if (!event_before(items_[c], last)) {
        break;
      }
      items_[i] = items_[c];
      i = c;
    }
    items_[i] = last;
  }

 private:
  std::array<Event, N> items_{};
  std::size_t size_ = 0U;
};

/** A small sorted list of one tile's events due in the current quantum. */
template <std::size_t N>
class LocalEvents {
 public:
  [[nodiscard]] bool empty() const noexcept { return size_ == 0U; }
  [[nodiscard]] std::size_t size() const noexcept { return size_; }
  void clear() noexcept { size_ = 0U; }
  [[nodiscard]] const Event& front() const noexcept { return items_[0]; }

  /** Sorted insert; @return false when full. */
  bool insert(const Event& e) noexcept {
    if (size_ == N) {
      return false;
    }
    std::size_t i = size_;
    while (i > 0U && event_before(e, items_[i - 1U])) {
      items_[i] = items_[i - 1U];
      --i;
    }
    items_[i] = e;
    ++size_;
    return true;
  }

  /** Removes the front event. Precondition: !empty(). */
  void pop_front() noexcept {
    for (std::size_t i = 1U; i < size_; ++i) {
      items_[i - 1U] = items_[i];
    }
    --size_;
  }

 private:
  std::array<Event, N> items_{};
  std::size_t size_ = 0U;
};

}  // namespace bsp
