/**
 * @file core.hpp
 * @brief Internal kernel services for the synchronisation objects: blocking and waking.
 */
#pragma once

#include "bsp_tile64/api/memory.hpp"
#include "kernel/detail/tcb.hpp"
#include "kernel/types.hpp"

#include <array>
#include <cstddef>

namespace k::detail {

/** Priority-ordered (FIFO among equals) list of tasks blocked on one object. */
struct WaitList {
  TaskId head = kNoTask;
};

/** A wait list is emulated state (bsp::ControlLayout): the kernel checks every link it follows. */
inline constexpr std::array kWaitListFields{BSP_CONTROL_STATE(WaitList, head)};
inline constexpr bsp::ControlLayout kWaitListLayout{kWaitListFields, sizeof(WaitList), alignof(WaitList)};
static_assert(bsp::control_layout_ok(kWaitListLayout), "every member of WaitList");

/** Kernel state of the current tile (nullptr if its kernel is not running). */
KernelState* current_kernel() noexcept;

/** True on a task of a tile whose kernel runs (not host code, not an interrupt hook). */
bool can_block() noexcept;

/** True while the kernel's interrupt handler runs on this tile. */
bool in_isr() noexcept;

/**
 * Blocks the running task on @p wl (may be nullptr: sleep) until woken or until
 * @p to ticks pass. Interrupts must be masked by the caller (the object's state
 * was checked under the same mask). @return why it woke. [task]
 */
WakeReason block_current(WaitList* wl, Timeout to, std::uint32_t arg) noexcept;

/** Wakes the first waiter of @p wl with @p result; returns its id or kNoTask. [task|isr] */
TaskId wake_one(WaitList& wl, std::uint32_t result) noexcept;

/** Wakes the blocked task @p id (signalled) with @p result. [task|isr] */
void wake_task(TaskId id, std::uint32_t result) noexcept;

/** Removes @p id from @p wl (a waiter that timed out or was satisfied). */
void wait_remove(WaitList& wl, TaskId id) noexcept;

/** After readying tasks from task context: switch if a more urgent task may run. [task] */
void reschedule() noexcept;

/** Trace a kernel event on the current tile. */
void trace_event(std::uint16_t kind, TaskId a, TaskId b) noexcept;

}  // namespace k::detail
