/**
 * @file port.hpp
 * @brief The port contract: everything the kernel may use of the board, and nothing more.
 *
 * This is the single documented interface between the per-tile kernel and the
 * emulated board (as Zephyr's kernel_arch_interface.h is between kernel and
 * arch). The kernel includes this header, bsp_tile64/api/work.hpp and
 * bsp_tile64/api/memory.hpp; it never includes the board's internals. The layers
 * above the board may include from bsp_tile64/ only the board's interface
 * headers (this folder, bsp_tile64/api/: kBoardInterfaceDir in
 * tools/common/rules/flight_rules.hpp), and `make lint` rejects anything else.
 *
 * Execution model (DESIGN.md section 3):
 * - Each tile runs one context at a time: a boot context provided by the board,
 *   then the kernel's task contexts (fibers with static stacks in tile RAM).
 * - Code takes zero emulated time; time advances only through consume() and
 *   wait_for_interrupt(). Both may leave the current context: at a quantum end
 *   the tile returns to the driver and resumes at the next quantum; at an
 *   interrupt the board calls the tile's interrupt handler on the current
 *   context, and the handler may switch to another context (preemption).
 *   consume() returns only when all of its cycles have been charged to the
 *   context that called it.
 * - Interrupts are taken at their exact cycle: an interrupt due at cycle T on a
 *   tile whose context is inside consume() runs when the tile's time reaches T.
 * - Cross-tile effects (interrupts raised by another tile, messages) become
 *   visible at quantum barriers only.
 *
 * Calls marked [task] run on a tile's context; [isr] may also run inside an
 * interrupt handler; [host] are for the image and tests, outside tile contexts.
 */
#pragma once

#include "bsp_tile64/api/work.hpp"

#include <cstddef>
#include <cstdint>

#include <csetjmp>

#include <ucontext.h>

/**
 * BSP_ASAN is 1 in an AddressSanitizer build, whichever compiler made it (GCC defines
 * __SANITIZE_ADDRESS__; Clang 14 only answers __has_feature), else 0. The port annotates its
 * fiber switches for ASan, and the kernel scales task stacks for instrumented frames, by it.
 */
#if defined(__SANITIZE_ADDRESS__)
#define BSP_ASAN 1  // NOLINT(cppcoreguidelines-macro-usage): selects code at compile time
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define BSP_ASAN 1  // NOLINT(cppcoreguidelines-macro-usage): selects code at compile time
#endif
#endif
#ifndef BSP_ASAN
#define BSP_ASAN 0  // NOLINT(cppcoreguidelines-macro-usage): selects code at compile time
#endif

namespace bsp {

/** This build is instrumented by AddressSanitizer (BSP_ASAN). */
inline constexpr bool kAddressSanitizer = BSP_ASAN != 0;

using Cycles = std::uint64_t;
using TileId = std::uint32_t;

inline constexpr TileId kNoTile = 0xFFFF'FFFFU;

// ------------------------------------------------------------------ contexts

/** Entry of a context; must never return (a task's trampoline loops or exits). */
using ContextEntry = void (*)(void* arg);

/** A saved execution context. Plain data, so the kernel can embed it in static TCBs. */
struct Context {
  ucontext_t uc;            ///< how a fresh context is entered the first time (and the sanitizer builds' switch)
  /**
   * Where a context that switched away resumes (no signal-mask syscall). On
   * x86-64 its stack pointer, with the callee-saved registers pushed below
   * it; elsewhere a jmp_buf. One member's room either way, so a Context (and
   * the kernel blocks that embed it in the tiles' RAM) has the same size on
   * every host build.
   */
  union {
    jmp_buf jb;
    void* sp;
  };
  bool has_jb;              ///< jb or sp is valid: the context has switched away at least once, or starts there
  void* stack_base;         ///< lowest address of the stack
  std::size_t stack_bytes;  ///< stack size
  void* asan_fake_stack;    ///< AddressSanitizer fiber bookkeeping (unused without ASan)
};

/**
 * Prepares @p ctx to start at entry(arg) on [stack, stack + stack_bytes).
 * The stack must be 16-byte aligned and at least kMinStackBytes. [task|host]
 */
void context_init(Context& ctx, std::byte* stack, std::size_t stack_bytes, ContextEntry entry, void* arg) noexcept;

/** Saves the running context into @p from and resumes @p to, on the same tile. [task|isr] */
void context_switch(Context& from, Context& to) noexcept;

inline constexpr std::size_t kMinStackBytes = std::size_t{16U} * 1024U;

// ------------------------------------------------------------------ time and work

/** The tile whose context is running. [task|isr] */
TileId current_tile() noexcept;

/** Local time of the current tile, in cycles since the board started. [task|isr] */
Cycles now() noexcept;

/** Charges @p cycles of work to the current context (see the execution model). [task] */
void consume(Cycles cycles) noexcept;

/** Charges counted work through the cost model of the chip profile. [task] */
void consume(const Work& work) noexcept;

/** Cycles the cost model gives for @p work on the current chip profile. [task|isr|host] */
Cycles cost_of(const Work& work) noexcept;

/**
 * Idles the tile until its next interrupt (WFI). Time jumps to the next event;
 * pending interrupts are taken before this returns. [task]
 */
void wait_for_interrupt() noexcept;

// ------------------------------------------------------------------ interrupts

enum class Irq : std::uint8_t {
  kTimer = 0,     ///< the tile's periodic timer (the kernel tick)
  kUdn = 1,       ///< a message arrived in one of the tile's UDN queues
  kDevice = 2,    ///< a device (IMU, camera) has data for this tile
  kWatchdog = 3,  ///< a watchdog this tile monitors expired
  kSoft = 4,      ///< raised by software (another tile, or this one)
  kCount = 5,
};

/**
 * Handler of all interrupts of a tile, called on the tile's current context with
 * the interrupt's cycle as the tile's time. Interrupts are masked while it runs.
 * It may call context_switch() to preempt the interrupted context.
 */
using IrqHandler = void (*)(TileId tile, Irq irq);

/** Installs the interrupt handler of @p tile (the kernel does this at boot). [task|host] */
void set_irq_handler(TileId tile, IrqHandler handler) noexcept;

/**
 * Raises @p irq on @p tile. From the tile itself it is pending at once; from
 * another tile or the board it becomes visible at the next quantum barrier. [task|isr|host]
 */
void raise_irq(TileId tile, Irq irq) noexcept;

/** Masks (true) or unmasks interrupts on the current tile; returns the previous mask. [task|isr] */
bool mask_irqs(bool masked) noexcept;

/** Starts the current tile's periodic timer: an Irq::kTimer every @p period cycles. [task] */
void timer_start(Cycles period) noexcept;

/**
 * Moves the running timer's next expiry to cycle @p at (at once if @p at is
 * not after the tile's time); it is periodic again from there. A tickless
 * kernel sets it to the next tick anything is due before its tile idles. No
 * effect while the timer is stopped. [task|isr]
 */
void timer_next(Cycles at) noexcept;

/**
 * The configured kernel tick period in cycles (1 ms at the profile's clock by
 * default); a kernel passes it to timer_start(). Period 0 to timer_start() stops the timer. [task|isr|host]
 */
Cycles tick_cycles() noexcept;

/** Number of tiles of the chip profile (cols * rows); tile ids are 0 .. tile_count() - 1. [task|isr|host] */
TileId tile_count() noexcept;

// ------------------------------------------------------------------ watchdog

/**
 * Arms the current tile's watchdog: it expires @p timeout cycles after the last
 * kick. On expiry the board logs it, raises Irq::kWatchdog on the monitor tile
 * (see board configuration), and resets the tile if @p reset_on_expiry. [task]
 */
void watchdog_arm(Cycles timeout, bool reset_on_expiry) noexcept;

/** Kicks the current tile's watchdog. [task|isr] */
void watchdog_kick() noexcept;

/**
 * Selects the current tile as the watchdog monitor: Irq::kWatchdog goes to it
 * from the next barrier on (the model of the watchdogs' expiry line wired to
 * two supervisor tiles through a select; the board configuration names the
 * first). A supervisor that takes over from a cut-off one calls it. [task]
 */
void watchdog_monitor_select() noexcept;

/** The tile Irq::kWatchdog goes to now (kNoTile: none). [task|isr|host] */
TileId watchdog_monitor() noexcept;

/** Takes (reads and clears) the set of tiles whose watchdog expired, as a bit mask. [task|isr] */
std::uint64_t watchdog_take_expired() noexcept;

/** The tile's reset-cause register: why it last booted. */
enum class BootCause : std::uint8_t {
  kPowerOn = 0,   ///< switched on
  kCommand = 1,   ///< reset on command (another tile's power control, or the host)
  kWatchdog = 2,  ///< its own watchdog expired with reset on expiry
  kOther = 3,     ///< not commanded: a crash or an external reset
};

/** Why the current tile last booted. [task|isr] */
BootCause boot_cause() noexcept;

/** The current tile's boot counter register: boots since the board started (1 at the first). [task|isr] */
std::uint32_t boot_count() noexcept;

// ------------------------------------------------------------------ boot and trace

/**
 * Boot entry of a tile: runs on the board's boot context of the tile when the
 * tile is powered on (after its boot delay) and after every reset. Typically
 * starts the kernel from a task table and never returns.
 */
using BootEntry = void (*)(TileId tile);

/**
 * Trace kinds are partitioned by layer so they never collide:
 * board 0x0000-0x0FFF, kernel 0x1000-0x1FFF, udn 0x2000-0x2FFF,
 * fdir 0x3000-0x3FFF, trn 0x4000-0x4FFF.
 */
inline constexpr std::uint16_t kTraceKernelBase = 0x1000U;
inline constexpr std::uint16_t kTraceUdnBase = 0x2000U;
inline constexpr std::uint16_t kTraceFdirBase = 0x3000U;
inline constexpr std::uint16_t kTraceTrnBase = 0x4000U;

/** Records a trace event of the current tile into the board trace and its hash. [task|isr] */
void trace(std::uint16_t kind, std::uint64_t a, std::uint64_t b) noexcept;

/**
 * Publication hook for silent-data-corruption faults: a task passes each value
 * it publishes through here; the fault injector may corrupt it (and logs it).
 * @return true if the value was corrupted. [task]
 */
bool publish_filter(std::uint32_t channel, void* data, std::size_t bytes) noexcept;

}  // namespace bsp
