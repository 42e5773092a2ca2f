/**
 * @file task_table.hpp
 * @brief Static task tables: one constexpr table per tile role, checked at compile time.
 *
 * Example:
 * @code
 *   constexpr k::TaskSpec kVisionTasks[] = {
 *       {"vision", &vision_main, nullptr, 4, 0, 0, 32 * 1024, k::Policy::kPreemptive},
 *       {"health", &health_main, nullptr, 8, 100, 100, 16 * 1024, k::Policy::kCooperative},
 *   };
 *   static_assert(k::check_table(kVisionTasks) == k::TableError::kOk);
 * @endcode
 */
#pragma once

#include "bsp_tile64/api/memory.hpp"
#include "bsp_tile64/api/port.hpp"
#include "kernel/config.hpp"

#include <cstddef>
#include <cstdint>
#include <span>
#include <type_traits>

namespace k {

enum class Policy : std::uint8_t {
  kPreemptive,   ///< preempted as soon as a more urgent task is ready
  kCooperative,  ///< runs until it blocks or yields
};

/** Entry of a task. A periodic task loops on wait_period(); returning ends the task. */
using TaskEntry = void (*)(void* arg);

struct TaskSpec {
  const char* name;
  TaskEntry entry;
  void* arg;
  std::uint8_t priority;        ///< 0 most urgent; below kNumPriorities - 1 (the idle level)
  std::uint32_t period_ticks;   ///< 0: aperiodic
  std::uint32_t deadline_ticks; ///< relative deadline; 0 means equal to the period
  std::uint32_t stack_bytes;    ///< multiple of 16, at least bsp::kMinStackBytes
  Policy policy;
  /**
   * Check-in budget for the tile's health agent: the task calls k::checkin()
   * at least once every watch_ticks, or the agent stops kicking the tile's
   * hardware watchdog. 0: not watched.
   */
  std::uint32_t watch_ticks = 0U;
};

using TaskTable = std::span<const TaskSpec>;

enum class TableError : std::uint8_t {
  kOk,
  kEmpty,
  kTooManyTasks,
  kNullEntry,
  kDuplicateName,
  kBadPriority,
  kStackTooSmall,
  kStackMisaligned,
  kDeadlineAfterPeriod,
  kOverBudget,  ///< stacks and control blocks exceed the tile's RAM region
};

/** Bytes of tile RAM the kernel itself takes besides task stacks (control blocks, idle stack). */
inline constexpr std::size_t kKernelOverheadBytes = std::size_t{8U} * 1024U + config::kIdleStackBytes;

namespace detail {
constexpr bool same_name(const char* a, const char* b) noexcept {
  std::size_t i = 0;
  for (; i < 64U && a[i] != '\0' && a[i] == b[i]; ++i) {
  }
  return i == 64U || a[i] == b[i];
}
}  // namespace detail

/** Checks a table; usable in static_assert. Bounded by kMaxTasks^2 name comparisons. */
constexpr TableError check_table(TaskTable t) noexcept {
  if (t.empty()) {
    return TableError::kEmpty;
  }
  if (t.size() > config::kMaxTasks - 1U) {  // one slot is the idle task's
    return TableError::kTooManyTasks;
  }
  std::size_t bytes = kKernelOverheadBytes;
  for (std::size_t i = 0; i < t.size(); ++i) {
    const TaskSpec& s = t[i];
    // A null entry is caught when start() checks the table at run time. At
    // compile time the address of a function defined in another translation
    // unit cannot be compared with null under -fno-delete-null-pointer-checks
    // (implied by UBSan), which would make every static_assert ill-formed.
    if (s.name == nullptr || (!std::is_constant_evaluated() && s.entry == nullptr)) {
      return TableError::kNullEntry;
    }
    for (std::size_t j = 0; j < i; ++j) {
      if (detail::same_name(s.name, t[j].name)) {
        return TableError::kDuplicateName;
      }
    }
    if (s.priority >= config::kNumPriorities - 1U) {
      return TableError::kBadPriority;
    }
    if (s.stack_bytes < bsp::kMinStackBytes) {
      return TableError::kStackTooSmall;
    }
    if (s.stack_bytes % 16U != 0U) {
      return TableError::kStackMisaligned;
    }
    if (s.period_ticks != 0U && s.deadline_ticks > s.period_ticks) {
      return TableError::kDeadlineAfterPeriod;
    }
    bytes += s.stack_bytes;
  }
  return bytes <= bsp::kTileRamBytes ? TableError::kOk : TableError::kOverBudget;
}

}  // namespace k
