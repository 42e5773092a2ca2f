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
 * Sanitizer builds keep swapcontext for every switch (ASan's fiber
 * annotations are written for it, and its longjmp interceptor would clear the
 * wrong stack's shadow).
 */
// _FORTIFY_SOURCE turns _longjmp into __longjmp_chk, which refuses a jump to
// another stack: these jumps go between fiber stacks by design.
#if defined(_FORTIFY_SOURCE)
#undef _FORTIFY_SOURCE
#endif
#include "bsp_tile64/board_state.hpp"
#include "bsp_tile64/port.hpp"

#include <cstring>

#include <ucontext.h>

#if defined(__SANITIZE_ADDRESS__)
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
#if defined(__SANITIZE_ADDRESS__)
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
#if defined(__SANITIZE_ADDRESS__)
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

namespace detail {

void switch_raw(Context& from, Context& to) noexcept {
  g_switch_from = &from;
  g_switch_to = &to;
  asan_start(&from.asan_fake_stack, to.stack_base, to.stack_bytes);
#if defined(__SANITIZE_ADDRESS__)
  if (swapcontext(&from.uc, &to.uc) != 0) {
    __builtin_trap();  // cannot happen with a context made by context_init: nothing sane to continue with
  }
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
#if !defined(__SANITIZE_ADDRESS__)
  if (to.has_jb) {
    _longjmp(to.jb, 1);  // NOLINT(cert-err52-cpp): fiber switch, see the file comment
  }
#endif
  static_cast<void>(setcontext(&to.uc));
  __builtin_trap();  // setcontext returns only on failure
}

void unpoison(std::byte* p, std::size_t bytes) noexcept {
#if defined(__SANITIZE_ADDRESS__)
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
}

void context_switch(Context& from, Context& to) noexcept {
  detail::Tile* t = detail::running_tile();
  if (t != nullptr) {
    t->current = &to;
  }
  detail::switch_raw(from, to);
}

}  // namespace bsp
