/**
 * @file config_check.hpp
 * @brief Fails the build on kernel configuration values out of range.
 *
 * Included by kernel/detail/tcb.hpp, which the scheduler and the
 * synchronisation objects include, so no build of the kernel skips it.
 */
#pragma once

#include "bsp_tile64/api/port.hpp"
#include "kernel/config.hpp"

static_assert(k::config::kMaxTasks >= 2 && k::config::kMaxTasks <= 64, "kMaxTasks: 2..64 (idle + one task)");
static_assert(k::config::kNumPriorities >= 2 && k::config::kNumPriorities <= 32,
              "kNumPriorities: 2..32 (one 32-bit ready bitmap)");
static_assert(k::config::kIdleStackBytes >= bsp::kMinStackBytes, "idle stack below the port's minimum");
static_assert(k::config::kCanaryBytes % 16U == 0U, "canary must keep the stack 16-byte aligned");
