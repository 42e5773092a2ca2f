/**
 * @file ram_record_test.cpp
 * @brief The host's read of a declared record (tools/common/mission/ram_record.hpp): what a task wrote
 *        in its tile's RAM, byte for byte; an unknown record, a wrong type or tile refused by name.
 */
#include "tools/common/mission/ram_record.hpp"

#include "bsp_tile64/emu/board.hpp"
#include "bsp_tile64/api/memory.hpp"
#include "kernel/kernel.hpp"

#include <gtest/gtest.h>

#include <array>
#include <cstddef>
#include <cstdint>
#include <string>

namespace {

struct Counts {
  std::uint32_t passes;
  std::uint32_t last_tick;
  double half_passes;
};
constexpr std::array kCountsFields{
    BSP_CONTROL_STATE(Counts, passes),
    BSP_CONTROL_STATE(Counts, last_tick),
    BSP_CONTROL_STATE(Counts, half_passes),
};
constexpr bsp::ControlLayout kCountsLayout{kCountsFields, sizeof(Counts), alignof(Counts)};
static_assert(bsp::control_layout_ok(kCountsLayout), "every member of Counts");
/** Named as the task is: its stack carve has the same name, and is not the record. */
constexpr bsp::RamRecord<Counts> kCountsRecord{"counter", &kCountsLayout};

constexpr bsp::TileId kTile = 0U;
constexpr bsp::Cycles kTick = bsp::kTile64.cycles_per_ms();

/** What the task last wrote, kept on the host side to compare the read with. */
Counts g_written{};
bool g_carved = false;

void counter_main(void* /*arg*/) {
  bsp::MemError err = bsp::MemError::kOk;
  Counts* c = bsp::carve_record(bsp::Region{bsp::current_tile()}, kCountsRecord, &err);
  g_carved = c != nullptr;
  if (c == nullptr) {
    return;
  }
  for (;;) {
    ++c->passes;
    c->last_tick = static_cast<std::uint32_t>(k::now_ticks());
    c->half_passes = 0.5 * static_cast<double>(c->passes);
    g_written = *c;
    (void)k::wait_period();
  }
}

class RamRecord : public ::testing::Test {
 protected:
  void SetUp() override {
    static constexpr k::TaskSpec kTable[] = {
        {"counter", &counter_main, nullptr, 1, 1, 0, 16U * 1024U, k::Policy::kPreemptive},
    };
    g_written = Counts{};
    g_carved = false;
    bsp::BoardConfig cfg = bsp::default_config(bsp::kTile64);
    cfg.powered_at_start = 1U << kTile;
    cfg.monitor_tile = bsp::kNoTile;
    cfg.boot[kTile] = &k::boot_entry;
    k::set_task_table(kTile, kTable, kTick);
    ASSERT_EQ(bsp::board_init(cfg), bsp::BoardError::kOk);
    (void)bsp::run_for(20U * kTick);
    ASSERT_TRUE(g_carved);
  }
};

TEST_F(RamRecord, TheHostReadsWhatTheTaskWroteInItsTilesRam) {
  Counts read{};
  std::string error;
  ASSERT_TRUE(tools::read_record(kTile, kCountsRecord, read, error)) << error;
  EXPECT_GE(read.passes, 15U) << "a pass every tick for about 19 ticks";
  EXPECT_EQ(read.passes, g_written.passes);
  EXPECT_EQ(read.last_tick, g_written.last_tick);
  EXPECT_EQ(read.half_passes, g_written.half_passes);
  EXPECT_TRUE(error.empty());
  Counts again{};
  EXPECT_EQ(tools::try_read_record(kTile, kCountsRecord, again), tools::RecordRead::kOk);
  EXPECT_EQ(again.passes, read.passes) << "the board did not run between the two reads";
}

TEST_F(RamRecord, AnUnknownRecordIsRefusedByName) {
  constexpr bsp::RamRecord<Counts> kNone{"no_such_record", &kCountsLayout};
  Counts out{};
  out.passes = 77U;
  std::string error;
  EXPECT_FALSE(tools::read_record(kTile, kNone, out, error));
  EXPECT_EQ(error, "no record 'no_such_record' on tile 0 (no carve of that name: not a record, or its task has not "
                   "carved it)");
  EXPECT_EQ(out.passes, 77U) << "left alone";
  EXPECT_EQ(tools::try_read_record(kTile, kNone, out), tools::RecordRead::kNoRecord);
}

TEST_F(RamRecord, ATileWithoutTheRecordRefusesIt) {
  Counts out{};
  std::string error;
  EXPECT_FALSE(tools::read_record(1U, kCountsRecord, out, error)) << "tile 1 runs nothing";
  EXPECT_NE(error.find("no record 'counter' on tile 1"), std::string::npos) << error;
  EXPECT_FALSE(tools::read_record(bsp::tile_count(), kCountsRecord, out, error));
  EXPECT_NE(error.find("tile 64 is not on the chip (64 tiles)"), std::string::npos) << error;
}

TEST_F(RamRecord, ARecordOfAnotherSizeIsRefused) {
  struct Smaller {
    std::uint32_t passes;
  };
  constexpr bsp::RamRecord<Smaller> kWrongType{"counter", nullptr};
  Smaller out{};
  std::string error;
  EXPECT_FALSE(tools::read_record(kTile, kWrongType, out, error));
  EXPECT_EQ(error, "record 'counter' on tile 0 is 16 bytes, the reader's type 4");
}

}  // namespace
