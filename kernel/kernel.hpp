/**
 * @file kernel.hpp
 * @brief The kernel's public interface in one include.
 */
#pragma once

#include "kernel/event.hpp"
#include "kernel/pool.hpp"
#include "kernel/queue.hpp"
#include "kernel/sched.hpp"
#include "kernel/sem.hpp"
#include "kernel/task_table.hpp"
#include "kernel/types.hpp"
