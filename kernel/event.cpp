/**
 * @file event.cpp
 * @brief Event flags.
 *
 * A waiter keeps its wanted bits in Tcb::wait_arg and its mode in
 * Tcb::wait_mode_all; set() wakes every waiter whose condition now holds,
 * handing it the flags as they were at that moment (Tcb::wait_result).
 */
#include "kernel/event.hpp"

#include "bsp_tile64/api/port.hpp"
#include "kernel/detail/tcb.hpp"

namespace k {
namespace {

bool satisfied(std::uint32_t flags, std::uint32_t wanted, WaitMode mode) noexcept {
  return mode == WaitMode::kAll ? (flags & wanted) == wanted : (flags & wanted) != 0U;
}

}  // namespace

Status EventFlags::wait(std::uint32_t wanted, WaitMode mode, bool clear, Timeout to, std::uint32_t* got) noexcept {
  if (wanted == 0U) {
    return Status::kBadArg;
  }
  const bool m = bsp::mask_irqs(true);
  Status s = Status::kOk;
  std::uint32_t result = 0;
  if (satisfied(flags_, wanted, mode)) {
    result = flags_;
  } else if (to.ticks == kNoWait.ticks) {
    s = Status::kWouldBlock;
  } else if (!detail::can_block()) {
    s = Status::kBadState;
  } else {
    detail::KernelState& ks = *detail::current_kernel();
    detail::Tcb& me = ks.tcbs[ks.current];
    me.wait_mode_all = (mode == WaitMode::kAll);
    const detail::WakeReason why = detail::block_current(&waiters_, to, wanted);
    s = (why == detail::WakeReason::kSignalled) ? Status::kOk : Status::kTimeout;
    result = me.wait_result;
  }
  if (s == Status::kOk && clear) {
    flags_ &= ~wanted;
  }
  if (got != nullptr) {
    *got = result;
  }
  (void)bsp::mask_irqs(m);
  return s;
}

void EventFlags::set_masked(std::uint32_t bits) noexcept {
  flags_ |= bits;
  detail::KernelState* ks = detail::current_kernel();
  if (ks == nullptr) {
    return;  // host code: no task can be waiting
  }
  // Wake every satisfied waiter; each woken one is removed, so walk from the head.
  TaskId id = waiters_.head;
  // A link past the tasks (an upset of the list or of a task block) ends the walk: those behind it time out.
  for (std::uint32_t n = 0; id < ks->task_count && id < config::kMaxTasks && n < config::kMaxTasks; ++n) {
    const detail::Tcb& t = ks->tcbs[id];
    const TaskId next = t.next_waiter;
    const WaitMode mode = t.wait_mode_all ? WaitMode::kAll : WaitMode::kAny;
    if (satisfied(flags_, t.wait_arg, mode)) {
      detail::wake_task(id, flags_);
    }
    id = next;
  }
}

void EventFlags::set(std::uint32_t bits) noexcept {
  const bool m = bsp::mask_irqs(true);
  set_masked(bits);
  if (!detail::in_isr()) {
    detail::reschedule();
  }
  (void)bsp::mask_irqs(m);
}

void EventFlags::set_from_isr(std::uint32_t bits) noexcept {
  const bool m = bsp::mask_irqs(true);
  set_masked(bits);
  (void)bsp::mask_irqs(m);
}

void EventFlags::clear(std::uint32_t bits) noexcept {
  const bool m = bsp::mask_irqs(true);
  flags_ &= ~bits;
  (void)bsp::mask_irqs(m);
}

}  // namespace k
