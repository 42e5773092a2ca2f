/**
 * @file fault_injector_test.cpp
 * @brief The fault injector: planned and random faults, ground truth, SEU, SDC, hang, reset, watchdog failure.
 */
#include "bsp_tile64/faults/fault_injector.hpp"

#include "board_fixture.hpp"
#include "bsp_tile64/emu/board.hpp"
#include "bsp_tile64/api/memory.hpp"
#include "bsp_tile64/api/port.hpp"
#include "bsp_tile64/emu/trace.hpp"

#include <gtest/gtest.h>

#include <array>
#include <bit>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <span>
#include <vector>

namespace {

using board_test::idle_forever;
using board_test::small_config;
using bsp::Cycles;
using bsp::FaultKind;
using bsp::FaultSpec;
using bsp::FaultStatus;
using bsp::TileId;

constexpr std::size_t kDataBytes = 4096U;
std::array<std::byte*, bsp::kMaxTiles> g_data{};

void boot_data(TileId tile) {
  const bsp::Carve c = bsp::carve(bsp::Region{tile}, kDataBytes, 64U, "data");
  g_data[tile] = c.ptr;
  if (c.ptr != nullptr) {
    std::memset(c.ptr, 0x3C, kDataBytes);
  }
  idle_forever();
}

bsp::BoardConfig data_config(std::uint64_t powered) {
  bsp::BoardConfig c = small_config();
  c.powered_at_start = powered;
  for (auto& e : c.boot) {
    e = boot_data;
  }
  return c;
}

/** Bit positions (byte * 8 + bit) where two equal-sized buffers differ. */
std::vector<std::size_t> diff_bits(std::span<const std::byte> a, std::span<const std::byte> b) {
  std::vector<std::size_t> out;
  for (std::size_t i = 0; i < a.size(); ++i) {
    const auto x = static_cast<unsigned>(a[i] ^ b[i]);
    for (unsigned k = 0; k < 8U; ++k) {
      if (((x >> k) & 1U) != 0U) {
        out.push_back(i * 8U + k);
      }
    }
  }
  return out;
}

TEST(FaultInjector, RandomSeuFlipsExactlyOneBitAtTheLoggedAddress) {
  g_data.fill(nullptr);
  ASSERT_EQ(bsp::board_init(data_config(1U)), bsp::BoardError::kOk);
  bsp::run_for(1000U);
  ASSERT_NE(g_data[0], nullptr);
  std::array<std::byte, kDataBytes> before{};
  std::memcpy(before.data(), g_data[0], kDataBytes);
  FaultSpec s{};
  s.cycle = 5432U;
  s.kind = FaultKind::kSeu;
  s.tile = 0U;
  ASSERT_EQ(bsp::fault_plan_add(s), bsp::FaultError::kOk);
  bsp::run_for(9000U);
  ASSERT_EQ(bsp::fault_log().size(), 1U);
  const bsp::FaultRecord& r = bsp::fault_log()[0];
  EXPECT_EQ(r.status, FaultStatus::kApplied);
  EXPECT_EQ(r.applied_cycle, 5432U);
  EXPECT_FALSE(r.random);
  const auto diffs = diff_bits(before, {g_data[0], kDataBytes});
  ASSERT_EQ(diffs.size(), 1U) << "exactly one bit flips";
  const std::size_t data_offset = static_cast<std::size_t>(g_data[0] - bsp::region_span(bsp::Region{0}).data());
  EXPECT_EQ(diffs[0], (r.offset - data_offset) * 8U + r.bit);
  EXPECT_EQ(r.address, reinterpret_cast<std::uintptr_t>(g_data[0] + (r.offset - data_offset)));  // NOLINT(cppcoreguidelines-pro-type-reinterpret-cast): compare with the logged address
  const auto traced = board_test::events_of(bsp::BoardEvent::kFault, 0U);
  ASSERT_EQ(traced.size(), 1U);
  EXPECT_EQ(traced[0].time, 5432U);
}

void boot_data_and_stack(TileId tile) {
  // A stack carved under a task-like name (as the kernel carves every task's): random upsets skip it.
  const bsp::Carve st = bsp::carve_stack(bsp::Region{tile}, kDataBytes, 16U, "work");
  if (st.ptr != nullptr) {
    std::memset(st.ptr, 0x5A, kDataBytes);
  }
  boot_data(tile);
}

// The host runs on the contexts' stacks: a random upset never lands in one, whatever its name (the
// kernel carves each task's stack under the task's name; before, only names with "stack" were
// skipped).
TEST(FaultInjector, RandomSeusNeverLandInAStack) {
  g_data.fill(nullptr);
  bsp::BoardConfig c = data_config(1U);
  c.boot[0] = boot_data_and_stack;
  ASSERT_EQ(bsp::board_init(c), bsp::BoardError::kOk);
  bsp::run_for(1000U);
  ASSERT_NE(g_data[0], nullptr);
  const std::span<const bsp::CarveRecord> carves = bsp::region_carves(bsp::Region{0});
  std::size_t stack_start = 0U;
  std::size_t stack_bytes = 0U;
  for (const bsp::CarveRecord& r : carves) {
    if (std::strcmp(r.what, "work") == 0) {
      EXPECT_EQ(r.use, bsp::CarveUse::kStack);
      stack_start = r.offset;
      stack_bytes = r.bytes;
    } else if (std::strcmp(r.what, "data") == 0) {
      EXPECT_EQ(r.use, bsp::CarveUse::kData);
    }
  }
  ASSERT_EQ(stack_bytes, kDataBytes);
  for (std::uint32_t i = 0; i < 100U; ++i) {
    FaultSpec s{};
    s.cycle = 2000U + 10U * i;
    s.kind = FaultKind::kSeu;
    s.tile = 0U;
    ASSERT_EQ(bsp::fault_plan_add(s), bsp::FaultError::kOk);
  }
  bsp::run_for(5000U);
  ASSERT_EQ(bsp::fault_log().size(), 100U);
  for (const bsp::FaultRecord& r : bsp::fault_log()) {
    EXPECT_EQ(r.status, FaultStatus::kApplied);
    EXPECT_FALSE(r.offset >= stack_start && r.offset < stack_start + stack_bytes) << "offset " << r.offset;
  }
}

// A random upset's byte comes from the injector's stream, seeded by the board: the first upset of
// every run of a seed lands on the same byte. A plan (a campaign) says where with position: the byte
// at that fraction of the upset space (the carves that are not stacks, in RAM order), or of a carve.
TEST(FaultInjector, APositionPlacesTheUpsetInTheSpace) {
  const auto first_offset = [](double position, const char* carve) {
    g_data.fill(nullptr);
    bsp::BoardConfig c = data_config(1U);
    c.boot[0] = boot_data_and_stack;
    EXPECT_EQ(bsp::board_init(c), bsp::BoardError::kOk);
    bsp::run_for(1000U);
    FaultSpec s{};
    s.cycle = 2000U;
    s.kind = FaultKind::kSeu;
    s.tile = 0U;
    s.position = position;
    if (carve != nullptr) {
      std::snprintf(s.carve.data(), s.carve.size(), "%s", carve);
    }
    EXPECT_EQ(bsp::fault_plan_add(s), bsp::FaultError::kOk);
    bsp::run_for(5000U);
    EXPECT_EQ(bsp::fault_log().size(), 1U);
    return bsp::fault_log().empty() ? ~0ULL : bsp::fault_log()[0].offset;
  };
  std::size_t data_start = 0U;
  const auto drawn_a = first_offset(-1.0, nullptr);
  const auto drawn_b = first_offset(-1.0, nullptr);
  EXPECT_EQ(drawn_a, drawn_b) << "the stream draws the same first byte";
  for (const bsp::CarveRecord& r : bsp::region_carves(bsp::Region{0})) {
    data_start = std::strcmp(r.what, "data") == 0 ? r.offset : data_start;
  }
  // The space is the data carve alone (the stack is not in it): position p is byte p * kDataBytes.
  EXPECT_EQ(first_offset(0.0, nullptr), data_start);
  EXPECT_EQ(first_offset(0.5, nullptr), data_start + kDataBytes / 2U);
  EXPECT_EQ(first_offset(0.999999, nullptr), data_start + kDataBytes - 1U);
  // In a named carve: its start plus the fraction of its size.
  EXPECT_EQ(first_offset(0.25, "data"), data_start + kDataBytes / 4U);
  EXPECT_NE(first_offset(0.25, "data"), first_offset(0.75, "data"));
}

void boot_data_and_control(TileId tile) {
  const bsp::Carve ctl = bsp::carve_control(bsp::Region{tile}, 256U, 16U, "control");
  if (ctl.ptr != nullptr) {
    std::memset(ctl.ptr, 0x77, 256U);
  }
  boot_data(tile);
}

// The emulator follows the host addresses kept in control data (task control blocks, the
// endpoint): an upset aimed there flips nothing and crashes the tile instead, as a core_reset;
// the ground truth says so. A drawn SEU that lands there does the same (a random flip of a task
// control block's stack pointer crashed the whole emulator before).
TEST(FaultInjector, AnUpsetOfControlDataIsACrashOfTheTile) {
  g_data.fill(nullptr);
  bsp::BoardConfig c = data_config(1U);
  c.boot[0] = boot_data_and_control;
  ASSERT_EQ(bsp::board_init(c), bsp::BoardError::kOk);
  bsp::run_for(1000U);
  const std::uint64_t boots = bsp::tile_stats(0).boots;
  FaultSpec s{};
  s.cycle = 2000U;
  s.kind = FaultKind::kSeu;
  s.tile = 0U;
  s.offset = 17U;
  std::snprintf(s.carve.data(), s.carve.size(), "%s", "control");
  ASSERT_EQ(bsp::fault_plan_add(s), bsp::FaultError::kOk);
  bsp::run_for(100000U);
  ASSERT_EQ(bsp::fault_log().size(), 1U);
  const bsp::FaultRecord& r = bsp::fault_log()[0];
  EXPECT_EQ(r.status, FaultStatus::kApplied);
  EXPECT_TRUE(r.crashed);
  EXPECT_EQ(r.upset, bsp::UpsetModel::kControlCrash) << "no layout declared: the whole carve is host state";
  ASSERT_NE(r.carve, nullptr);
  EXPECT_STREQ(r.carve, "control");
  EXPECT_EQ(r.address, 0U) << "nothing was flipped";
  EXPECT_EQ(bsp::tile_stats(0).boots, boots + 1U) << "the tile crashed and booted again";
}

// A control struct of the kind the flight code carves: a host pointer, a counter, a flag, an index.
struct Ctl {
  const void* host;
  std::uint32_t seq;
  bool open;
  std::uint8_t index;
  std::array<std::uint16_t, 3> ring;
};
constexpr std::array kCtlFields{BSP_CONTROL_HOST(Ctl, host), BSP_CONTROL_STATE(Ctl, seq), BSP_CONTROL_STATE(Ctl, open),
                                BSP_CONTROL_STATE(Ctl, index), BSP_CONTROL_STATE(Ctl, ring)};
constexpr bsp::ControlLayout kCtlLayout{kCtlFields, sizeof(Ctl), alignof(Ctl)};
static_assert(bsp::control_layout_ok(kCtlLayout));
std::array<Ctl*, bsp::kMaxTiles> g_ctl{};

void boot_data_and_declared_control(TileId tile) {
  bsp::MemError err = bsp::MemError::kOk;
  Ctl* c = bsp::carve_control_array<Ctl>(bsp::Region{tile}, 2U, "ctl", &err, &kCtlLayout);
  g_ctl[tile] = c;
  if (c != nullptr) {
    for (std::size_t i = 0; i < 2U; ++i) {
      c[i] = Ctl{&g_ctl, 0x1234U, true, 7U, {1U, 2U, 3U}};
    }
  }
  boot_data(tile);
}

/** Flies one planned upset of bit @p bit of byte @p offset of carve "ctl" on tile 0; returns its record. */
bsp::FaultRecord upset_ctl(std::uint64_t offset, std::uint32_t bit, std::uint64_t& boots_after) {
  g_data.fill(nullptr);
  g_ctl.fill(nullptr);
  bsp::BoardConfig c = data_config(1U);
  c.boot[0] = boot_data_and_declared_control;
  EXPECT_EQ(bsp::board_init(c), bsp::BoardError::kOk);
  bsp::run_for(1000U);
  FaultSpec s{};
  s.cycle = 2000U;
  s.kind = FaultKind::kSeu;
  s.tile = 0U;
  s.offset = offset;
  s.bit = bit;
  std::snprintf(s.carve.data(), s.carve.size(), "%s", "ctl");
  EXPECT_EQ(bsp::fault_plan_add(s), bsp::FaultError::kOk);
  bsp::run_for(100000U);
  boots_after = bsp::tile_stats(0).boots;
  EXPECT_EQ(bsp::fault_log().size(), 1U);
  return bsp::fault_log().empty() ? bsp::FaultRecord{} : bsp::fault_log()[0];
}

// Issue 54 item 6: an upset of emulated state in control data (a sequence number, a flag, an index)
// is made for real and left to the software: the value changes, the tile is not reset.
TEST(FaultInjector, AnUpsetOfEmulatedStateInControlDataFlipsTheBit) {
  std::uint64_t boots = 0U;
  const bsp::FaultRecord r = upset_ctl(sizeof(Ctl) + offsetof(Ctl, seq), 4U, boots);
  EXPECT_EQ(r.status, FaultStatus::kApplied);
  EXPECT_FALSE(r.crashed);
  EXPECT_EQ(r.upset, bsp::UpsetModel::kFlipped);
  ASSERT_NE(g_ctl[0], nullptr);
  EXPECT_EQ(g_ctl[0][1].seq, 0x1234U ^ 0x10U) << "the second element's sequence number took the flip";
  EXPECT_EQ(g_ctl[0][0].seq, 0x1234U);
  EXPECT_EQ(boots, 1U) << "no reset";
  EXPECT_NE(r.address, 0U);
  // A bool's low bit is its value: true becomes false, nothing else moves.
  const bsp::FaultRecord b = upset_ctl(offsetof(Ctl, open), 0U, boots);
  EXPECT_EQ(b.upset, bsp::UpsetModel::kFlipped);
  EXPECT_FALSE(g_ctl[0][0].open);
  EXPECT_EQ(boots, 1U);
  const bsp::FaultRecord i = upset_ctl(offsetof(Ctl, ring) + 2U, 1U, boots);
  EXPECT_EQ(i.upset, bsp::UpsetModel::kFlipped);
  EXPECT_EQ(g_ctl[0][0].ring[1], 2U ^ 2U);
}

// A byte that stands for host state (a pointer) stays the crash model, and so do a bool's bits 1-7
// (a bool that is neither 0 nor 1 is undefined behaviour of the emulator, not a value of the tile's).
TEST(FaultInjector, AnUpsetOfHostStateInControlDataIsStillACrash) {
  std::uint64_t boots = 0U;
  for (std::uint64_t at : {offsetof(Ctl, host), offsetof(Ctl, host) + sizeof(void*) - 1U, sizeof(Ctl) + offsetof(Ctl, host)}) {
    const bsp::FaultRecord r = upset_ctl(at, 3U, boots);
    EXPECT_EQ(r.status, FaultStatus::kApplied) << at;
    EXPECT_TRUE(r.crashed) << at;
    EXPECT_EQ(r.upset, bsp::UpsetModel::kHostCrash) << at;
    EXPECT_EQ(r.address, 0U) << "nothing was flipped";
    EXPECT_EQ(boots, 2U) << "the tile crashed and booted again";
  }
  const bsp::FaultRecord b = upset_ctl(offsetof(Ctl, open), 1U, boots);
  EXPECT_EQ(b.upset, bsp::UpsetModel::kHostCrash);
  EXPECT_TRUE(b.crashed);
}

// The layout check refuses a member left out, two members out of order, a pointer declared as
// emulated state; the live bits follow a nested layout and count padding as emulated RAM.
TEST(ControlLayout, TheCheckRefusesAnIncompleteOrWrongDeclaration) {
  constexpr std::array missing{BSP_CONTROL_HOST(Ctl, host), BSP_CONTROL_STATE(Ctl, open), BSP_CONTROL_STATE(Ctl, index),
                               BSP_CONTROL_STATE(Ctl, ring)};
  static_assert(!bsp::control_layout_ok(bsp::ControlLayout{missing, sizeof(Ctl), alignof(Ctl)}));
  constexpr std::array swapped{BSP_CONTROL_HOST(Ctl, host), BSP_CONTROL_STATE(Ctl, open), BSP_CONTROL_STATE(Ctl, seq),
                               BSP_CONTROL_STATE(Ctl, index), BSP_CONTROL_STATE(Ctl, ring)};
  static_assert(!bsp::control_layout_ok(bsp::ControlLayout{swapped, sizeof(Ctl), alignof(Ctl)}));
  constexpr std::array pointer_as_state{BSP_CONTROL_STATE(Ctl, host), BSP_CONTROL_STATE(Ctl, seq),
                                        BSP_CONTROL_STATE(Ctl, open), BSP_CONTROL_STATE(Ctl, index),
                                        BSP_CONTROL_STATE(Ctl, ring)};
  static_assert(!bsp::control_layout_ok(bsp::ControlLayout{pointer_as_state, sizeof(Ctl), alignof(Ctl)}));
  struct Outer {
    std::uint64_t n;
    std::array<Ctl, 2> inner;
  };
  static constexpr std::array outer{BSP_CONTROL_STATE(Outer, n), BSP_CONTROL_NESTED(Outer, inner, kCtlLayout)};
  static constexpr bsp::ControlLayout outer_layout{outer, sizeof(Outer), alignof(Outer)};
  static_assert(bsp::control_layout_ok(outer_layout));
  const std::size_t second = offsetof(Outer, inner) + sizeof(Ctl);
  EXPECT_EQ(bsp::control_live_bits(&outer_layout, 0U), 0xFFU);
  EXPECT_EQ(bsp::control_live_bits(&outer_layout, second + offsetof(Ctl, host)), 0U);
  EXPECT_EQ(bsp::control_live_bits(&outer_layout, second + offsetof(Ctl, open)), 0x01U);
  EXPECT_EQ(bsp::control_live_bits(&outer_layout, second + offsetof(Ctl, seq) + 3U), 0xFFU);
  EXPECT_EQ(bsp::control_live_bits(&outer_layout, second + offsetof(Ctl, index) + 1U), 0xFFU) << "padding";
  EXPECT_EQ(bsp::control_live_bits(nullptr, 5U), 0U) << "no layout: the whole carve is host state";
  EXPECT_TRUE(bsp::control_bit_is_host(&outer_layout, second + offsetof(Ctl, open), 7U));
  EXPECT_FALSE(bsp::control_bit_is_host(&outer_layout, second + offsetof(Ctl, open), 0U));
}

// A layout that is not the carved type's is refused at the carve.
TEST(ControlLayout, ACarveWithAnotherTypesLayoutIsRefused) {
  bsp::MemError err = bsp::MemError::kOk;
  EXPECT_EQ(bsp::region_reset(bsp::Region{0}), bsp::MemError::kOk);
  EXPECT_EQ(bsp::carve_control_array<std::uint64_t>(bsp::Region{0}, 1U, "x", &err, &kCtlLayout), nullptr);
  EXPECT_EQ(err, bsp::MemError::kBadLayout);
  EXPECT_TRUE(bsp::region_carves(bsp::Region{0}).empty());
  EXPECT_NE(bsp::carve_control_array<Ctl>(bsp::Region{0}, 1U, "ctl", &err, &kCtlLayout), nullptr);
  EXPECT_EQ(err, bsp::MemError::kOk);
  ASSERT_EQ(bsp::region_carves(bsp::Region{0}).size(), 1U);
  EXPECT_EQ(bsp::region_carves(bsp::Region{0})[0].layout, &kCtlLayout);
  EXPECT_EQ(bsp::region_reset(bsp::Region{0}), bsp::MemError::kOk);
}

TEST(FaultInjector, PlannedSeuFlipsTheChosenBitForEveryBitPosition) {
  g_data.fill(nullptr);
  ASSERT_EQ(bsp::board_init(data_config(1U)), bsp::BoardError::kOk);
  bsp::run_for(1000U);
  ASSERT_NE(g_data[0], nullptr);
  const std::size_t base = static_cast<std::size_t>(g_data[0] - bsp::region_span(bsp::Region{0}).data());
  for (std::uint32_t bit = 0; bit < 8U; ++bit) {
    FaultSpec s{};
    s.cycle = 2000U + 100U * bit;
    s.kind = FaultKind::kSeu;
    s.offset = base + std::size_t{10U} * bit;
    s.bit = bit;
    ASSERT_EQ(bsp::fault_plan_add(s), bsp::FaultError::kOk);
  }
  bsp::run_for(3000U);
  ASSERT_EQ(bsp::fault_log().size(), 8U);
  for (std::uint32_t bit = 0; bit < 8U; ++bit) {
    EXPECT_EQ(static_cast<unsigned>(g_data[0][std::size_t{10U} * bit]), 0x3CU ^ (1U << bit)) << "bit " << bit;
    EXPECT_EQ(bsp::fault_log()[bit].bit, bit);
  }
}

TEST(FaultInjector, AnSeuAimedAtACarveLandsInIt) {
  g_data.fill(nullptr);
  ASSERT_EQ(bsp::board_init(data_config(1U)), bsp::BoardError::kOk);
  bsp::run_for(1000U);
  ASSERT_NE(g_data[0], nullptr);
  const std::size_t base = static_cast<std::size_t>(g_data[0] - bsp::region_span(bsp::Region{0}).data());
  constexpr std::uint32_t kDraws = 40U;
  for (std::uint32_t i = 0; i < kDraws; ++i) {
    FaultSpec s{};
    s.cycle = 2000U + 50U * i;
    s.kind = FaultKind::kSeu;
    std::snprintf(s.carve.data(), s.carve.size(), "data");  // random offset inside it
    ASSERT_EQ(bsp::fault_plan_add(s), bsp::FaultError::kOk);
  }
  FaultSpec fixed{};
  fixed.cycle = 5000U;
  fixed.kind = FaultKind::kSeu;
  fixed.offset = 100U;  // counted from the carve's start
  fixed.bit = 3U;
  std::snprintf(fixed.carve.data(), fixed.carve.size(), "data");
  ASSERT_EQ(bsp::fault_plan_add(fixed), bsp::FaultError::kOk);
  bsp::run_for(6000U);
  ASSERT_EQ(bsp::fault_log().size(), kDraws + 1U);
  for (const bsp::FaultRecord& r : bsp::fault_log()) {
    ASSERT_EQ(r.status, FaultStatus::kApplied);
    EXPECT_GE(r.offset, base);
    EXPECT_LT(r.offset, base + kDataBytes) << "inside the carve";
  }
  EXPECT_EQ(bsp::fault_log()[kDraws].offset, base + 100U);
  EXPECT_EQ(bsp::fault_log()[kDraws].bit, 3U);
}

TEST(FaultInjector, AnSeuAimedAtACarveTheTileLacksOrPastItsEndIsSkipped) {
  g_data.fill(nullptr);
  ASSERT_EQ(bsp::board_init(data_config(1U)), bsp::BoardError::kOk);
  bsp::run_for(1000U);
  std::array<std::byte, kDataBytes> before{};
  std::memcpy(before.data(), g_data[0], kDataBytes);
  FaultSpec none{};
  none.cycle = 2000U;
  none.kind = FaultKind::kSeu;
  std::snprintf(none.carve.data(), none.carve.size(), "no such carve");
  ASSERT_EQ(bsp::fault_plan_add(none), bsp::FaultError::kOk);
  FaultSpec past = none;
  past.cycle = 2100U;
  past.offset = kDataBytes;
  std::snprintf(past.carve.data(), past.carve.size(), "data");
  ASSERT_EQ(bsp::fault_plan_add(past), bsp::FaultError::kOk);
  bsp::run_for(3000U);
  ASSERT_EQ(bsp::fault_log().size(), 2U);
  EXPECT_EQ(bsp::fault_log()[0].status, FaultStatus::kSkipped);
  EXPECT_EQ(bsp::fault_log()[1].status, FaultStatus::kSkipped);
  EXPECT_TRUE(diff_bits(before, {g_data[0], kDataBytes}).empty()) << "nothing flipped";
}

TEST(FaultInjector, PlanIsAppliedInTimeOrderWhateverTheInsertionOrder) {
  ASSERT_EQ(bsp::board_init(data_config(0b111U)), bsp::BoardError::kOk);
  const std::array<Cycles, 3> at{7000U, 3000U, 5000U};
  for (TileId t = 0; t < 3U; ++t) {
    FaultSpec s{};
    s.cycle = at[t];
    s.kind = FaultKind::kWatchdogFail;
    s.tile = t;
    ASSERT_EQ(bsp::fault_plan_add(s), bsp::FaultError::kOk);
  }
  FaultSpec bad{};
  bad.tile = 64U;
  EXPECT_EQ(bsp::fault_plan_add(bad), bsp::FaultError::kBadTile);
  bsp::run_for(10'000U);
  const auto log = bsp::fault_log();
  ASSERT_EQ(log.size(), 3U);
  EXPECT_EQ(log[0].applied_cycle, 3000U);
  EXPECT_EQ(log[1].applied_cycle, 5000U);
  EXPECT_EQ(log[2].applied_cycle, 7000U);
}

std::array<std::uint32_t, bsp::kMaxTiles> g_kicks{};

void boot_kicker(TileId tile) {
  bsp::watchdog_arm(3000U, false);
  for (int i = 0; i < 1000; ++i) {
    bsp::consume(500U);
    bsp::watchdog_kick();
    ++g_kicks[tile];
  }
  idle_forever();
}

TEST(FaultInjector, PlannedHangStopsTheTileAtItsCycleAndTheWatchdogExpires) {
  g_kicks.fill(0U);
  bsp::BoardConfig c = small_config();
  c.powered_at_start = 0b10U;
  c.boot[1] = boot_kicker;
  ASSERT_EQ(bsp::board_init(c), bsp::BoardError::kOk);
  FaultSpec s{};
  s.cycle = 5250U;
  s.kind = FaultKind::kCoreHang;
  s.tile = 1U;
  ASSERT_EQ(bsp::fault_plan_add(s), bsp::FaultError::kOk);
  bsp::run_for(20'000U);
  EXPECT_EQ(g_kicks[1], 10U);  // kicks at 600 .. 5100; the hang at 5250 interrupts the next consume
  EXPECT_TRUE(bsp::tile_stopped(1));
  const auto hang = board_test::events_of(bsp::BoardEvent::kHang, 1U);
  ASSERT_EQ(hang.size(), 1U);
  EXPECT_EQ(hang[0].time, 5250U);
  const auto expired = board_test::events_of(bsp::BoardEvent::kWatchdogExpired, 1U);
  ASSERT_EQ(expired.size(), 1U);
  EXPECT_EQ(expired[0].time, 8100U);  // last kick 5100 + 3000
}

TEST(FaultInjector, WatchdogFailureMeansTheWatchdogNeverExpires) {
  g_kicks.fill(0U);
  bsp::BoardConfig c = small_config();
  c.powered_at_start = 0b11U;
  c.boot[0] = boot_kicker;
  c.boot[1] = boot_kicker;
  ASSERT_EQ(bsp::board_init(c), bsp::BoardError::kOk);
  for (TileId t = 0; t < 2U; ++t) {
    FaultSpec hang{};
    hang.cycle = 2000U;
    hang.kind = FaultKind::kCoreHang;
    hang.tile = t;
    ASSERT_EQ(bsp::fault_plan_add(hang), bsp::FaultError::kOk);
  }
  FaultSpec wd{};
  wd.cycle = 1000U;
  wd.kind = FaultKind::kWatchdogFail;
  wd.tile = 1U;
  ASSERT_EQ(bsp::fault_plan_add(wd), bsp::FaultError::kOk);
  bsp::run_for(20'000U);
  EXPECT_EQ(bsp::tile_stats(0).watchdog_expiries, 1U);
  EXPECT_EQ(bsp::tile_stats(1).watchdog_expiries, 0U) << "a failed watchdog expired";
}

void boot_counting(TileId tile) {
  ++g_kicks[tile];
  boot_data(tile);
}

TEST(FaultInjector, CrashResetEmptiesTheRegionAndBootsAgainAfterTheDelay) {
  g_kicks.fill(0U);
  bsp::BoardConfig c = small_config();
  c.powered_at_start = 0b100U;
  c.boot[2] = boot_counting;
  ASSERT_EQ(bsp::board_init(c), bsp::BoardError::kOk);
  FaultSpec s{};
  s.cycle = 3333U;
  s.kind = FaultKind::kCoreReset;
  s.tile = 2U;
  ASSERT_EQ(bsp::fault_plan_add(s), bsp::FaultError::kOk);
  bsp::run_for(3400U);
  EXPECT_EQ(bsp::power_state(2), bsp::PowerState::kBooting);
  EXPECT_EQ(bsp::region_used(bsp::Region{2}), 0U);
  bsp::run_for(1000U);
  EXPECT_EQ(g_kicks[2], 2U);
  EXPECT_EQ(bsp::tile_stats(2).resets, 1U);
  const auto resets = board_test::events_of(bsp::BoardEvent::kReset, 2U);
  ASSERT_EQ(resets.size(), 1U);
  EXPECT_EQ(resets[0].time, 3333U);
  EXPECT_EQ(resets[0].a, static_cast<std::uint64_t>(bsp::ResetReason::kFault));
}

std::vector<std::pair<Cycles, std::uint32_t>> g_published;

void boot_publisher(TileId /*tile*/) {
  for (std::uint32_t i = 0; i < 10U; ++i) {
    bsp::consume(1000U);
    std::uint32_t value = 0x1000U + i;
    static_cast<void>(bsp::publish_filter(i % 2U == 0U ? 7U : 8U, &value, sizeof value));
    g_published.emplace_back(bsp::now(), value);
  }
  idle_forever();
}

TEST(FaultInjector, SdcCorruptsTheNextPublicationOnItsChannelAndLogsTheBit) {
  g_published.clear();
  bsp::BoardConfig c = small_config();
  c.powered_at_start = 1U;
  c.boot[0] = boot_publisher;
  ASSERT_EQ(bsp::board_init(c), bsp::BoardError::kOk);
  FaultSpec s{};
  s.cycle = 2500U;
  s.kind = FaultKind::kSdc;
  s.channel = 8U;
  s.bit = 3U;
  ASSERT_EQ(bsp::fault_plan_add(s), bsp::FaultError::kOk);
  bsp::run_for(12'000U);
  ASSERT_EQ(g_published.size(), 10U);
  // Publications at 1100, 2100, ...: channel 8 is used by odd i; the first after 2500 is i = 3 at 4100.
  for (std::uint32_t i = 0; i < 10U; ++i) {
    const std::uint32_t expect = (i == 3U) ? ((0x1000U + i) ^ (1U << 3U)) : 0x1000U + i;
    EXPECT_EQ(g_published[i].second, expect) << "publication " << i;
  }
  ASSERT_EQ(bsp::fault_log().size(), 1U);
  const bsp::FaultRecord& r = bsp::fault_log()[0];
  EXPECT_EQ(r.status, FaultStatus::kApplied);
  EXPECT_EQ(r.applied_cycle, 4100U);
  EXPECT_EQ(r.bit, 3U);
  EXPECT_EQ(r.offset, 0U);
}

std::vector<std::pair<double, double>> g_positions;

void boot_position_publisher(TileId /*tile*/) {
  for (std::uint32_t i = 0; i < 6U; ++i) {
    bsp::consume(1000U);
    std::array<double, 2> uv{100.0 + i, 50.0};
    static_cast<void>(bsp::publish_filter(6U, uv.data(), sizeof uv));
    g_positions.emplace_back(uv[0], uv[1]);
  }
  idle_forever();
}

// A lasting sdc (a shift): every value published on the channel from its time on has the shift added to
// its first double; it stays armed, counts its hits, and the first one is its applied time.
TEST(FaultInjector, AShiftChangesEveryLaterPublicationAndStaysArmed) {
  g_positions.clear();
  bsp::BoardConfig c = small_config();
  c.powered_at_start = 1U;
  c.boot[0] = boot_position_publisher;
  ASSERT_EQ(bsp::board_init(c), bsp::BoardError::kOk);
  FaultSpec s{};
  s.cycle = 2500U;
  s.kind = FaultKind::kSdc;
  s.channel = 6U;
  s.shift = 2.0;
  ASSERT_EQ(bsp::fault_plan_add(s), bsp::FaultError::kOk);
  bsp::run_for(12'000U);
  ASSERT_EQ(g_positions.size(), 6U);
  for (std::uint32_t i = 0; i < 6U; ++i) {
    EXPECT_EQ(g_positions[i].first, 100.0 + i + (i >= 2U ? 2.0 : 0.0)) << "publication " << i;
    EXPECT_EQ(g_positions[i].second, 50.0) << "only the first double moves";
  }
  ASSERT_EQ(bsp::fault_log().size(), 1U);
  const bsp::FaultRecord& r = bsp::fault_log()[0];
  EXPECT_EQ(r.status, FaultStatus::kApplied);
  EXPECT_EQ(r.applied_cycle, 3100U);
  EXPECT_EQ(r.hits, 4U);
}

bsp::FaultStatus fake_link_fail(bsp::FaultRecord& r, bsp::Rng& /*rng*/) {
  r.offset = r.spec.param;
  return FaultStatus::kApplied;
}

TEST(FaultInjector, NetworkKindsAreUnsupportedUntilTheNetworkModelRegistersAHandler) {
  ASSERT_EQ(bsp::board_init(data_config(0U)), bsp::BoardError::kOk);
  FaultSpec s{};
  s.cycle = 100U;
  s.kind = FaultKind::kLinkFail;
  s.tile = 9U;
  s.param = 3U;
  ASSERT_EQ(bsp::fault_plan_add(s), bsp::FaultError::kOk);
  s.cycle = 2100U;
  ASSERT_EQ(bsp::fault_plan_add(s), bsp::FaultError::kOk);
  bsp::run_for(1000U);
  ASSERT_EQ(bsp::fault_register_handler(FaultKind::kLinkFail, fake_link_fail), bsp::FaultError::kOk);
  bsp::run_for(2000U);
  ASSERT_EQ(bsp::fault_log().size(), 2U);
  EXPECT_EQ(bsp::fault_log()[0].status, FaultStatus::kUnsupported);
  EXPECT_EQ(bsp::fault_log()[1].status, FaultStatus::kApplied);
  EXPECT_EQ(bsp::fault_log()[1].offset, 3U);
  EXPECT_EQ(bsp::fault_log()[1].applied_cycle, 2100U);
}

std::vector<bsp::FaultRecord> random_campaign(std::uint64_t seed) {
  bsp::BoardConfig c = data_config(~0ULL);
  c.seed = seed;
  EXPECT_EQ(bsp::board_init(c), bsp::BoardError::kOk);
  EXPECT_EQ(bsp::fault_set_rate(FaultKind::kSeu, 1000.0), bsp::FaultError::kOk);
  EXPECT_EQ(bsp::fault_set_rate(FaultKind::kCoreHang, 500.0), bsp::FaultError::kOk);
  EXPECT_EQ(bsp::fault_set_rate(FaultKind::kSdc, -1.0), bsp::FaultError::kBadRate);
  bsp::run_for(7'000'000U);  // 10 ms: 64 tiles x 1500/s x 0.01 s = 960 faults expected
  const auto log = bsp::fault_log();
  return {log.begin(), log.end()};
}

bool same(const bsp::FaultRecord& a, const bsp::FaultRecord& b) {
  return a.spec.kind == b.spec.kind && a.spec.tile == b.spec.tile && a.applied_cycle == b.applied_cycle &&
         a.offset == b.offset && a.bit == b.bit && a.status == b.status;
}

TEST(FaultInjector, RandomFaultsFollowTheRatesAndRepeatExactlyForASeed) {
  const auto a = random_campaign(11U);
  const auto b = random_campaign(11U);
  const auto other = random_campaign(12U);
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t i = 0; i < a.size(); ++i) {
    EXPECT_TRUE(same(a[i], b[i])) << "record " << i;
  }
  // Poisson(960): 6 sigma is about 190.
  EXPECT_GT(a.size(), 770U);
  EXPECT_LT(a.size(), 1150U);
  std::size_t seu = 0U;
  for (const auto& r : a) {
    EXPECT_TRUE(r.random);
    seu += (r.spec.kind == FaultKind::kSeu) ? 1U : 0U;
  }
  EXPECT_GT(seu, a.size() / 2U);  // SEU is 2/3 of the rate
  bool differs = other.size() != a.size();
  for (std::size_t i = 0; !differs && i < a.size(); ++i) {
    differs = !same(a[i], other[i]);
  }
  EXPECT_TRUE(differs) << "another seed gave the same faults";
}

}  // namespace
