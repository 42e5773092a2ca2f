/**
 * @file queue.cpp
 * @brief Bounded message queue.
 *
 * Hand-off: when a receiver waits on an empty queue, a sender still goes
 * through the ring and then wakes the receiver, which pops on resuming. The
 * woken task is ready before any other task can run, but a more urgent task
 * could run first and take the item; the woken receiver then waits again
 * (bounded by its remaining timeout), so no item is ever lost or duplicated.
 */
#include "kernel/queue.hpp"

#include "bsp_tile64/api/port.hpp"

#include <cstring>

namespace k {

void QueueBase::push(const void* item) noexcept {
  const std::uint32_t tail = (head_ + count_) % capacity_;
  std::memcpy(storage_ + static_cast<std::size_t>(tail) * item_bytes_, item, item_bytes_);
  ++count_;
}

void QueueBase::pop(void* item) noexcept {
  std::memcpy(item, storage_ + static_cast<std::size_t>(head_) * item_bytes_, item_bytes_);
  head_ = (head_ + 1U) % capacity_;
  --count_;
}

Status QueueBase::send_masked(const void* item, Timeout to) noexcept {
  // Each pass either succeeds or blocks once; a woken sender can lose the slot
  // to a more urgent one, so retry a bounded number of times.
  for (std::uint32_t tries = 0; tries < config::kMaxTasks + 1U; ++tries) {
    if (count_ < capacity_) {
      push(item);
      (void)detail::wake_one(receivers_, 0);
      return Status::kOk;
    }
    if (to.ticks == kNoWait.ticks) {
      return Status::kExhausted;
    }
    if (!detail::can_block()) {
      return Status::kBadState;
    }
    if (detail::block_current(&senders_, to, 0) == detail::WakeReason::kTimeout) {
      return Status::kTimeout;
    }
  }
  return Status::kTimeout;
}

Status QueueBase::receive_masked(void* item, Timeout to) noexcept {
  for (std::uint32_t tries = 0; tries < config::kMaxTasks + 1U; ++tries) {
    if (count_ > 0U) {
      pop(item);
      (void)detail::wake_one(senders_, 0);
      return Status::kOk;
    }
    if (to.ticks == kNoWait.ticks) {
      return Status::kWouldBlock;
    }
    if (!detail::can_block()) {
      return Status::kBadState;
    }
    if (detail::block_current(&receivers_, to, 0) == detail::WakeReason::kTimeout) {
      return Status::kTimeout;
    }
  }
  return Status::kTimeout;
}

Status QueueBase::send(const void* item, Timeout to) noexcept {
  const bool m = bsp::mask_irqs(true);
  const Status s = send_masked(item, to);
  if (s == Status::kOk && !detail::in_isr()) {
    detail::reschedule();
  }
  (void)bsp::mask_irqs(m);
  return s;
}

Status QueueBase::send_from_isr(const void* item) noexcept {
  const bool m = bsp::mask_irqs(true);
  const Status s = send_masked(item, kNoWait);
  (void)bsp::mask_irqs(m);
  return s;
}

Status QueueBase::receive(void* item, Timeout to) noexcept {
  const bool m = bsp::mask_irqs(true);
  const Status s = receive_masked(item, to);
  if (s == Status::kOk && !detail::in_isr()) {
    detail::reschedule();
  }
  (void)bsp::mask_irqs(m);
  return s;
}

Status QueueBase::receive_from_isr(void* item) noexcept {
  const bool m = bsp::mask_irqs(true);
  const Status s = receive_masked(item, kNoWait);
  (void)bsp::mask_irqs(m);
  return s;
}

}  // namespace k
