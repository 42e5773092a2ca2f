/**
 * @file sched.cpp
 * @brief Kernel start, task switching, blocking and the interrupt handler.
 *
 * Interrupt mask protocol: kernel code that touches shared state runs with the
 * tile's interrupts masked. A context switch always happens masked; the resumed
 * context restores its own mask afterwards (a new task unmasks in its
 * trampoline). So the mask follows the context, as on a real CPU.
 */
#include "kernel/sched.hpp"

#include "bsp_tile64/api/memory.hpp"
#include "kernel/detail/core.hpp"
#include "kernel/detail/ready_queue.hpp"
#include "kernel/detail/stack.hpp"

#include <array>
#include <new>

namespace k {
namespace detail {
namespace {

struct TileKernel {
  TaskTable table;  ///< the table the tile boots next (a spare is given its role's before its reset)
  bsp::Cycles tick_cycles;
  KernelState* ks;
  bool in_isr;
  std::uint32_t booted_tasks;  ///< tasks of the kernel running now, idle included (check_kernel's reference)
  /*
   * Tickless idle (the timer's compare registers, outside the tile's RAM like
   * booted_tasks): tick k of the kernel is at origin + k * period; `armed`
   * is where the timer expires next.
   */
  bsp::Cycles origin;
  bsp::Cycles armed;
  bsp::Cycles period;  ///< the tick of the kernel running now (start()'s; `tick_cycles` is the next boot's)
};

std::array<TileKernel, bsp::kMaxTiles> g_tiles{};
FaultHook g_fault_hook = nullptr;
std::array<std::array<IsrHook, static_cast<std::size_t>(bsp::Irq::kCount)>, bsp::kMaxTiles> g_isr{};

void wait_remove_in(KernelState& ks, WaitList& wl, TaskId id) noexcept;

/**
 * Checks the running task's canary before it gives up the CPU. A broken canary
 * is a stack overflow: the task is faulted (never runs again), taken off any
 * wait list, counted, traced and reported. @return false if it was faulted.
 */
bool outgoing_ok(KernelState& ks) noexcept {
  Tcb& t = ks.tcbs[ks.current];
  if (detail::stack_canary_ok(t.stack)) {
    return true;
  }
  if (t.wait_object != nullptr) {
    wait_remove_in(ks, *static_cast<WaitList*>(t.wait_object), t.id);
    t.wait_object = nullptr;
  }
  t.wake_tick = 0;
  t.state = TaskState::kFaulted;
  ++ks.faults;
  trace_event(static_cast<std::uint16_t>(TraceKind::kStackOverflow), t.id, t.id);
  if (g_fault_hook != nullptr) {
    g_fault_hook(ks.tile, t.id);
  }
  return false;
}

/** Traces a repair of the kernel's own state: @p what (TraceKind::kKernelStateBad), task or level @p which. */
void repaired(std::uint32_t what, std::uint32_t which) noexcept {
  trace_event(static_cast<std::uint16_t>(TraceKind::kKernelStateBad), static_cast<TaskId>(what),
              static_cast<TaskId>(which));
}

/** True if ready level @p p is a well-formed FIFO of ready tasks of that priority, as the bitmap says. */
bool level_ok(const KernelState& ks, std::uint32_t p) noexcept {
  const Fifo& q = ks.ready[p];
  const bool marked = ((ks.ready_bitmap >> p) & 1U) != 0U;
  if (q.head == kNoTask || q.tail == kNoTask) {
    return q.head == q.tail && !marked;
  }
  TaskId id = q.head;
  for (std::uint32_t n = 0; n < ks.task_count; ++n) {
    if (id >= ks.task_count || ks.tcbs[id].state != TaskState::kReady || ks.tcbs[id].priority != p) {
      return false;
    }
    if (id == q.tail) {
      return marked && ks.tcbs[id].next_ready == kNoTask;
    }
    id = ks.tcbs[id].next_ready;
  }
  return false;  // a cycle, or the tail never reached
}

/** The ready queues again from the tasks' states: every ready task but the running one, by id. */
void rebuild_ready(KernelState& ks) noexcept {
  ks.ready.fill(Fifo{});
  ks.ready_bitmap = 0U;
  for (std::uint32_t i = 0; i < ks.task_count; ++i) {
    if (i != ks.current && ks.tcbs[i].state == TaskState::kReady) {
      ready_push(ks, static_cast<TaskId>(i));
    }
  }
}

/**
 * The kernel state lives in the tile's RAM and can take an upset. At each
 * scheduler entry, before its indices are followed: the task count, the idle
 * task and the tile against the kernel the tile started (its task count kept
 * outside its RAM by start(); the table for the next boot may already be
 * another), each task's priority (its table entry) and id, and the ready
 * queues (rebuilt from the tasks' states when one is not a well-formed FIFO).
 * Each repair is traced (kKernelStateBad). Whole state costs no emulated time.
 */
void check_kernel(KernelState& ks, bsp::TileId tile) noexcept {
  const std::uint32_t count = g_tiles[tile].booted_tasks;
  if (ks.task_count != count) {
    repaired(1U, 0U);
    ks.task_count = count;
  }
  if (ks.idle != count - 1U) {
    repaired(2U, 0U);
    ks.idle = static_cast<TaskId>(count - 1U);
  }
  if (ks.tile != tile) {
    repaired(3U, 0U);
    ks.tile = tile;
  }
  for (std::uint32_t i = 0; i < count; ++i) {
    Tcb& t = ks.tcbs[i];
    if (t.priority != t.spec->priority) {
      repaired(4U, i);
      t.priority = t.spec->priority;
    }
    if (t.id != i) {
      repaired(5U, i);
      t.id = static_cast<TaskId>(i);
    }
  }
  bool queues_ok = true;
  for (std::uint32_t p = 0; p < config::kNumPriorities && queues_ok; ++p) {
    queues_ok = level_ok(ks, p);
  }
  if (!queues_ok) {
    repaired(6U, 0U);
    rebuild_ready(ks);
  }
}

/** The tick the tile's time is in, counted from the kernel's start. */
Ticks tick_now(const TileKernel& tk) noexcept {
  const bsp::Cycles now = bsp::now();
  return tk.period == 0U || now < tk.origin ? 0U : (now - tk.origin) / tk.period;
}

/** The timer's next expiry at the start of tick @p tick. */
void arm(TileKernel& tk, Ticks tick) noexcept {
  const bsp::Cycles at = tk.origin + tick * tk.period;
  if (at != tk.armed) {
    tk.armed = at;
    bsp::timer_next(at);
  }
}

/**
 * The first tick after ks.ticks at which the kernel has something to do by
 * itself: a timeout, a periodic release, or the deadline of a job still
 * running. At most kMaxIdleTicks ahead (an interrupt wakes the tile sooner).
 */
Ticks next_due(const KernelState& ks) noexcept {
  Ticks due = ks.ticks + config::kMaxIdleTicks;
  const std::uint32_t count = ks.task_count < config::kMaxTasks ? ks.task_count : config::kMaxTasks;
  for (std::uint32_t i = 0; i < count; ++i) {
    const Tcb& t = ks.tcbs[i];
    if (t.state == TaskState::kBlocked && t.wake_tick != 0U && t.wake_tick < due) {
      due = t.wake_tick;
    }
    if (t.spec->period_ticks == 0U || t.state == TaskState::kDormant || t.state == TaskState::kFaulted) {
      continue;
    }
    due = t.next_release < due ? t.next_release : due;
    if (!t.job_done && !t.miss_counted && t.deadline_tick < due) {
      due = t.deadline_tick;
    }
  }
  return due > ks.ticks ? due : ks.ticks + 1U;
}

/** Switches from the current task to @p next (a different task). Irqs masked. */
void switch_to(KernelState& ks, TaskId next) noexcept {
  // Tickless: the idle task sleeps the tile to the next tick anything is due; any other task ticks every tick.
  const bsp::TileId tile = bsp::current_tile();
  TileKernel& tk = g_tiles[tile < bsp::kMaxTiles ? tile : 0U];
  if (next == ks.idle) {
    arm(tk, next_due(ks));
  } else if (ks.current == ks.idle) {
    arm(tk, ks.ticks + 1U);
  }
  Tcb& from = ks.tcbs[ks.current];
  Tcb& to = ks.tcbs[next];
  trace_event(static_cast<std::uint16_t>(TraceKind::kSwitch), ks.current, next);
  ks.current = next;
  ++to.activations;
  to.last_run_cycle = bsp::now();
  // The canary at the bottom of the incoming task's stack is checked when it
  // gives the CPU up again; that line is touched by nothing else, so it is
  // fetched now, while the task runs, instead of missing then (a host hint only).
  __builtin_prefetch(to.stack);
  bsp::context_switch(from.ctx, to.ctx);
}

/**
 * The running task gave up the CPU and is not in the ready queue (blocked,
 * waiting for its period, ended): run the most urgent ready task. The idle
 * task is always ready when nothing else is, so there is always one.
 */
void run_next(KernelState& ks) noexcept {
  (void)outgoing_ok(ks);
  check_kernel(ks, bsp::current_tile());
  switch_to(ks, ready_pop(ks));
}

void task_trampoline(void* arg) noexcept {
  auto* t = static_cast<Tcb*>(arg);
  (void)bsp::mask_irqs(false);
  t->spec->entry(t->spec->arg);
  (void)bsp::mask_irqs(true);
  KernelState* ks = current_kernel();
  trace_event(static_cast<std::uint16_t>(TraceKind::kTaskExit), t->id, t->id);
  // A dormant task is never resumed; were an upset of its state to make it ready, it goes dormant
  // again here instead of returning off its context.
  for (;;) {
    t->state = TaskState::kDormant;
    run_next(*ks);
  }
}

void idle_main(void* /*arg*/) noexcept {
  for (;;) {  // the idle loop: sleeps the tile until the next interrupt
    bsp::wait_for_interrupt();
  }
}

constexpr TaskSpec kIdleSpec{"idle", &idle_main, nullptr, config::kNumPriorities - 1U, 0, 0,
                             config::kIdleStackBytes, Policy::kPreemptive};

/**
 * AddressSanitizer builds put redzones around every local and keep more in
 * registers' spill slots, so an instrumented frame is two to three times the
 * release one: their task stacks are this many times the table's size. The
 * release image keeps the table's budgets (check_table), and the canary and
 * high-water checks watch the scaled stacks the same way.
 */
constexpr std::uint32_t kStackScale = bsp::kAddressSanitizer ? 3U : 1U;

Status make_task(KernelState& ks, const TaskSpec& spec, TaskId id) noexcept {
  const std::uint32_t stack_bytes = spec.stack_bytes * kStackScale;
  const bsp::Carve c = bsp::carve_stack(bsp::Region{ks.tile}, stack_bytes, 16U, spec.name);
  std::byte* const stack = c.ptr;
  if (c.error != bsp::MemError::kOk) {
    return Status::kNoMemory;
  }
  Tcb& t = ks.tcbs[id];
  t = Tcb{};
  t.spec = &spec;
  t.stack = stack;
  t.stack_bytes = stack_bytes;
  t.priority = spec.priority;
  t.id = id;
  t.state = TaskState::kReady;
  t.next_ready = kNoTask;
  t.next_waiter = kNoTask;
  if (spec.period_ticks != 0U) {
    t.next_release = spec.period_ticks;
    t.deadline_tick = (spec.deadline_ticks != 0U) ? spec.deadline_ticks : spec.period_ticks;
  }
  detail::stack_prepare(stack, stack_bytes);
  // The canary sits at the bottom; the context uses the rest.
  bsp::context_init(t.ctx, stack + config::kCanaryBytes, stack_bytes - config::kCanaryBytes,
                    &task_trampoline, &t);
  ready_push(ks, id);
  return Status::kOk;
}

Status build_kernel(TaskTable table, bsp::Cycles tick_cycles, KernelState*& out) noexcept {
  const bsp::TileId tile = bsp::current_tile();
  bsp::MemError err = bsp::MemError::kOk;
  auto* ks = bsp::carve_control_array<KernelState>(bsp::Region{tile}, 1, "kernel state", &err, &kKernelStateLayout);
  if (err != bsp::MemError::kOk) {
    return Status::kNoMemory;
  }
  ::new (ks) KernelState{};
  ks->tile = tile;
  ks->tick_cycles = tick_cycles;
  ks->current = kNoTask;
  for (Fifo& f : ks->ready) {
    f = Fifo{};
  }
  for (std::size_t i = 0; i < table.size(); ++i) {
    const Status s = make_task(*ks, table[i], static_cast<TaskId>(i));
    if (s != Status::kOk) {
      return s;
    }
  }
  ks->idle = static_cast<TaskId>(table.size());
  const Status s = make_task(*ks, kIdleSpec, ks->idle);
  if (s != Status::kOk) {
    return s;
  }
  ks->task_count = static_cast<std::uint32_t>(table.size()) + 1U;
  out = ks;
  return Status::kOk;
}

}  // namespace

KernelState* current_kernel() noexcept {
  const bsp::TileId t = bsp::current_tile();
  return t < bsp::kMaxTiles ? g_tiles[t].ks : nullptr;
}

bool can_block() noexcept { return current_kernel() != nullptr && !in_isr(); }

bool in_isr() noexcept {
  const bsp::TileId t = bsp::current_tile();
  return t < bsp::kMaxTiles && g_tiles[t].in_isr;
}

void trace_event(std::uint16_t kind, TaskId a, TaskId b) noexcept {
  KernelState* ks = current_kernel();
  if (ks == nullptr) {
    return;
  }
  TraceEntry& e = ks->trace_ring[ks->trace_head % config::kTraceRing];
  e = TraceEntry{bsp::now(), kind, a, b};
  ++ks->trace_head;
  bsp::trace(kind, a, b);
}

namespace {

/**
 * True if @p link, read from wait list @p wl, is a task blocked on it (or the
 * end). The head lives in the object's memory, which is the tasks' RAM and can
 * take an upset: a link that names no such task ends the list there (traced);
 * the waiters behind it wake by their timeout, or their task's watchdog finds them.
 */
bool link_ok(KernelState& ks, const WaitList& wl, TaskId& link) noexcept {
  if (link == kNoTask ||
      (link < ks.task_count && link < config::kMaxTasks && ks.tcbs[link].wait_object == &wl &&
       ks.tcbs[link].state == TaskState::kBlocked)) {
    return true;
  }
  trace_event(static_cast<std::uint16_t>(TraceKind::kWaitListCut), link, ks.current);
  link = kNoTask;
  return false;
}

void wait_insert(WaitList& wl, KernelState& ks, TaskId id) noexcept {
  Tcb& t = ks.tcbs[id];
  TaskId* link = &wl.head;
  // Behind every waiter of equal or more urgent priority: FIFO among equals.
  for (std::uint32_t n = 0; link_ok(ks, wl, *link) && *link != kNoTask && n < config::kMaxTasks; ++n) {
    if (ks.tcbs[*link].priority > t.priority) {
      break;
    }
    link = &ks.tcbs[*link].next_waiter;
  }
  t.next_waiter = *link;
  *link = id;
}

void wait_remove_in(KernelState& ks, WaitList& wl, TaskId id) noexcept {
  TaskId* link = &wl.head;
  for (std::uint32_t n = 0; link_ok(ks, wl, *link) && *link != kNoTask && n < config::kMaxTasks; ++n) {
    if (*link == id) {
      *link = ks.tcbs[id].next_waiter;
      ks.tcbs[id].next_waiter = kNoTask;
      return;
    }
    link = &ks.tcbs[*link].next_waiter;
  }
}


/** Makes a blocked task ready with @p why; removes it from its wait list. */
void make_ready(KernelState& ks, TaskId id, WakeReason why, std::uint32_t result) noexcept {
  Tcb& t = ks.tcbs[id];
  if (t.wait_object != nullptr) {
    wait_remove_in(ks, *static_cast<WaitList*>(t.wait_object), id);
  }
  t.wait_object = nullptr;
  t.wake_tick = 0;
  t.wake = why;
  t.wait_result = result;
  t.state = TaskState::kReady;
  ready_push(ks, id);
}

}  // namespace

void wait_remove(WaitList& wl, TaskId id) noexcept { wait_remove_in(*current_kernel(), wl, id); }

WakeReason block_current(WaitList* wl, Timeout to, std::uint32_t arg) noexcept {
  KernelState& ks = *current_kernel();
  Tcb& t = ks.tcbs[ks.current];
  t.state = TaskState::kBlocked;
  t.wake = WakeReason::kNone;
  t.wait_arg = arg;
  t.wait_object = wl;
  t.wake_tick = (to.ticks == kForever.ticks) ? 0U : ks.ticks + to.ticks;
  if (wl != nullptr) {
    wait_insert(*wl, ks, t.id);
  }
  trace_event(static_cast<std::uint16_t>(TraceKind::kBlock), t.id, t.id);
  run_next(ks);
  return t.wake;
}

TaskId wake_one(WaitList& wl, std::uint32_t result) noexcept {
  KernelState* ks = current_kernel();
  if (ks == nullptr || !link_ok(*ks, wl, wl.head) || wl.head == kNoTask) {
    return kNoTask;
  }
  const TaskId id = wl.head;
  make_ready(*ks, id, WakeReason::kSignalled, result);
  return id;
}

void wake_task(TaskId id, std::uint32_t result) noexcept {
  KernelState* ks = current_kernel();
  if (ks != nullptr && id < ks->task_count && ks->tcbs[id].state == TaskState::kBlocked) {
    make_ready(*ks, id, WakeReason::kSignalled, result);
  }
}

void reschedule() noexcept {
  KernelState* kp = current_kernel();
  if (kp == nullptr) {
    return;  // not on a tile (host code): nothing to schedule
  }
  KernelState& ks = *kp;
  check_kernel(ks, bsp::current_tile());
  const Tcb& cur = ks.tcbs[ks.current];
  if (cur.spec->policy == Policy::kCooperative) {
    return;  // a cooperative task keeps the CPU until it blocks or yields
  }
  const TaskId next = ready_peek(ks);
  if (next == kNoTask || ks.tcbs[next].priority >= cur.priority) {
    return;
  }
  if (!outgoing_ok(ks)) {
    switch_to(ks, ready_pop(ks));
    return;
  }
  (void)ready_pop(ks);
  ready_push_front(ks, ks.current);  // preempted: first of its level again
  switch_to(ks, next);
}

namespace {

/** Timeouts and periodic releases of one tick. Irqs masked (interrupt handler). */
void tick_tasks(KernelState& ks) noexcept {
  for (std::uint32_t i = 0; i < ks.task_count; ++i) {
    Tcb& t = ks.tcbs[i];
    if (t.state == TaskState::kBlocked && t.wake_tick != 0U && t.wake_tick <= ks.ticks) {
      make_ready(ks, t.id, WakeReason::kTimeout, 0);
    }
    const std::uint32_t period = t.spec->period_ticks;
    if (period == 0U || t.state == TaskState::kDormant || t.state == TaskState::kFaulted) {
      continue;
    }
    if (!t.job_done && !t.miss_counted && ks.ticks >= t.deadline_tick) {
      t.miss_counted = true;
      ++t.deadline_misses;
      trace_event(static_cast<std::uint16_t>(TraceKind::kDeadlineMiss), t.id, t.id);
    }
    if (ks.ticks < t.next_release) {
      continue;
    }
    const std::uint32_t rel = (t.spec->deadline_ticks != 0U) ? t.spec->deadline_ticks : period;
    if (t.state == TaskState::kWaitPeriod) {
      t.job_done = false;
      t.miss_counted = false;
      t.deadline_tick = t.next_release + rel;
      t.state = TaskState::kReady;
      ready_push(ks, t.id);
      trace_event(static_cast<std::uint16_t>(TraceKind::kRelease), t.id, t.id);
    } else {
      ++t.overruns;  // previous job still running: this release is skipped
      trace_event(static_cast<std::uint16_t>(TraceKind::kOverrun), t.id, t.id);
    }
    t.next_release += period;
  }
}

void irq_handler(bsp::TileId tile, bsp::Irq irq) noexcept {
  TileKernel& tk = g_tiles[tile];
  KernelState* ks = tk.ks;
  if (ks == nullptr) {
    return;
  }
  tk.in_isr = true;
  // The interrupted task's canary is checked if the handler switches away
  // from it (reschedule below); its line went cold while other tiles ran.
  __builtin_prefetch(ks->tcbs[ks->current].stack);
  // The ticks from the time (a tickless idle skips the ticks with nothing due).
  ks->ticks = tick_now(tk);
  if (irq == bsp::Irq::kTimer) {
    check_kernel(*ks, tile);
    tk.armed = tk.origin + (ks->ticks + 1U) * tk.period;  // periodic again from here
    tick_tasks(*ks);
  } else {
    const IsrHook hook = g_isr[tile][static_cast<std::size_t>(irq)];
    if (hook != nullptr) {
      hook(tile);
    }
  }
  // Leaving the handler's role before a switch: the resumed context is not in
  // an interrupt; when this one resumes, it finishes its handler.
  tk.in_isr = false;
  reschedule();
  if (ks->current == ks->idle) {
    arm(tk, next_due(*ks));  // still idle: sleep to the next tick anything is due
  }
}

}  // namespace
}  // namespace detail

using detail::KernelState;
using detail::TaskState;
using detail::Tcb;

void set_task_table(bsp::TileId tile, TaskTable table, bsp::Cycles tick_cycles) noexcept {
  if (tile < bsp::kMaxTiles) {
    detail::g_tiles[tile].table = table;
    detail::g_tiles[tile].tick_cycles = tick_cycles;
  }
}

void boot_entry(bsp::TileId tile) noexcept {
  if (tile >= bsp::kMaxTiles) {
    return;
  }
  const detail::TileKernel& s = detail::g_tiles[tile];
  // start() returns only on error: the board sees the boot entry return and
  // keeps the tile idle, where its watchdog (if armed) will report it.
  (void)start(s.table, s.tick_cycles);
}

Status start(TaskTable table, bsp::Cycles tick_cycles) noexcept {
  if (check_table(table) != TableError::kOk || tick_cycles == 0U) {
    return Status::kBadArg;
  }
  const bsp::TileId tile = bsp::current_tile();
  (void)bsp::mask_irqs(true);
  detail::g_tiles[tile].ks = nullptr;
  detail::g_tiles[tile].in_isr = false;
  detail::g_isr[tile] = {};
  KernelState* ks = nullptr;
  const Status s = detail::build_kernel(table, tick_cycles, ks);
  if (s != Status::kOk) {
    return s;
  }
  detail::g_tiles[tile].ks = ks;
  detail::g_tiles[tile].booted_tasks = ks->task_count;
  detail::trace_event(static_cast<std::uint16_t>(TraceKind::kStart), 0, 0);
  // Release every task at tick 0: periodic ones start their first job now.
  bsp::set_irq_handler(tile, &detail::irq_handler);
  bsp::timer_start(tick_cycles);
  detail::g_tiles[tile].origin = bsp::now();
  detail::g_tiles[tile].armed = bsp::now() + tick_cycles;
  detail::g_tiles[tile].period = tick_cycles;
  const TaskId first = detail::ready_pop(*ks);
  ks->current = first;
  Tcb& t = ks->tcbs[first];
  ++t.activations;
  t.last_run_cycle = bsp::now();
  bsp::context_switch(ks->boot_ctx, t.ctx);
  return Status::kBadState;  // the boot context is never resumed
}

void yield() noexcept {
  if (!detail::can_block()) {
    return;
  }
  const bool m = bsp::mask_irqs(true);
  KernelState& ks = *detail::current_kernel();
  detail::check_kernel(ks, bsp::current_tile());
  if (!detail::outgoing_ok(ks)) {
    detail::switch_to(ks, detail::ready_pop(ks));
  } else {
    detail::ready_push(ks, ks.current);
    const TaskId next = detail::ready_pop(ks);
    if (next != ks.current) {
      detail::switch_to(ks, next);
    }
  }
  (void)bsp::mask_irqs(m);
}

Ticks now_ticks() noexcept {
  const KernelState* ks = detail::current_kernel();
  return ks == nullptr ? 0U : ks->ticks;
}

void sleep_until(Ticks tick) noexcept {
  if (!detail::can_block()) {
    return;
  }
  const bool m = bsp::mask_irqs(true);
  KernelState& ks = *detail::current_kernel();
  if (tick > ks.ticks) {
    const Ticks delta = tick - ks.ticks;
    // Sleeps longer than a 32-bit timeout are not needed at 1 ms ticks (49 days).
    const auto ticks = static_cast<std::uint32_t>(delta < kForever.ticks ? delta : kForever.ticks - 1U);
    (void)detail::block_current(nullptr, Timeout{ticks}, 0);
  }
  (void)bsp::mask_irqs(m);
}

void sleep(Ticks ticks) noexcept {
  if (ticks == 0U) {
    yield();
    return;
  }
  sleep_until(now_ticks() + ticks);
}

Status wait_period() noexcept {
  if (!detail::can_block()) {
    return Status::kBadState;
  }
  const bool m = bsp::mask_irqs(true);
  KernelState& ks = *detail::current_kernel();
  Tcb& t = ks.tcbs[ks.current];
  if (t.spec->period_ticks == 0U) {
    (void)bsp::mask_irqs(m);
    return Status::kBadState;
  }
  t.job_done = true;
  ++t.jobs;
  t.state = TaskState::kWaitPeriod;
  detail::run_next(ks);
  (void)bsp::mask_irqs(m);
  return Status::kOk;
}

Status align_period(std::uint32_t phase) noexcept {
  if (!detail::can_block()) {
    return Status::kBadState;
  }
  const bool m = bsp::mask_irqs(true);
  KernelState& ks = *detail::current_kernel();
  Tcb& t = ks.tcbs[ks.current];
  const std::uint32_t period = t.spec->period_ticks;
  const bsp::Cycles tick = bsp::tick_cycles();
  if (period == 0U || phase >= period || tick == 0U) {
    (void)bsp::mask_irqs(m);
    return Status::kBadState;
  }
  const auto now = static_cast<std::uint32_t>((bsp::now() / tick) % period);
  const std::uint32_t ahead = (phase + period - now) % period;
  t.next_release = ks.ticks + (ahead == 0U ? period : ahead);
  (void)bsp::mask_irqs(m);
  return Status::kOk;
}

void checkin() noexcept {
  KernelState* ks = detail::current_kernel();
  if (ks == nullptr || !detail::can_block()) {
    return;
  }
  const bool m = bsp::mask_irqs(true);
  Tcb& t = ks->tcbs[ks->current];
  const Ticks gap = ks->ticks - t.last_checkin;
  t.max_checkin_gap = gap > t.max_checkin_gap ? gap : t.max_checkin_gap;
  t.last_checkin = ks->ticks;
  ++t.checkins;
  (void)bsp::mask_irqs(m);
}

TaskId self() noexcept {
  const KernelState* ks = detail::current_kernel();
  return ks == nullptr ? kNoTask : ks->current;
}

Status set_isr(bsp::Irq irq, IsrHook hook) noexcept {
  const bsp::TileId tile = bsp::current_tile();
  if (tile >= bsp::kMaxTiles || irq == bsp::Irq::kTimer || irq >= bsp::Irq::kCount) {
    return Status::kBadArg;
  }
  detail::g_isr[tile][static_cast<std::size_t>(irq)] = hook;
  return Status::kOk;
}

std::uint32_t task_count(bsp::TileId tile) noexcept {
  if (tile >= bsp::kMaxTiles || detail::g_tiles[tile].ks == nullptr) {
    return 0;
  }
  const std::uint32_t n = detail::g_tiles[tile].ks->task_count;
  return n < config::kMaxTasks ? n : config::kMaxTasks;  // an upset count, until the kernel's next check
}

Status task_stats(bsp::TileId tile, TaskId id, TaskStats* out) noexcept {
  if (out == nullptr || id >= task_count(tile)) {
    return Status::kBadArg;
  }
  const Tcb& t = detail::g_tiles[tile].ks->tcbs[id];
  *out = TaskStats{t.spec->name,    t.priority,       static_cast<std::uint8_t>(t.state),
                   t.activations,   t.jobs,           t.deadline_misses,
                   t.overruns,      t.last_run_cycle, t.stack_bytes,
                   detail::stack_high_water(t.stack, t.stack_bytes),
                   t.spec->watch_ticks, t.last_checkin, t.checkins, t.max_checkin_gap};
  return Status::kOk;
}

Status task_watch(bsp::TileId tile, TaskId id, TaskWatch* out) noexcept {
  if (out == nullptr || id >= task_count(tile)) {
    return Status::kBadArg;
  }
  const Tcb& t = detail::g_tiles[tile].ks->tcbs[id];
  *out = TaskWatch{t.spec->watch_ticks, t.last_checkin};
  return Status::kOk;
}

TaskId find_task(bsp::TileId tile, const char* name) noexcept {
  const std::uint32_t n = task_count(tile);
  for (std::uint32_t i = 0; i < n; ++i) {
    if (detail::same_name(detail::g_tiles[tile].ks->tcbs[i].spec->name, name)) {
      return static_cast<TaskId>(i);
    }
  }
  return kNoTask;
}

std::uint32_t stack_faults(bsp::TileId tile) noexcept {
  return task_count(tile) == 0U ? 0U : detail::g_tiles[tile].ks->faults;
}

void set_fault_hook(FaultHook hook) noexcept { detail::g_fault_hook = hook; }

}  // namespace k
