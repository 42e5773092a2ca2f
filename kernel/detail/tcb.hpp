/**
 * @file tcb.hpp
 * @brief Task control block and the per-tile kernel state (internal).
 */
#pragma once

#include "bsp_tile64/api/memory.hpp"
#include "bsp_tile64/api/port.hpp"
#include "kernel/config.hpp"
#include "kernel/config_check.hpp"
#include "kernel/task_table.hpp"
#include "kernel/types.hpp"

#include <array>
#include <cstddef>
#include <cstdint>

namespace k::detail {

enum class TaskState : std::uint8_t {
  kReady,       ///< in a ready queue, or running
  kBlocked,     ///< waiting on an object and/or a timeout
  kWaitPeriod,  ///< periodic task waiting for its next release
  kDormant,     ///< returned from its entry
  kFaulted,     ///< stopped by the kernel (stack overflow)
};

/** Why a blocked task woke up. */
enum class WakeReason : std::uint8_t { kNone, kSignalled, kTimeout };

struct Tcb {
  bsp::Context ctx;
  const TaskSpec* spec;
  std::byte* stack;  ///< lowest address; the canary sits here
  std::uint32_t stack_bytes;
  std::uint8_t priority;
  TaskId id;
  TaskState state;
  WakeReason wake;
  TaskId next_ready;   ///< ready FIFO link
  TaskId next_waiter;  ///< wait-list link
  void* wait_object;   ///< object waited on (nullptr: sleep only)
  Ticks wake_tick;     ///< timeout tick, or 0 for none
  std::uint32_t wait_arg;  ///< object-specific (event mask, wanted mode)
  std::uint32_t wait_result;
  bool wait_mode_all;      ///< event flags: wait for all wanted bits
  // Periodic accounting.
  Ticks next_release;
  Ticks deadline_tick;
  bool job_done;
  bool miss_counted;
  // Health counters.
  std::uint64_t activations;    ///< times the task was switched in
  std::uint64_t jobs;           ///< periodic jobs completed
  std::uint32_t deadline_misses;
  std::uint32_t overruns;       ///< releases skipped because the previous job ran on
  bsp::Cycles last_run_cycle;
  Ticks last_checkin;           ///< tick of the last k::checkin() (the task's start before the first)
  std::uint64_t checkins;
  Ticks max_checkin_gap;        ///< longest time between two check-ins (the task's start counts as one)
};

/** A FIFO of task ids linked through Tcb::next_ready. */
struct Fifo {
  TaskId head = kNoTask;
  TaskId tail = kNoTask;
};

struct TraceEntry {
  bsp::Cycles cycle;
  std::uint16_t kind;
  std::uint8_t a;
  std::uint8_t b;
};

/** The whole kernel state of one tile; carved from the tile's RAM region at start. */
struct KernelState {
  std::array<Tcb, config::kMaxTasks> tcbs;
  std::array<Fifo, config::kNumPriorities> ready;
  std::uint32_t ready_bitmap;  ///< bit p set when ready[p] is not empty
  std::uint32_t task_count;    ///< including idle (the last slot used)
  TaskId current;
  TaskId idle;
  Ticks ticks;
  bsp::Cycles tick_cycles;
  bsp::TileId tile;
  std::uint32_t faults;        ///< stack overflows detected
  std::uint32_t trace_head;
  std::array<TraceEntry, config::kTraceRing> trace_ring;
  bsp::Context boot_ctx;       ///< where start() came from (never resumed)
};

/*
 * What an upset of the kernel state does (bsp::ControlLayout). Host state,
 * modelled as a crash of the tile: the saved host contexts, the pointers (task
 * spec, stack, the object waited on), a stack's extent, and `current`, which
 * says into which saved host context the running one is saved at the next
 * switch (a wrong one resumes a context on a stack that moved on). The rest is
 * the tile's own state, flipped for real: check_kernel() (sched.cpp) finds an
 * upset task count, idle task, tile, priority, task id or ready queue at each
 * scheduler entry and repairs it (kKernelStateBad in the trace); a task state
 * or a timer that is wrong stops or wakes a task, which its watchdog sees.
 */
inline constexpr std::array kTcbFields{
    BSP_CONTROL_HOST(Tcb, ctx),
    BSP_CONTROL_HOST(Tcb, spec),
    BSP_CONTROL_HOST(Tcb, stack),
    BSP_CONTROL_HOST(Tcb, stack_bytes),
    BSP_CONTROL_STATE(Tcb, priority),
    BSP_CONTROL_STATE(Tcb, id),
    BSP_CONTROL_STATE(Tcb, state),
    BSP_CONTROL_STATE(Tcb, wake),
    BSP_CONTROL_STATE(Tcb, next_ready),
    BSP_CONTROL_STATE(Tcb, next_waiter),
    BSP_CONTROL_HOST(Tcb, wait_object),
    BSP_CONTROL_STATE(Tcb, wake_tick),
    BSP_CONTROL_STATE(Tcb, wait_arg),
    BSP_CONTROL_STATE(Tcb, wait_result),
    BSP_CONTROL_STATE(Tcb, wait_mode_all),
    BSP_CONTROL_STATE(Tcb, next_release),
    BSP_CONTROL_STATE(Tcb, deadline_tick),
    BSP_CONTROL_STATE(Tcb, job_done),
    BSP_CONTROL_STATE(Tcb, miss_counted),
    BSP_CONTROL_STATE(Tcb, activations),
    BSP_CONTROL_STATE(Tcb, jobs),
    BSP_CONTROL_STATE(Tcb, deadline_misses),
    BSP_CONTROL_STATE(Tcb, overruns),
    BSP_CONTROL_STATE(Tcb, last_run_cycle),
    BSP_CONTROL_STATE(Tcb, last_checkin),
    BSP_CONTROL_STATE(Tcb, checkins),
    BSP_CONTROL_STATE(Tcb, max_checkin_gap),
};
inline constexpr bsp::ControlLayout kTcbLayout{kTcbFields, sizeof(Tcb), alignof(Tcb)};
static_assert(bsp::control_layout_ok(kTcbLayout), "every member of Tcb");

inline constexpr std::array kFifoFields{BSP_CONTROL_STATE(Fifo, head), BSP_CONTROL_STATE(Fifo, tail)};
inline constexpr bsp::ControlLayout kFifoLayout{kFifoFields, sizeof(Fifo), alignof(Fifo)};
static_assert(bsp::control_layout_ok(kFifoLayout), "every member of Fifo");

inline constexpr std::array kTraceEntryFields{BSP_CONTROL_STATE(TraceEntry, cycle), BSP_CONTROL_STATE(TraceEntry, kind),
                                              BSP_CONTROL_STATE(TraceEntry, a), BSP_CONTROL_STATE(TraceEntry, b)};
inline constexpr bsp::ControlLayout kTraceEntryLayout{kTraceEntryFields, sizeof(TraceEntry), alignof(TraceEntry)};
static_assert(bsp::control_layout_ok(kTraceEntryLayout), "every member of TraceEntry");

inline constexpr std::array kKernelStateFields{
    BSP_CONTROL_NESTED(KernelState, tcbs, kTcbLayout),
    BSP_CONTROL_NESTED(KernelState, ready, kFifoLayout),
    BSP_CONTROL_STATE(KernelState, ready_bitmap),
    BSP_CONTROL_STATE(KernelState, task_count),
    BSP_CONTROL_HOST(KernelState, current),
    BSP_CONTROL_STATE(KernelState, idle),
    BSP_CONTROL_STATE(KernelState, ticks),
    BSP_CONTROL_STATE(KernelState, tick_cycles),
    BSP_CONTROL_STATE(KernelState, tile),
    BSP_CONTROL_STATE(KernelState, faults),
    BSP_CONTROL_STATE(KernelState, trace_head),
    BSP_CONTROL_NESTED(KernelState, trace_ring, kTraceEntryLayout),
    BSP_CONTROL_HOST(KernelState, boot_ctx),
};
inline constexpr bsp::ControlLayout kKernelStateLayout{kKernelStateFields, sizeof(KernelState), alignof(KernelState)};
static_assert(bsp::control_layout_ok(kKernelStateLayout), "every member of KernelState");

}  // namespace k::detail
