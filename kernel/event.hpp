/**
 * @file event.hpp
 * @brief Event flags: 32 bits a task waits on (any or all), set from tasks or interrupts.
 */
#pragma once

#include "kernel/detail/core.hpp"
#include "kernel/types.hpp"

#include <array>
#include <cstdint>

namespace k {

enum class WaitMode : std::uint8_t {
  kAny,  ///< wake when any of the wanted bits is set
  kAll,  ///< wake when all of them are set
};

class EventFlags {
 public:
  /**
   * Waits for @p wanted bits per @p mode, up to @p to. On success *got holds the
   * flags that satisfied the wait, and those wanted bits are cleared if @p clear. [task]
   */
  Status wait(std::uint32_t wanted, WaitMode mode, bool clear, Timeout to, std::uint32_t* got) noexcept;

  /** Sets bits and wakes every waiter now satisfied. [task] */
  void set(std::uint32_t bits) noexcept;

  /** set() from an interrupt hook. [isr] */
  void set_from_isr(std::uint32_t bits) noexcept;

  void clear(std::uint32_t bits) noexcept;

  [[nodiscard]] std::uint32_t value() const noexcept { return flags_; }

 private:
  void set_masked(std::uint32_t bits) noexcept;
  std::uint32_t flags_ = 0;
  detail::WaitList waiters_{};
  friend struct EventFlagsLayout;
};

/** Event flags in a control struct are emulated state (bsp::ControlLayout), like a Semaphore's. */
struct EventFlagsLayout {
  static constexpr std::array kFields{BSP_CONTROL_STATE(EventFlags, flags_),
                                      BSP_CONTROL_NESTED(EventFlags, waiters_, detail::kWaitListLayout)};
  static constexpr bsp::ControlLayout kLayout{kFields, sizeof(EventFlags), alignof(EventFlags)};
  static_assert(bsp::control_layout_ok(kLayout), "every member of EventFlags");
};

}  // namespace k
