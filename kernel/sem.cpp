/**
 * @file sem.cpp
 * @brief Counting semaphore.
 */
#include "kernel/sem.hpp"

#include "bsp_tile64/api/port.hpp"

namespace k {

Status Semaphore::take(Timeout to) noexcept {
  const bool m = bsp::mask_irqs(true);
  Status s = Status::kOk;
  if (count_ > 0U) {
    --count_;
  } else if (to.ticks == kNoWait.ticks) {
    s = Status::kWouldBlock;
  } else if (!detail::can_block()) {
    s = Status::kBadState;
  } else {
    // give() hands the unit straight to the woken waiter (count stays 0).
    s = (detail::block_current(&waiters_, to, 0) == detail::WakeReason::kSignalled) ? Status::kOk
                                                                                   : Status::kTimeout;
  }
  (void)bsp::mask_irqs(m);
  return s;
}

Status Semaphore::give_masked() noexcept {
  if (detail::wake_one(waiters_, 1) != kNoTask) {
    return Status::kOk;
  }
  if (count_ >= max_) {
    return Status::kExhausted;
  }
  ++count_;
  return Status::kOk;
}

Status Semaphore::give() noexcept {
  const bool m = bsp::mask_irqs(true);
  const Status s = give_masked();
  if (!detail::in_isr()) {
    detail::reschedule();
  }
  (void)bsp::mask_irqs(m);
  return s;
}

Status Semaphore::give_from_isr() noexcept {
  const bool m = bsp::mask_irqs(true);
  const Status s = give_masked();
  (void)bsp::mask_irqs(m);
  return s;
}

}  // namespace k
