/**
 * @file fault_injector.cpp
 * @brief Fault plan, random fault draws, built-in board fault handlers, the SDC publication hook.
 */
#include "bsp_tile64/faults/fault_injector.hpp"

#include "bsp_tile64/emu/board.hpp"
#include "bsp_tile64/emu/board_state.hpp"
#include "bsp_tile64/api/memory.hpp"
#include "bsp_tile64/emu/trace.hpp"

#include <array>
#include <cmath>
#include <cstring>

namespace bsp {
namespace {

constexpr std::size_t kKinds = static_cast<std::size_t>(FaultKind::kCount);
/** Random faults scheduled per barrier at most (a guard: rates are per second, quanta are short). */
constexpr std::uint32_t kMaxRandomPerBarrier = 64U;
constexpr Cycles kNever = ~Cycles{0};

struct Injector {
  Rng rng{1U, StreamId::kFaults};
  std::array<FaultSpec, kFaultPlanCapacity> plan{};
  std::size_t plan_count = 0U;
  std::size_t plan_next = 0U;
  std::array<double, kKinds> rate{};
  Cycles next_random = kNever;
  std::array<FaultRecord, kFaultLogCapacity> log{};
  std::size_t log_count = 0U;
  std::uint64_t dropped = 0U;
  std::array<FaultHandler, kKinds> handler{};
  std::array<std::size_t, kMaxArmedSdc> armed{};
  std::size_t armed_count = 0U;
};

Injector g_inj{};

void trace_fault(const FaultRecord& r, std::size_t index) noexcept {
  const std::uint64_t a = (static_cast<std::uint64_t>(index) << 16U) |
                          (static_cast<std::uint64_t>(r.status) << 8U) | static_cast<std::uint64_t>(r.spec.kind);
  const std::uint64_t b = (r.offset << 8U) ^ r.bit;
  trace_record(r.applied_cycle, r.spec.tile, static_cast<std::uint16_t>(BoardEvent::kFault), a, b);
}

FaultStatus apply_hang(FaultRecord& r, Rng& /*rng*/) noexcept {
  return hang_tile(r.spec.tile) == BoardError::kOk ? FaultStatus::kApplied : FaultStatus::kSkipped;
}

FaultStatus apply_reset(FaultRecord& r, Rng& /*rng*/) noexcept {
  return reset_tile_for(r.spec.tile, ResetReason::kFault) == BoardError::kOk ? FaultStatus::kApplied
                                                                              : FaultStatus::kSkipped;
}

FaultStatus apply_watchdog_fail(FaultRecord& r, Rng& /*rng*/) noexcept {
  return set_watchdog_failed(r.spec.tile, true) == BoardError::kOk ? FaultStatus::kApplied : FaultStatus::kSkipped;
}

/**
 * Random SEUs avoid the contexts' stacks (every task's, and the board's boot
 * stack): the host runs on them, and a flipped host return address would crash
 * the emulator, not the tile. Before, only carves named "stack" were avoided,
 * and every task stack (carved under its task's name) was drawn.
 */
bool seu_target(const CarveRecord& c) noexcept { return c.use != CarveUse::kStack; }

/** The carve of @p tile that holds byte @p offset; nullptr for uncarved RAM. */
const CarveRecord* carve_at(TileId tile, std::uint64_t offset) noexcept {
  for (const CarveRecord& c : region_carves(Region{tile})) {
    if (offset >= c.offset && offset - c.offset < c.bytes) {
      return &c;
    }
  }
  return nullptr;
}

/** Index of the byte at fraction @p position of @p bytes (position in [0, 1)). */
std::uint64_t at_fraction(double position, std::uint64_t bytes) noexcept {
  const auto i = static_cast<std::uint64_t>(position * static_cast<double>(bytes));
  return i < bytes ? i : bytes - 1U;
}

/**
 * A byte offset among the carves that are SEU targets: at @p position of them (in RAM order) when it
 * is in [0, 1), else drawn uniformly; false if there are none.
 */
bool draw_seu_offset(TileId tile, double position, Rng& rng, std::uint64_t& offset) noexcept {
  const std::span<const CarveRecord> carves = region_carves(Region{tile});
  std::uint64_t total = 0U;
  for (const CarveRecord& c : carves) {
    total += seu_target(c) ? c.bytes : 0U;
  }
  if (total == 0U) {
    return false;
  }
  std::uint64_t pick = position >= 0.0 ? at_fraction(position, total) : rng.below(total);
  for (const CarveRecord& c : carves) {
    if (!seu_target(c)) {
      continue;
    }
    if (pick < c.bytes) {
      offset = c.offset + pick;
      return true;
    }
    pick -= c.bytes;
  }
  return false;
}

/**
 * The carve of @p tile named @p name: its start and size; false if the tile has none by that name.
 * A task's stack is carved under the task's name, and a task may name its state carve the same
 * (`tile_health`, `net_health`, `vision_coord`): the state is meant, the stack only when it is
 * the one carve of that name.
 */
bool find_carve(TileId tile, const std::array<char, kCarveNameMax>& name, std::size_t& start, std::size_t& bytes) noexcept {
  const CarveRecord* found = nullptr;
  for (const CarveRecord& c : region_carves(Region{tile})) {
    if (c.what != nullptr && std::strncmp(c.what, name.data(), kCarveNameMax) == 0 &&
        (found == nullptr || found->use == CarveUse::kStack)) {
      found = &c;
    }
  }
  if (found == nullptr) {
    return false;
  }
  start = found->offset;
  bytes = found->bytes;
  return true;
}

/** How an upset of bit @p bit of byte @p at of carve @p hit (nullptr: uncarved RAM) is modelled. */
UpsetModel upset_model(const CarveRecord* hit, std::uint64_t at, std::uint32_t bit) noexcept {
  if (hit == nullptr || hit->use == CarveUse::kData) {
    return UpsetModel::kFlipped;
  }
  if (hit->use == CarveUse::kStack) {
    return UpsetModel::kStackCrash;
  }
  if (hit->layout == nullptr) {
    return UpsetModel::kControlCrash;
  }
  return control_bit_is_host(hit->layout, static_cast<std::size_t>(at), bit) ? UpsetModel::kHostCrash
                                                                             : UpsetModel::kFlipped;
}

FaultStatus apply_seu(FaultRecord& r, Rng& rng) noexcept {
  const std::span<std::byte> ram = region_span(Region{r.spec.tile});
  std::uint64_t offset = r.spec.offset;
  if (r.spec.carve[0] != '\0') {
    std::size_t start = 0U;
    std::size_t bytes = 0U;
    if (!find_carve(r.spec.tile, r.spec.carve, start, bytes) || bytes == 0U ||
        (offset != kRandomOffset && offset >= bytes)) {
      return FaultStatus::kSkipped;
    }
    offset = start + (offset != kRandomOffset ? offset
                      : r.spec.position >= 0.0 ? at_fraction(r.spec.position, bytes)
                                               : rng.below(bytes));
  } else if (offset == kRandomOffset) {
    if (!draw_seu_offset(r.spec.tile, r.spec.position, rng, offset)) {
      return FaultStatus::kSkipped;
    }
  } else if (offset >= ram.size()) {
    return FaultStatus::kSkipped;
  }
  const std::uint32_t bit = r.spec.bit == kRandomBit ? static_cast<std::uint32_t>(rng.below(8U)) : r.spec.bit % 8U;
  const CarveRecord* hit = carve_at(r.spec.tile, offset);
  r.carve = hit != nullptr ? hit->what : nullptr;
  r.carve_offset = hit != nullptr ? offset - hit->offset : 0U;
  r.upset = upset_model(hit, r.carve_offset, bit);
  if (r.upset != UpsetModel::kFlipped) {
    // Host addresses live there: flipping one would crash the emulator. The tile crashes instead.
    r.offset = offset;
    r.bit = bit;
    r.crashed = true;
    return reset_tile_for(r.spec.tile, ResetReason::kFault) == BoardError::kOk ? FaultStatus::kApplied
                                                                                : FaultStatus::kSkipped;
  }
  // Data, or emulated state in control data (a counter, an index, a flag): flipped for real, the
  // flight code finds it or lives with it.
  std::byte& target = ram[static_cast<std::size_t>(offset)];
  target ^= static_cast<std::byte>(1U << bit);
  r.offset = offset;
  r.bit = bit;
  r.address = reinterpret_cast<std::uintptr_t>(&target);  // NOLINT(cppcoreguidelines-pro-type-reinterpret-cast): ground truth is an address
  return FaultStatus::kApplied;
}

/** A lasting SDC: @p shift added to the first double of the value (none when it is shorter). */
void shift_value(FaultRecord& r, std::size_t index, void* data, std::size_t bytes) noexcept {
  if (bytes < sizeof(double)) {
    return;
  }
  double v = 0.0;
  std::memcpy(&v, data, sizeof v);
  v += r.spec.shift;
  std::memcpy(data, &v, sizeof v);
  if (r.hits == 0U) {
    r.status = FaultStatus::kApplied;
    r.applied_cycle = now();
    r.offset = 0U;
    r.bit = 0U;
    r.address = reinterpret_cast<std::uintptr_t>(data);  // NOLINT(cppcoreguidelines-pro-type-reinterpret-cast): ground truth is an address
  }
  ++r.hits;
  trace_record(now(), r.spec.tile, static_cast<std::uint16_t>(BoardEvent::kSdcApplied), index, 0U);
}

FaultStatus apply_sdc(FaultRecord& r, Rng& /*rng*/) noexcept {
  if (g_inj.armed_count >= kMaxArmedSdc) {
    return FaultStatus::kSkipped;
  }
  g_inj.armed[g_inj.armed_count++] = static_cast<std::size_t>(&r - g_inj.log.data());
  return FaultStatus::kArmed;
}

/** Delivery of a fault event on its target tile, at its exact cycle. */
void on_fault_event(TileId /*tile*/, Cycles cycle, std::uint64_t arg) noexcept {
  const auto index = static_cast<std::size_t>(arg);
  FaultRecord& r = g_inj.log[index];
  r.applied_cycle = cycle;
  const FaultHandler h = g_inj.handler[static_cast<std::size_t>(r.spec.kind)];
  r.status = (h == nullptr) ? FaultStatus::kUnsupported : h(r, g_inj.rng);
  trace_fault(r, index);
}

void schedule_fault(const FaultSpec& spec, bool random, Cycles q_start) noexcept {
  if (g_inj.log_count >= kFaultLogCapacity) {
    ++g_inj.dropped;
    return;
  }
  const std::size_t index = g_inj.log_count++;
  FaultRecord& r = g_inj.log[index];
  r = FaultRecord{spec, random, FaultStatus::kScheduled, 0U, 0U, 0U, 0U};
  const Cycles at = spec.cycle < q_start ? q_start : spec.cycle;
  if (schedule_event(at, spec.tile, Irq::kCount, on_fault_event, index) != BoardError::kOk) {
    r.status = FaultStatus::kSkipped;
    r.applied_cycle = q_start;
    trace_fault(r, index);
  }
}

double total_rate() noexcept {
  double sum = 0.0;
  for (const double r : g_inj.rate) {
    sum += r;
  }
  return sum;
}

/** Exponential inter-arrival time of the whole board's random faults, in cycles (at least 1). */
Cycles draw_interval() noexcept {
  const double per_second = total_rate() * static_cast<double>(tile_count());
  if (per_second <= 0.0) {
    return kNever;
  }
  const double seconds = -std::log(1.0 - g_inj.rng.uniform()) / per_second;
  const double cycles = std::ceil(seconds * static_cast<double>(detail::board().config.profile.clock_hz));
  return cycles < 1.0 ? 1U : (cycles >= 1.8e19 ? kNever : static_cast<Cycles>(cycles));
}

FaultSpec draw_fault(Cycles cycle) noexcept {
  FaultSpec s{};
  s.cycle = cycle;
  double pick = g_inj.rng.uniform() * total_rate();
  s.kind = FaultKind::kCoreHang;
  for (std::size_t k = 0; k < kKinds; ++k) {
    if (g_inj.rate[k] > 0.0) {
      s.kind = static_cast<FaultKind>(k);  // last kind with a rate catches rounding at the top
      if (pick < g_inj.rate[k]) {
        break;
      }
      pick -= g_inj.rate[k];
    }
  }
  s.tile = static_cast<TileId>(g_inj.rng.below(tile_count()));
  return s;
}

}  // namespace

namespace detail {

void injector_reset(std::uint64_t seed) noexcept {
  g_inj.rng = Rng(seed, StreamId::kFaults);
  g_inj.plan_count = 0U;
  g_inj.plan_next = 0U;
  g_inj.rate.fill(0.0);
  g_inj.next_random = kNever;
  g_inj.log_count = 0U;
  g_inj.dropped = 0U;
  g_inj.armed_count = 0U;
  g_inj.handler.fill(nullptr);
  g_inj.handler[static_cast<std::size_t>(FaultKind::kCoreHang)] = apply_hang;
  g_inj.handler[static_cast<std::size_t>(FaultKind::kCoreReset)] = apply_reset;
  g_inj.handler[static_cast<std::size_t>(FaultKind::kSdc)] = apply_sdc;
  g_inj.handler[static_cast<std::size_t>(FaultKind::kSeu)] = apply_seu;
  g_inj.handler[static_cast<std::size_t>(FaultKind::kWatchdogFail)] = apply_watchdog_fail;
}

void injector_barrier(Cycles q_start, Cycles q_end) noexcept {
  for (std::size_t n = 0; n < kFaultPlanCapacity; ++n) {
    if (g_inj.plan_next >= g_inj.plan_count || g_inj.plan[g_inj.plan_next].cycle >= q_end) {
      break;
    }
    schedule_fault(g_inj.plan[g_inj.plan_next], false, q_start);
    ++g_inj.plan_next;
  }
  for (std::uint32_t n = 0; n < kMaxRandomPerBarrier; ++n) {
    if (g_inj.next_random >= q_end) {
      break;
    }
    schedule_fault(draw_fault(g_inj.next_random), true, q_start);
    const Cycles dt = draw_interval();
    g_inj.next_random = (dt > kNever - g_inj.next_random) ? kNever : g_inj.next_random + dt;
  }
}

}  // namespace detail

FaultError fault_plan_add(const FaultSpec& spec) noexcept {
  if (spec.tile >= tile_count()) {
    return FaultError::kBadTile;
  }
  if (spec.kind >= FaultKind::kCount) {
    return FaultError::kBadKind;
  }
  if (g_inj.plan_count >= kFaultPlanCapacity) {
    return FaultError::kFull;
  }
  std::size_t i = g_inj.plan_count;
  while (i > g_inj.plan_next && spec.cycle < g_inj.plan[i - 1U].cycle) {
    g_inj.plan[i] = g_inj.plan[i - 1U];
    --i;
  }
  g_inj.plan[i] = spec;
  ++g_inj.plan_count;
  return FaultError::kOk;
}

FaultError fault_set_rate(FaultKind kind, double per_tile_per_second) noexcept {
  if (kind >= FaultKind::kCount) {
    return FaultError::kBadKind;
  }
  if (!(per_tile_per_second >= 0.0) || std::isinf(per_tile_per_second)) {
    return FaultError::kBadRate;
  }
  g_inj.rate[static_cast<std::size_t>(kind)] = per_tile_per_second;
  const Cycles dt = draw_interval();
  const Cycles now = board_time();
  g_inj.next_random = (dt > kNever - now) ? kNever : now + dt;
  return FaultError::kOk;
}

FaultError fault_register_handler(FaultKind kind, FaultHandler handler) noexcept {
  if (kind >= FaultKind::kCount) {
    return FaultError::kBadKind;
  }
  g_inj.handler[static_cast<std::size_t>(kind)] = handler;
  return FaultError::kOk;
}

std::span<const FaultRecord> fault_log() noexcept { return {g_inj.log.data(), g_inj.log_count}; }

std::uint64_t fault_log_dropped() noexcept { return g_inj.dropped; }

bool publish_filter(std::uint32_t channel, void* data, std::size_t bytes) noexcept {
  const TileId tile = current_tile();
  if (tile == kNoTile || data == nullptr || bytes == 0U) {
    return false;
  }
  for (std::size_t i = 0; i < g_inj.armed_count; ++i) {
    FaultRecord& r = g_inj.log[g_inj.armed[i]];
    if (r.spec.tile != tile || (r.spec.channel != kAnyChannel && r.spec.channel != channel)) {
      continue;
    }
    if (r.spec.shift != 0.0) {
      shift_value(r, g_inj.armed[i], data, bytes);
      return true;  // lasting: it stays armed
    }
    const std::uint64_t bits = static_cast<std::uint64_t>(bytes) * 8U;
    const std::uint64_t bit = r.spec.bit == kRandomBit ? g_inj.rng.below(bits) : r.spec.bit % bits;
    std::byte* p = static_cast<std::byte*>(data) + bit / 8U;
    *p ^= static_cast<std::byte>(1U << (bit % 8U));
    r.status = FaultStatus::kApplied;
    r.applied_cycle = now();
    r.offset = bit / 8U;
    r.bit = static_cast<std::uint32_t>(bit);
    r.address = reinterpret_cast<std::uintptr_t>(p);  // NOLINT(cppcoreguidelines-pro-type-reinterpret-cast): ground truth is an address
    const std::size_t index = g_inj.armed[i];
    for (std::size_t j = i + 1U; j < g_inj.armed_count; ++j) {
      g_inj.armed[j - 1U] = g_inj.armed[j];
    }
    --g_inj.armed_count;
    trace_record(r.applied_cycle, tile, static_cast<std::uint16_t>(BoardEvent::kSdcApplied), index, bit);
    return true;
  }
  return false;
}

}  // namespace bsp
