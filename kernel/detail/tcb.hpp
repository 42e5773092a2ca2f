/**
 * @file tcb.hpp
 * @brief Task control block and the per-tile kernel state (internal).
 */
#pragma once

#include "bsp_tile64/api/port.hpp"
#include "kernel/config.hpp"
#include "kernel/config_check.hpp"
#include "kernel/task_table.hpp"
#include "kernel/types.hpp"

#include <array>
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

}  // namespace k::detail
