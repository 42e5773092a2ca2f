/**
 * @file tile_health_test.cpp
 * @brief Two-level watchdogs on a small board: the tile-health supervisor on tile 0, two worker
 *        tiles with their health agents; hangs, stalled tasks, crashes and the reset cap.
 */
#include "fdir/tile_health.hpp"

#include "bsp_tile64/emu/board.hpp"
#include "bsp_tile64/faults/fault_injector.hpp"
#include "bsp_tile64/emu/udn_net.hpp"
#include "fdir/event_log.hpp"
#include "fdir/ft_sink.hpp"
#include "kernel/kernel.hpp"
#include "tests/fdir/fdir_fixture.hpp"
#include "trn/tasks/tile_map.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace {

using fdir::EventId;
using fdir_test::events_of;
using fdir_test::kTick;

constexpr bsp::TileId kSup = 0;
constexpr bsp::TileId kA = 1;
constexpr bsp::TileId kB = 2;
constexpr std::uint32_t kWorkBudget = 30U;
/** Reset or switch-on to boot entry, as a test can still catch a tile in between. */
constexpr std::uint32_t kBootDelayTicks = 10U;

/** Set by the test: the worker of that tile stops checking in (once; a restart runs normally). */
std::array<bool, 3> g_stall{};
/** Check-ins each tile's worker made: a quiet board is a board whose tasks run, not one that runs nothing. */
std::array<std::uint32_t, 3> g_checkins{};

void work_main(void* /*arg*/) {
  const bsp::TileId self = bsp::current_tile();
  for (;;) {
    if (self < g_stall.size() && g_stall[self]) {
      g_stall[self] = false;
      for (;;) {
        k::sleep(5);  // alive, but never checks in again
      }
    }
    k::checkin();
    if (self < g_checkins.size()) {
      ++g_checkins[self];
    }
    k::sleep(5);
  }
}

constexpr k::TaskSpec kWorkerTable[] = {
    trn::tasks::kCommTask,
    trn::tasks::kAgentTask,
    {"work", &work_main, nullptr, 2, 0, 0, 16U * 1024U, k::Policy::kPreemptive, kWorkBudget},
};
static_assert(k::check_table(kWorkerTable) == k::TableError::kOk);

std::vector<fdir::Event> events_with(bsp::TileId tile, EventId id, std::uint32_t subject) {
  std::vector<fdir::Event> out;
  for (const fdir::Event& e : events_of(tile)) {
    if (e.id == id && e.subject == subject) {
      out.push_back(e);
    }
  }
  return out;
}

double ms(bsp::Cycles c) { return static_cast<double>(c) / static_cast<double>(kTick); }

class TileHealth : public ::testing::Test {
 protected:
  void SetUp() override {
    g_stall = {};
    g_checkins = {};
    trn::tasks::ImageConfig image{};
    ASSERT_EQ(udn::fault_map_init(image.endpoint.boot_map, bsp::kTile64.cols, bsp::kTile64.rows),
              udn::RouteError::kOk);
    image.endpoint.sink = fdir::ft_event_sink();
    image.agent.health_tile = kSup;
    image.agent.watcher_tile = kB;  // the supervisor's tile is watched by tile B's agent
    image.tile_health.watched = (1ULL << kA) | (1ULL << kB);
    ASSERT_EQ(trn::tasks::configure_image(image), trn::tasks::ImageError::kOk);
    bsp::BoardConfig cfg = bsp::default_config(bsp::kTile64);
    cfg.powered_at_start = (1ULL << kSup) | (1ULL << kA) | (1ULL << kB);
    cfg.monitor_tile = kSup;
    cfg.boot_delay_cycles = kBootDelayTicks * kTick;
    for (const bsp::TileId t : {kSup, kA, kB}) {
      cfg.boot[t] = &k::boot_entry;
    }
    k::set_task_table(kSup, trn::tasks::kSupervisorRole, kTick);
    k::set_task_table(kA, kWorkerTable, kTick);
    k::set_task_table(kB, kWorkerTable, kTick);
    ASSERT_EQ(bsp::region_reset(bsp::Region{bsp::Region::kDdr}), bsp::MemError::kOk);
    ASSERT_EQ(bsp::board_init(cfg), bsp::BoardError::kOk);
    ASSERT_EQ(bsp::udn_net_init(bsp::NetConfig{}), bsp::NetError::kOk);
    ASSERT_EQ(fdir::event_log_init(), fdir::LogError::kOk);
    (void)bsp::run_for(200U * kTick);
  }
};

TEST_F(TileHealth, AQuietBoardRaisesNothing) {
  const std::array<std::uint32_t, 3> before = g_checkins;
  (void)bsp::run_for(500U * kTick);
  const fdir::TileHealthView v = fdir::tile_health_view(kSup);
  // The board is alive and watched: both workers check in every 5 ticks, the supervisor votes self-tests.
  for (const bsp::TileId t : {kA, kB}) {
    EXPECT_GE(g_checkins[t] - before[t], 90U) << "tile " << t << " checked in";
  }
  EXPECT_GT(v.self_tests, 0U) << "the supervisor ran its self-test rounds";
  EXPECT_EQ(v.expiries, 0U);
  EXPECT_EQ(v.resets, 0U);
  EXPECT_EQ(v.rebooted, 0U);
  for (const bsp::TileId t : {kSup, kA, kB}) {
    EXPECT_EQ(bsp::tile_stats(t).watchdog_expiries, 0U) << "tile " << t;
  }
  EXPECT_TRUE(events_with(kB, EventId::kSupervisorSilent, kSup).empty()) << "the heartbeat is heard";
}

TEST_F(TileHealth, AHungTileIsNamedResetAndReportsBack) {
  const bsp::Cycles hung_at = bsp::board_time();
  ASSERT_EQ(bsp::hang_tile(kA), bsp::BoardError::kOk);
  (void)bsp::run_for(400U * kTick);
  const auto expired = events_with(kSup, EventId::kWatchdogExpired, kA);
  ASSERT_EQ(expired.size(), 1U);
  // The agent kicks every 5 ms with a 20 ms timeout: named within 30 ms.
  EXPECT_LE(ms(expired[0].cycle - hung_at), 30.0);
  ASSERT_EQ(events_with(kSup, EventId::kTileReset, kA).size(), 1U);
  const auto back = events_with(kSup, EventId::kTileRecovered, kA);
  ASSERT_EQ(back.size(), 1U);
  EXPECT_EQ(back[0].cause, static_cast<std::uint32_t>(bsp::BootCause::kCommand));
  EXPECT_EQ(bsp::tile_stats(kA).resets, 1U);
  EXPECT_FALSE(bsp::tile_stopped(kA));
  EXPECT_TRUE(events_with(kSup, EventId::kWatchdogExpired, kB).empty());
  const fdir::TileHealthView v = fdir::tile_health_view(kSup);
  EXPECT_EQ(v.recovered, 1U);
  EXPECT_EQ(v.pending, 0U);
}

TEST_F(TileHealth, AStalledTaskStopsTheKicksOfItsTile) {
  g_stall[kB] = true;
  (void)bsp::run_for(400U * kTick);
  const auto overdue = events_with(kB, EventId::kTaskOverdue, k::find_task(kB, "work"));
  ASSERT_FALSE(overdue.empty());
  EXPECT_EQ(overdue[0].cause, kB);
  EXPECT_EQ(overdue[0].b, kWorkBudget);
  EXPECT_EQ(events_with(kSup, EventId::kWatchdogExpired, kB).size(), 1U);
  EXPECT_EQ(events_with(kSup, EventId::kTileRecovered, kB).size(), 1U);
  EXPECT_TRUE(events_with(kSup, EventId::kWatchdogExpired, kA).empty());
}

TEST_F(TileHealth, ACrashIsReportedAsAnUncommandedBoot) {
  ASSERT_EQ(bsp::reset_tile_for(kB, bsp::ResetReason::kFault), bsp::BoardError::kOk);
  (void)bsp::run_for(300U * kTick);
  const auto rebooted = events_with(kSup, EventId::kTileRebooted, kB);
  ASSERT_EQ(rebooted.size(), 1U);
  EXPECT_EQ(rebooted[0].cause, static_cast<std::uint32_t>(bsp::BootCause::kOther));
  EXPECT_TRUE(events_with(kSup, EventId::kTileReset, kB).empty());
}

TEST_F(TileHealth, ResetsStopAtTheCap) {
  for (int i = 0; i < 4; ++i) {
    ASSERT_EQ(bsp::hang_tile(kA), bsp::BoardError::kOk);
    (void)bsp::run_for(400U * kTick);
  }
  EXPECT_EQ(events_with(kSup, EventId::kTileReset, kA).size(), 3U);
  EXPECT_EQ(events_with(kSup, EventId::kTileRecovered, kA).size(), 3U);
  EXPECT_EQ(events_with(kSup, EventId::kActionCapped, kA).size(), 1U);
  EXPECT_EQ(bsp::tile_stats(kA).resets, 3U);
  // The fourth hang retires the tile: switched off, no role to move here.
  EXPECT_EQ(bsp::power_state(kA), bsp::PowerState::kOff);
  EXPECT_NE(fdir::tile_health_view(kSup).retired & (1ULL << kA), 0ULL);
}

TEST_F(TileHealth, AResetTileThatNeverReportsIsLost) {
  ASSERT_EQ(bsp::hang_tile(kA), bsp::BoardError::kOk);
  for (int i = 0; i < 100 && events_with(kSup, EventId::kTileReset, kA).empty(); ++i) {
    (void)bsp::run_for(kTick);
  }
  ASSERT_EQ(events_with(kSup, EventId::kTileReset, kA).size(), 1U);
  (void)bsp::run_for(2U * kTick);  // the reset command is applied at the next barrier
  ASSERT_EQ(bsp::power_state(kA), bsp::PowerState::kBooting);
  ASSERT_EQ(bsp::power_off(kA), bsp::BoardError::kOk);  // it never boots
  (void)bsp::run_for(400U * kTick);
  EXPECT_EQ(events_with(kSup, EventId::kTileLost, kA).size(), 1U);
  EXPECT_TRUE(events_with(kSup, EventId::kTileRecovered, kA).empty());
  EXPECT_EQ(fdir::tile_health_view(kSup).lost, 1U);
}

TEST_F(TileHealth, TheSupervisorsOwnWatchdogResetsItsTile) {
  ASSERT_EQ(bsp::hang_tile(kSup), bsp::BoardError::kOk);
  (void)bsp::run_for(300U * kTick);
  EXPECT_EQ(bsp::tile_stats(kSup).resets, 1U);
  EXPECT_FALSE(bsp::tile_stopped(kSup));
  const auto rebooted = events_with(kSup, EventId::kTileRebooted, kSup);
  ASSERT_EQ(rebooted.size(), 1U);
  EXPECT_EQ(rebooted[0].cause, static_cast<std::uint32_t>(bsp::BootCause::kWatchdog));
  // Its own watchdog and boot come well within the watcher's timeout: one reset, not two.
  EXPECT_TRUE(events_with(kB, EventId::kSupervisorSilent, kSup).empty());
  // Back in service: a hang of a worker is handled by the restarted supervisor.
  ASSERT_EQ(bsp::hang_tile(kB), bsp::BoardError::kOk);
  (void)bsp::run_for(400U * kTick);
  EXPECT_EQ(events_with(kSup, EventId::kTileReset, kB).size(), 1U);
}

// The watcher is never alone: with its own watchdog failed, a hung supervisor is found by the tile
// that hears its heartbeat, reset by it, and seen back; then it supervises again.
TEST_F(TileHealth, AHungSupervisorWhoseWatchdogFailedIsResetByItsWatcher) {
  ASSERT_EQ(bsp::set_watchdog_failed(kSup, true), bsp::BoardError::kOk);
  const bsp::Cycles hung_at = bsp::board_time();
  ASSERT_EQ(bsp::hang_tile(kSup), bsp::BoardError::kOk);
  (void)bsp::run_for(300U * kTick);
  const auto unheard = events_with(kB, EventId::kSupervisorUnheard, kSup);
  ASSERT_EQ(unheard.size(), 1U);
  EXPECT_EQ(unheard[0].cause, kB);
  // Heartbeats every 5 ticks, a 40-tick timeout checked every 5: suspected within 50 ms.
  EXPECT_LE(ms(unheard[0].cycle - hung_at), 50.0);
  // Named hung once the reset brought it back.
  const auto silent = events_with(kB, EventId::kSupervisorSilent, kSup);
  ASSERT_EQ(silent.size(), 1U);
  EXPECT_GT(silent[0].cycle, unheard[0].cycle);
  const auto reset = events_with(kB, EventId::kTileReset, kSup);
  ASSERT_EQ(reset.size(), 1U);
  EXPECT_EQ(reset[0].cause, 1U) << "reset by the watcher";
  const auto back = events_with(kB, EventId::kTileRecovered, kSup);
  ASSERT_EQ(back.size(), 1U);
  EXPECT_EQ(back[0].cause, static_cast<std::uint32_t>(bsp::BootCause::kCommand));
  EXPECT_EQ(bsp::tile_stats(kSup).resets, 1U);
  EXPECT_FALSE(bsp::tile_stopped(kSup));
  ASSERT_EQ(bsp::hang_tile(kA), bsp::BoardError::kOk);
  (void)bsp::run_for(400U * kTick);
  EXPECT_EQ(events_with(kSup, EventId::kTileRecovered, kA).size(), 1U) << "the supervisor works again";
}

// The watcher's resets have a cap too: the fourth hang is named, then left (action_capped).
TEST_F(TileHealth, TheWatchersResetsStopAtTheCap) {
  ASSERT_EQ(bsp::set_watchdog_failed(kSup, true), bsp::BoardError::kOk);
  for (int i = 0; i < 4; ++i) {
    ASSERT_EQ(bsp::hang_tile(kSup), bsp::BoardError::kOk);
    (void)bsp::run_for(300U * kTick);
  }
  EXPECT_EQ(events_with(kB, EventId::kSupervisorUnheard, kSup).size(), 4U);
  EXPECT_EQ(events_with(kB, EventId::kSupervisorSilent, kSup).size(), 3U) << "the capped fourth is never heard back";
  EXPECT_EQ(events_with(kB, EventId::kTileReset, kSup).size(), 3U);
  EXPECT_EQ(events_with(kB, EventId::kTileRecovered, kSup).size(), 3U);
  EXPECT_EQ(events_with(kB, EventId::kActionCapped, kSup).size(), 1U);
  EXPECT_TRUE(bsp::tile_stopped(kSup));
}

/** Self-tests on a board of four: the supervisor and three watched tiles, every round voted 2 of 3. */
class SelfTests : public ::testing::Test {
 protected:
  static constexpr bsp::TileId kC = 3;

  /** Ticks a round waits for its answers. */
  virtual std::uint32_t wait_ticks() const { return 40U; }

  void SetUp() override {
    trn::tasks::ImageConfig image{};
    ASSERT_EQ(udn::fault_map_init(image.endpoint.boot_map, bsp::kTile64.cols, bsp::kTile64.rows),
              udn::RouteError::kOk);
    image.endpoint.sink = fdir::ft_event_sink();
    image.agent.health_tile = kSup;
    image.tile_health.watched = (1ULL << kA) | (1ULL << kB) | (1ULL << kC);
    image.tile_health.self_test_wait_ticks = wait_ticks();
    ASSERT_EQ(trn::tasks::configure_image(image), trn::tasks::ImageError::kOk);
    bsp::BoardConfig cfg = bsp::default_config(bsp::kTile64);
    cfg.powered_at_start = (1ULL << kSup) | (1ULL << kA) | (1ULL << kB) | (1ULL << kC);
    cfg.monitor_tile = kSup;
    cfg.boot_delay_cycles = kBootDelayTicks * kTick;
    for (const bsp::TileId t : {kSup, kA, kB, kC}) {
      cfg.boot[t] = &k::boot_entry;
    }
    k::set_task_table(kSup, trn::tasks::kSupervisorRole, kTick);
    for (const bsp::TileId t : {kA, kB, kC}) {
      k::set_task_table(t, kWorkerTable, kTick);
    }
    ASSERT_EQ(bsp::region_reset(bsp::Region{bsp::Region::kDdr}), bsp::MemError::kOk);
    ASSERT_EQ(bsp::board_init(cfg), bsp::BoardError::kOk);
    ASSERT_EQ(bsp::udn_net_init(bsp::NetConfig{}), bsp::NetError::kOk);
    ASSERT_EQ(fdir::event_log_init(), fdir::LogError::kOk);
  }
};

/**
 * Self-tests whose answers always miss the round's wait (1 tick: an answer takes an agent pass
 * and a network crossing): every round is reported late for its three tiles, and the answers
 * that still come before the next round are voted.
 */
class SelfTestLate : public SelfTests {
 protected:
  std::uint32_t wait_ticks() const override { return 1U; }
};

/** An upset of @p tile's resident self-test pattern, @p byte and @p bit into it, one tick from now. */
bsp::FaultSpec pattern_upset(bsp::TileId tile, std::uint64_t byte, std::uint32_t bit) {
  bsp::FaultSpec seu{};
  seu.cycle = bsp::board_time() + kTick;
  seu.kind = bsp::FaultKind::kSeu;
  seu.tile = tile;
  seu.offset = byte;
  seu.bit = bit;
  std::copy_n(fdir::kSelfTestCarve, std::char_traits<char>::length(fdir::kSelfTestCarve), seu.carve.begin());
  return seu;
}

/** A corrupted self-test digest of @p tile, one tick from now. */
bsp::FaultSpec digest_sdc(bsp::TileId tile) {
  bsp::FaultSpec sdc{};
  sdc.cycle = bsp::board_time() + kTick;
  sdc.kind = bsp::FaultKind::kSdc;
  sdc.tile = tile;
  sdc.channel = fdir::kSelfTestChannel;
  return sdc;
}

// A ping would pass a tile whose memory took an upset; the self-test reads the tile's resident
// pattern, so the tile is outvoted, and the agent's rewrite of the pattern after each answer (the
// scrub) makes it agree in its next round: a transient upset is not a retirement.
TEST_F(SelfTests, AnUpsetOfAResidentPatternIsOutvotedThenScrubbed) {
  (void)bsp::run_for(200U * kTick);
  ASSERT_EQ(bsp::fault_plan_add(pattern_upset(kB, 1234U, 5U)), bsp::FaultError::kOk);
  (void)bsp::run_for(600U * kTick);
  ASSERT_EQ(bsp::fault_log().size(), 1U);
  EXPECT_EQ(bsp::fault_log()[0].status, bsp::FaultStatus::kApplied);
  ASSERT_EQ(events_with(kSup, EventId::kSelfTestMismatch, kB).size(), 1U);
  EXPECT_EQ(events_with(kSup, EventId::kSelfTestAgree, kB).size(), 1U);
  EXPECT_EQ(fdir::tile_health_view(kSup).retired, 0ULL);
  EXPECT_EQ(fdir::tile_health_view(kSup).mismatches, 1U) << "no healthy tile is outvoted";
}

// The supervisor's own tile takes its turn as a target and computes its digest itself: outvoted
// twice in a row, it resets its own tile (no spare takes the supervisor's role), then agrees.
TEST_F(SelfTests, TheSupervisorTakesItsTurnAndResetsItselfWhenOutvotedTwice) {
  (void)bsp::run_for(100U * kTick);
  for (std::uint32_t n = 1U; n <= 2U; ++n) {
    ASSERT_EQ(bsp::fault_plan_add(digest_sdc(kSup)), bsp::FaultError::kOk);
    for (int i = 0; i < 400 && events_with(kSup, EventId::kSelfTestMismatch, kSup).size() < n; ++i) {
      (void)bsp::run_for(kTick);
    }
    ASSERT_EQ(events_with(kSup, EventId::kSelfTestMismatch, kSup).size(), n);
  }
  ASSERT_EQ(events_with(kSup, EventId::kTileReset, kSup).size(), 1U);
  (void)bsp::run_for(400U * kTick);
  EXPECT_EQ(bsp::tile_stats(kSup).resets, 1U);
  const auto rebooted = events_with(kSup, EventId::kTileRebooted, kSup);
  ASSERT_EQ(rebooted.size(), 1U) << "the supervisor writes its own restart";
  EXPECT_EQ(fdir::tile_health_view(kSup).mismatches, 0U) << "a clean start: no tile outvoted since";
  EXPECT_GE(fdir::tile_health_view(kSup).self_tests, 4U) << "the restarted supervisor votes again";
}

TEST_F(SelfTestLate, LateAnswersAreReportedAndStillVoted) {
  (void)bsp::run_for(600U * kTick);
  const fdir::TileHealthView v = fdir::tile_health_view(kSup);
  EXPECT_GE(v.self_tests_late, 5U) << "every round misses a 1-tick wait";
  EXPECT_GE(v.self_tests, 5U) << "the late answers complete their rounds";
  EXPECT_EQ(v.mismatches, 0U);
  EXPECT_FALSE(events_with(kSup, EventId::kSelfTestLate, kB).empty());
}

TEST_F(SelfTestLate, AWrongDigestThatComesLateIsStillOutvoted) {
  (void)bsp::run_for(200U * kTick);
  bsp::FaultSpec sdc{};
  sdc.cycle = bsp::board_time() + kTick;
  sdc.kind = bsp::FaultKind::kSdc;
  sdc.tile = kB;
  sdc.channel = fdir::kSelfTestChannel;
  ASSERT_EQ(bsp::fault_plan_add(sdc), bsp::FaultError::kOk);
  (void)bsp::run_for(300U * kTick);
  const auto outvoted = events_with(kSup, EventId::kSelfTestMismatch, kB);
  ASSERT_EQ(outvoted.size(), 1U) << "a late answer used to be dropped with its round";
  EXPECT_TRUE(events_with(kSup, EventId::kSelfTestMismatch, kA).empty());
  EXPECT_TRUE(events_with(kSup, EventId::kSelfTestMismatch, kC).empty());
}

// The digest of a seed is a fixed value (a literal, taken from the kernel when it was written): tiles
// that run this code agree by construction, and a change of the kernel or the pattern shows here.
TEST(SelfTestKernel, TheDigestOfASeedIsPinned) {
  std::vector<std::uint8_t> pattern(fdir::kSelfTestPatternBytes);
  fdir::self_test_pattern_fill(pattern);
  bsp::Work w1{};
  bsp::Work w2{};
  const std::uint32_t a = fdir::self_test_kernel(41U, pattern, w1);
  EXPECT_EQ(a, 2227140200U);
  EXPECT_NE(fdir::self_test_kernel(42U, pattern, w2), a) << "another seed, another digest";
  EXPECT_GT(w1.flops, 0U);
  EXPECT_GE(w1.int_macs, fdir::kSelfTestPatternBytes);
}

// Every single flipped bit of the resident pattern changes the digest (the weights are odd).
TEST(SelfTestKernel, EveryUpsetOfThePatternChangesTheDigest) {
  std::vector<std::uint8_t> pattern(fdir::kSelfTestPatternBytes);
  fdir::self_test_pattern_fill(pattern);
  bsp::Work w{};
  for (const std::uint32_t seed : {7U, 0x9E3779B9U}) {
    const std::uint32_t clean = fdir::self_test_kernel(seed, pattern, w);
    for (std::size_t i = 0; i < pattern.size(); ++i) {
      for (std::uint32_t b = 0; b < 8U; ++b) {
        pattern[i] = static_cast<std::uint8_t>(pattern[i] ^ (1U << b));
        ASSERT_NE(fdir::self_test_kernel(seed, pattern, w), clean) << "byte " << i << " bit " << b;
        pattern[i] = static_cast<std::uint8_t>(pattern[i] ^ (1U << b));
      }
    }
  }
}

}  // namespace
