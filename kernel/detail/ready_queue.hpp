/**
 * @file ready_queue.hpp
 * @brief O(1) ready queue: a FIFO per priority and a bitmap of non-empty levels (internal).
 */
#pragma once

#include "kernel/detail/tcb.hpp"

#include <bit>

namespace k::detail {

/**
 * The ready level of @p t. A priority is the tile's own state and can take an
 * upset: one past the levels is taken again from the task's table entry (the
 * kernel's check traces it at its next entry, check_kernel).
 */
inline Fifo& level_of(KernelState& ks, Tcb& t) noexcept {
  if (t.priority >= config::kNumPriorities) {
    t.priority = t.spec->priority;
  }
  return ks.ready[t.priority % config::kNumPriorities];
}

inline void ready_push(KernelState& ks, TaskId id) noexcept {
  Tcb& t = ks.tcbs[id];
  Fifo& q = level_of(ks, t);
  t.next_ready = kNoTask;
  if (q.tail >= config::kMaxTasks) {  // kNoTask, or an upset tail: the queues are rebuilt at the next check
    q.head = id;
  } else {
    ks.tcbs[q.tail].next_ready = id;
  }
  q.tail = id;
  ks.ready_bitmap |= (1U << t.priority);
}

/** Puts @p id at the head of its level (a preempted task keeps its turn). */
inline void ready_push_front(KernelState& ks, TaskId id) noexcept {
  Tcb& t = ks.tcbs[id];
  Fifo& q = level_of(ks, t);
  t.next_ready = q.head;
  q.head = id;
  if (q.tail >= config::kMaxTasks) {
    q.tail = id;
  }
  ks.ready_bitmap |= (1U << t.priority);
}

/** Most urgent ready task (lowest priority number), or kNoTask. O(1). */
inline TaskId ready_peek(const KernelState& ks) noexcept {
  if (ks.ready_bitmap == 0U) {
    return kNoTask;
  }
  const auto level = static_cast<std::uint32_t>(std::countr_zero(ks.ready_bitmap));
  const TaskId head = ks.ready[level].head;
  return head < config::kMaxTasks ? head : kNoTask;  // an upset head: the kernel's check rebuilds the queues
}

inline TaskId ready_pop(KernelState& ks) noexcept {
  const TaskId id = ready_peek(ks);
  if (id == kNoTask) {
    return kNoTask;
  }
  Tcb& t = ks.tcbs[id];
  Fifo& q = level_of(ks, t);
  q.head = t.next_ready;
  if (q.head == kNoTask) {
    q.tail = kNoTask;
    ks.ready_bitmap &= ~(1U << t.priority);
  }
  t.next_ready = kNoTask;
  return id;
}

}  // namespace k::detail
