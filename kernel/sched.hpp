/**
 * @file sched.hpp
 * @brief The per-tile kernel: start from a task table, scheduling, time, health counters.
 *
 * One kernel instance runs on every tile, from a static task table. Scheduling
 * is fixed-priority preemptive (0 most urgent), FIFO among equal priorities,
 * with cooperative tasks as an option (they run until they block or yield).
 * Preemption happens at a timer interrupt that falls inside another task's
 * charged work, at any other interrupt that readies a more urgent task, or
 * when a running task readies one.
 *
 * Periodic tasks are released every period_ticks from tick 0 and end each job
 * with wait_period(). Overrun policy: a release that finds the previous job
 * still running is skipped and counted as an overrun; the late job's deadline
 * miss is counted once, at its deadline tick. Both are traced.
 *
 * Calls tagged [task] run on a task of the current tile; [isr] also in an
 * interrupt hook; [host] outside any tile (images, tests).
 */
#pragma once

#include "bsp_tile64/api/port.hpp"
#include "kernel/task_table.hpp"
#include "kernel/types.hpp"

#include <cstdint>

namespace k {

/** Kernel trace event kinds (in bsp::trace and the per-tile ring). */
enum class TraceKind : std::uint16_t {
  kStart = bsp::kTraceKernelBase,
  kSwitch,        ///< a: from task, b: to task
  kRelease,       ///< a: task
  kBlock,         ///< a: task
  kDeadlineMiss,  ///< a: task
  kOverrun,       ///< a: task
  kStackOverflow, ///< a: task
  kTaskExit,      ///< a: task
  kWaitListCut,   ///< a: the link that named no waiter (an upset wait list), b: the running task
  /**
   * The kernel's own state held a value no valid state holds (an upset of its
   * RAM), repaired: a: what (1 task count, 2 idle task, 3 tile, 4 a task's
   * priority, 5 a task's id, 6 the ready queues, rebuilt), b: the task or the
   * priority level (0 for the first three).
   */
  kKernelStateBad,
};

/** Registers the task table and tick of a tile, used by boot_entry(). [host] */
void set_task_table(bsp::TileId tile, TaskTable table, bsp::Cycles tick_cycles) noexcept;

/** bsp::BootEntry that starts the kernel from the tile's registered table; never returns. */
void boot_entry(bsp::TileId tile) noexcept;

/**
 * Starts the kernel on the current tile from @p table: carves control blocks and
 * stacks from the tile's RAM, adds the idle task, releases every task at tick 0,
 * starts the tick timer and runs the most urgent task. Never returns on success.
 * @return kBadArg for an invalid table, kNoMemory if the tile's RAM cannot hold it.
 */
Status start(TaskTable table, bsp::Cycles tick_cycles) noexcept;

/**
 * The running task tells its tile's health agent it is making progress (the
 * task watchdog's feed): records the current tick as its last check-in. [task]
 */
void checkin() noexcept;

/** Moves the running task behind the other ready tasks of its priority. [task] */
void yield() noexcept;

/** Ticks since the kernel of the current tile started. [task|isr] */
Ticks now_ticks() noexcept;

/** Blocks the running task for @p ticks ticks (0: yield). [task] */
void sleep(Ticks ticks) noexcept;

/** Blocks the running task until the tick count reaches @p tick. [task] */
void sleep_until(Ticks tick) noexcept;

/** Ends the current job of a periodic task and blocks until its next release. [task] */
Status wait_period() noexcept;

/**
 * Moves the running periodic task's next release to the first tick at which
 * the board's time in ticks (bsp::now(), not the tile's ticks since its boot)
 * is @p phase modulo its period: a task started late (its tile switched on or
 * reset in flight) is then released together with a peer whose releases fall
 * at that phase. Call before wait_period(). [task]
 * @return kBadState for a task that is not periodic or a phase not below its period.
 */
Status align_period(std::uint32_t phase) noexcept;

/** Identifier of the running task. [task] */
TaskId self() noexcept;

/** Interrupt hook of a device or network driver, run in the kernel's interrupt handler. */
using IsrHook = void (*)(bsp::TileId tile);

/** Installs @p hook for @p irq on the current tile (the timer is the kernel's own). [task] */
Status set_isr(bsp::Irq irq, IsrHook hook) noexcept;

/** Health view of one task. */
struct TaskStats {
  const char* name;
  std::uint8_t priority;
  std::uint8_t state;  ///< detail::TaskState as a number
  std::uint64_t activations;
  std::uint64_t jobs;
  std::uint32_t deadline_misses;
  std::uint32_t overruns;
  bsp::Cycles last_run_cycle;
  std::uint32_t stack_bytes;
  std::uint32_t stack_high_water;  ///< most stack bytes ever used (from the paint)
  std::uint32_t watch_ticks;       ///< check-in budget from the task table (0: not watched)
  Ticks last_checkin;              ///< tick of the last check-in (0 before the first)
  std::uint64_t checkins;
  Ticks max_checkin_gap;           ///< longest time between two check-ins, in ticks
};

/** Number of tasks on @p tile including idle; 0 if its kernel is not running. [task|host] */
std::uint32_t task_count(bsp::TileId tile) noexcept;

/** Stats of task @p id on @p tile. @return kBadArg if out of range. [task|host] */
Status task_stats(bsp::TileId tile, TaskId id, TaskStats* out) noexcept;

/** What a tile's agent needs to watch one task's check-ins: cheap, no stack scan. */
struct TaskWatch {
  std::uint32_t watch_ticks;  ///< check-in budget from the task table (0: not watched)
  Ticks last_checkin;         ///< tick of the last check-in (0 before the first)
};

/**
 * Check-in budget and last check-in of task @p id on @p tile (task_stats
 * without the stack's high-water scan, which reads the whole painted stack).
 * @return kBadArg if out of range. [task|host]
 */
Status task_watch(bsp::TileId tile, TaskId id, TaskWatch* out) noexcept;

/** Task id by name on @p tile, or kNoTask. [task|host] */
TaskId find_task(bsp::TileId tile, const char* name) noexcept;

/** Stack overflows detected on @p tile since its kernel started. [task|host] */
std::uint32_t stack_faults(bsp::TileId tile) noexcept;

/** Hook called when the kernel detects a tile fault (stack overflow). [host] */
using FaultHook = void (*)(bsp::TileId tile, TaskId task);
void set_fault_hook(FaultHook hook) noexcept;

}  // namespace k
