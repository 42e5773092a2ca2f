/**
 * @file sem.hpp
 * @brief Counting semaphore with blocking, timed and non-blocking take; interrupt-safe give.
 *
 * A semaphore belongs to one tile (tiles share nothing but the network): it is
 * used only by that tile's tasks and interrupt hooks.
 */
#pragma once

#include "kernel/detail/core.hpp"
#include "kernel/types.hpp"

#include <array>
#include <cstddef>
#include <cstdint>

namespace k {

class Semaphore {
 public:
  constexpr Semaphore(std::uint32_t initial, std::uint32_t max) noexcept : count_(initial), max_(max) {}

  /** Takes one unit, waiting up to @p to. kWouldBlock for kNoWait, kTimeout on expiry. [task] */
  Status take(Timeout to) noexcept;

  /** Gives one unit; wakes the most urgent waiter. kExhausted at the maximum. [task] */
  Status give() noexcept;

  /** give() from an interrupt hook: the switch, if any, happens when the handler ends. [isr] */
  Status give_from_isr() noexcept;

  [[nodiscard]] std::uint32_t count() const noexcept { return count_; }

 private:
  Status give_masked() noexcept;
  std::uint32_t count_;
  std::uint32_t max_;
  detail::WaitList waiters_{};
  friend struct SemaphoreLayout;
};

/**
 * A semaphore in a control struct is emulated state (bsp::ControlLayout): its
 * counts are numbers, its wait list is checked by the kernel at every link.
 */
struct SemaphoreLayout {
  static constexpr std::array kFields{BSP_CONTROL_STATE(Semaphore, count_), BSP_CONTROL_STATE(Semaphore, max_),
                                      BSP_CONTROL_NESTED(Semaphore, waiters_, detail::kWaitListLayout)};
  static constexpr bsp::ControlLayout kLayout{kFields, sizeof(Semaphore), alignof(Semaphore)};
  static_assert(bsp::control_layout_ok(kLayout), "every member of Semaphore");
};

}  // namespace k
