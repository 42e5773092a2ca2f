/**
 * @file board_bench.cpp
 * @brief Host cost of the emulated board: 64 idle tiles, 64 busy tiles, one context switch.
 *
 * The figures that matter are host seconds per emulated second (counter
 * "host_s_per_emu_s") and nanoseconds per context switch. swapcontext saves and
 * restores the signal mask with a syscall; BM_SignalMaskSyscall shows that part.
 */
#include "bsp_tile64/emu/board.hpp"
#include "bsp_tile64/api/port.hpp"

#include <benchmark/benchmark.h>

#include <array>
#include <csignal>
#include <cstddef>
#include <cstdint>

namespace {

void empty_handler(bsp::TileId /*tile*/, bsp::Irq /*irq*/) {}

[[noreturn]] void boot_idle(bsp::TileId tile) {
  bsp::set_irq_handler(tile, empty_handler);
  bsp::timer_start(bsp::tick_cycles());
  for (;;) {
    bsp::wait_for_interrupt();
  }
}

[[noreturn]] void boot_busy(bsp::TileId tile) {
  bsp::set_irq_handler(tile, empty_handler);
  bsp::timer_start(bsp::tick_cycles());
  bsp::watchdog_arm(bsp::tick_cycles() * 10U, false);
  bsp::Work w{};
  w.int_ops = 2000U;
  w.int_macs = 500U;
  w.flops = 20U;
  w.mem_words = 300U;
  for (;;) {
    bsp::consume(w);  // about 3 microseconds of TILE64 work per call
    bsp::watchdog_kick();
  }
}

void run_board(benchmark::State& state, bsp::BootEntry entry) {
  bsp::BoardConfig c = bsp::default_config(bsp::kTile64);  // 1 ms tick and quantum
  for (auto& e : c.boot) {
    e = entry;
  }
  if (bsp::board_init(c) != bsp::BoardError::kOk) {
    state.SkipWithError("board_init failed");
    return;
  }
  const bsp::Cycles slice = bsp::kTile64.clock_hz / 10U;  // 100 ms of emulated time per iteration
  for (auto _ : state) {
    benchmark::DoNotOptimize(bsp::run_for(slice));
  }
  // 0.1 emulated second per iteration, inverted: host seconds per emulated second.
  state.counters["host_s_per_emu_s"] =
      benchmark::Counter(0.1, benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
}

void BM_Idle64Tiles(benchmark::State& state) { run_board(state, boot_idle); }
BENCHMARK(BM_Idle64Tiles)->Unit(benchmark::kMillisecond)->MinTime(2.0);

void BM_Busy64Tiles(benchmark::State& state) { run_board(state, boot_busy); }
BENCHMARK(BM_Busy64Tiles)->Unit(benchmark::kMillisecond)->MinTime(2.0);

bsp::Context g_host{};
bsp::Context g_fiber{};
alignas(16) std::array<std::byte, std::size_t{64U} * 1024U> g_stack{};

[[noreturn]] void ping(void* /*arg*/) {
  for (;;) {
    bsp::context_switch(g_fiber, g_host);
  }
}

/** One iteration is two switches (there and back); the counter reports one. */
void BM_ContextSwitch(benchmark::State& state) {
  bsp::context_init(g_fiber, g_stack.data(), g_stack.size(), ping, nullptr);
  for (auto _ : state) {
    bsp::context_switch(g_host, g_fiber);
  }
  state.counters["ns_per_switch"] =
      benchmark::Counter(2.0 * 1e-9, benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
}
BENCHMARK(BM_ContextSwitch);

/** The syscall swapcontext makes on every switch to save and restore the signal mask. */
void BM_SignalMaskSyscall(benchmark::State& state) {
  sigset_t old{};
  for (auto _ : state) {
    benchmark::DoNotOptimize(sigprocmask(SIG_SETMASK, nullptr, &old));
  }
}
BENCHMARK(BM_SignalMaskSyscall);

}  // namespace

BENCHMARK_MAIN();
