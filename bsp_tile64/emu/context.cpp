/**
 * @file context.cpp
 * @brief The context-switch port: ucontext fibers on caller-provided stacks, with ASan fiber annotations.
 *
 * A new context starts in a trampoline that reads its entry and argument from a
 * launch record at the top of its own stack, so no pointer has to be squeezed
 * through makecontext's int arguments. A context is entered the first time
 * with swapcontext (makecontext is the portable way onto a new stack); after
 * that, every switch saves with _setjmp and resumes with _longjmp, which leave
 * the signal mask alone: swapcontext's rt_sigprocmask syscall cost ~200 ns per
 * switch (tests/bench/board_bench), the largest share of a mission's host
 * time. The emulator takes no signals, so the mask never needs switching.
 * On x86-64 a switch is smaller still: the callee-saved registers pushed on
 * the running stack, its stack pointer saved, the other's loaded and its
 * registers popped (bsp_fiber_swap below; glibc's _longjmp also demangles
 * pointers and walks cleanup handlers). A fresh context gets a first frame
 * that returns into its trampoline, so it needs no swapcontext either. The
 * floating-point control words stay the thread's, as with _longjmp.
 * Sanitizer builds keep swapcontext for every switch (ASan's fiber
 * annotations are written for it, and its longjmp interceptor would clear the
 * wrong stack's shadow).
 */
// _FORTIFY_SOURCE turns _longjmp into __longjmp_chk, which refuses a jump to
// another stack: these jumps go between fiber stacks by design.
#if defined(_FORTIFY_SOURCE)
#undef _FORTIFY_SOURCE
#endif
#include "bsp_tile64/emu/board_state.hpp"
#include "bsp_tile64/api/port.hpp"

#include <cstdint>
#include <cstring>

#include <ucontext.h>

#if BSP_ASAN
#include <sanitizer/asan_interface.h>
#include <sanitizer/common_interface_defs.h>
#endif

namespace bsp {
namespace {

/** Entry and argument of a context that has not started yet; stored at its stack top. */
struct Launch {
  ContextEntry entry;
  void* arg;
};
constexpr std::size_t kLaunchBytes = 32U;  // sizeof(Launch) rounded up to keep the stack 16-aligned
static_assert(sizeof(Launch) <= kLaunchBytes);

Context* g_switch_from = nullptr;  // context that made the last switch
Context* g_switch_to = nullptr;    // context the last switch resumed

void asan_start(void** fake_save, const void* bottom, std::size_t size) noexcept {
#if BSP_ASAN
  __sanitizer_start_switch_fiber(fake_save, bottom, size);
#else
  static_cast<void>(fake_save);
  static_cast<void>(bottom);
  static_cast<void>(size);
#endif
}

/**
 * Completes a switch and records where the context we came from really has its
 * stack: a Context saved by context_switch() may have been made by the host or
 * reused across stacks (a boot context after a reset), so its bounds are taken
 * from ASan on every switch rather than trusted.
 */
void asan_finish(void* fake_save) noexcept {
#if BSP_ASAN
  const void* bottom = nullptr;
  std::size_t size = 0U;
  __sanitizer_finish_switch_fiber(fake_save, &bottom, &size);
  if (g_switch_from != nullptr && bottom != nullptr) {
    g_switch_from->stack_base = const_cast<void*>(bottom);  // NOLINT(cppcoreguidelines-pro-type-const-cast): ASan API gives a const pointer to a stack we own
    g_switch_from->stack_bytes = size;
  }
#else
  static_cast<void>(fake_save);
#endif
}

void trampoline() {
  asan_finish(nullptr);
  Context* self = g_switch_to;
  Launch launch{};
  std::memcpy(&launch, static_cast<std::byte*>(self->stack_base) + self->stack_bytes, sizeof(Launch));
  detail::on_context_start();
  launch.entry(launch.arg);
  detail::on_context_return();
}

}  // namespace

#if defined(__x86_64__) && !BSP_ASAN
#define BSP_FIBER_SWAP 1  // NOLINT(cppcoreguidelines-macro-usage): selects the switch below at compile time

extern "C" {
/** Pushes the callee-saved registers, stores the stack pointer in *save_sp, loads load_sp, pops and returns there. */
void bsp_fiber_swap(void** save_sp, void* load_sp) noexcept;
/** Where a fresh context's first frame returns to: calls bsp_fiber_entry on a 16-byte aligned stack. */
void bsp_fiber_start() noexcept;
/** The C++ side of bsp_fiber_start. */
[[noreturn]] void bsp_fiber_entry() noexcept;
}

// The System V callee-saved registers; everything else is dead across the call.
asm(R"(
  .text
  .p2align 4
  .globl bsp_fiber_swap
  .hidden bsp_fiber_swap
  .type bsp_fiber_swap, @function
bsp_fiber_swap:
  pushq %rbp
  pushq %rbx
  pushq %r12
  pushq %r13
  pushq %r14
  pushq %r15
  movq %rsp, (%rdi)
  movq %rsi, %rsp
  popq %r15
  popq %r14
  popq %r13
  popq %r12
  popq %rbx
  popq %rbp
  ret
  .size bsp_fiber_swap, .-bsp_fiber_swap

  .p2align 4
  .globl bsp_fiber_start
  .hidden bsp_fiber_start
  .type bsp_fiber_start, @function
bsp_fiber_start:
  call bsp_fiber_entry
  ud2
  .size bsp_fiber_start, .-bsp_fiber_start
)");

void bsp_fiber_entry() noexcept {
  trampoline();
  __builtin_trap();  // the trampoline leaves through on_context_return() and never comes back
}

namespace {

/** Registers bsp_fiber_swap pops (r15 r14 r13 r12 rbx rbp), then its return address. */
constexpr std::size_t kFirstFrameWords = 7U;

/** Lays out a first frame below the top of [stack, stack + usable) that bsp_fiber_swap resumes into bsp_fiber_start. */
void first_frame(Context& ctx, std::byte* stack, std::size_t usable) noexcept {
  // After the return pops the frame, the stack pointer is 16-byte aligned, as a call expects it.
  const std::size_t misalign = reinterpret_cast<std::uintptr_t>(stack + usable) % 16U;  // NOLINT(cppcoreguidelines-pro-type-reinterpret-cast): the alignment of a stack address
  const std::size_t after_return = usable - misalign - 16U;
  std::byte* const frame = stack + (after_return - kFirstFrameWords * sizeof(void*));
  std::memset(frame, 0, (kFirstFrameWords - 1U) * sizeof(void*));  // the registers it pops
  void (*const start)() noexcept = &bsp_fiber_start;
  std::memcpy(frame + (kFirstFrameWords - 1U) * sizeof(void*), &start, sizeof start);  // the return address
  ctx.sp = frame;
  ctx.has_jb = true;
}

}  // namespace
#endif

namespace detail {

void switch_raw(Context& from, Context& to) noexcept {
  g_switch_from = &from;
  g_switch_to = &to;
  asan_start(&from.asan_fake_stack, to.stack_base, to.stack_bytes);
#if BSP_ASAN
  if (swapcontext(&from.uc, &to.uc) != 0) {
    __builtin_trap();  // cannot happen with a context made by context_init: nothing sane to continue with
  }
#elif defined(BSP_FIBER_SWAP)
  from.has_jb = true;
  bsp_fiber_swap(&from.sp, to.sp);  // to.sp is valid: every context was made by context_init or has switched away
#else
  if (_setjmp(from.jb) == 0) {  // NOLINT(cert-err52-cpp): fiber switch, see the file comment
    from.has_jb = true;
    if (to.has_jb) {
      _longjmp(to.jb, 1);  // NOLINT(cert-err52-cpp): fiber switch, see the file comment
    }
    if (swapcontext(&from.uc, &to.uc) != 0) {  // first entry into a fresh context
      __builtin_trap();
    }
  }
#endif
  asan_finish(from.asan_fake_stack);
}

void switch_abandon(Context& to) noexcept {
  g_switch_from = &board().scratch_ctx;
  g_switch_to = &to;
  asan_start(nullptr, to.stack_base, to.stack_bytes);  // nullptr: this fiber is gone for good
#if defined(BSP_FIBER_SWAP)
  bsp_fiber_swap(&board().scratch_ctx.sp, to.sp);  // the scratch context is never resumed
  __builtin_trap();
#elif !BSP_ASAN
  if (to.has_jb) {
    _longjmp(to.jb, 1);  // NOLINT(cert-err52-cpp): fiber switch, see the file comment
  }
#endif
  static_cast<void>(setcontext(&to.uc));
  __builtin_trap();  // setcontext returns only on failure
}

void unpoison(std::byte* p, std::size_t bytes) noexcept {
#if BSP_ASAN
  __asan_unpoison_memory_region(p, bytes);
#else
  static_cast<void>(p);
  static_cast<void>(bytes);
#endif
}

}  // namespace detail

void context_init(Context& ctx, std::byte* stack, std::size_t stack_bytes, ContextEntry entry, void* arg) noexcept {
  // A reused stack may still carry ASan redzones of frames that never returned.
  detail::unpoison(stack, stack_bytes);
  const std::size_t usable = stack_bytes - kLaunchBytes;
  const Launch launch{entry, arg};
  std::memcpy(stack + usable, &launch, sizeof(Launch));
  if (getcontext(&ctx.uc) != 0) {
    __builtin_trap();  // getcontext does not fail on Linux; continuing would run garbage
  }
  ctx.uc.uc_stack.ss_sp = stack;
  ctx.uc.uc_stack.ss_size = usable;
  ctx.uc.uc_link = nullptr;
  ctx.stack_base = stack;
  ctx.stack_bytes = usable;
  ctx.asan_fake_stack = nullptr;
  ctx.has_jb = false;
  makecontext(&ctx.uc, trampoline, 0);
#if defined(BSP_FIBER_SWAP)
  first_frame(ctx, stack, usable);
#endif
}

void context_switch(Context& from, Context& to) noexcept {
  detail::Tile* t = detail::running_tile();
  if (t != nullptr) {
    t->current = &to;
  }
  detail::switch_raw(from, to);
}

}  // namespace bsp
