/**
 * @file tile_health.hpp
 * @brief Core health, two-level watchdogs: every tile's health agent, and the tile-health
 *        supervisor that takes the watchdog interrupt, resets a silent tile and sees it back.
 *
 * Level 1, on every tile (health_agent_main, a periodic task): each watched
 * task (TaskSpec::watch_ticks > 0) checks in with k::checkin() within its
 * budget; the agent kicks the tile's hardware watchdog only while every
 * watched task is within budget. A task past its budget is written once as
 * kTaskOverdue and the kicks stop, so the hardware watchdog expires. At its
 * start the agent arms the watchdog and sends the supervisor a boot report
 * with the tile's reset cause (kMsgBooted on kFtChanHealth).
 *
 * Level 2, on the supervisor's tile (tile_health_task_main): the board raises
 * Irq::kWatchdog there when any tile's watchdog expires. The supervisor names
 * the tile (kWatchdogExpired) and, through a health-table monitor per tile
 * (fdir/health_table.hpp; cap max_resets, as cFS HS), resets it
 * (kTileReset). The reset tile boots its role's task table again; its agent's
 * boot report closes the recovery (kTileRecovered, with the time since the
 * reset). A boot report nobody commanded (a crash) is kTileRebooted; a reset
 * tile silent for boot_timeout_ticks is kTileLost.
 *
 * Computational self-tests (the paper's "neighbours ask C to compute a task
 * and check the result"): every self_test_ticks the supervisor asks a target
 * tile (round robin over the watched tiles) and two tiles nearest it to
 * compute self_test_kernel from the same seed; each agent passes its digest
 * through bsp::publish_filter (where a corrupted output is injected) and
 * sends it back. The digests are voted: a tile outvoted by the other two is
 * written (kSelfTestMismatch, detection) and, after disagreements_to_fail
 * rounds in a row, retired like a silent tile; a suspect that agrees again is
 * kSelfTestAgree (recovery). A tile that has not answered at the round's
 * wait is reported (kSelfTestLate: a busy tile, or a silent one, which the
 * watchdog covers) and the round is voted if its answer still comes before
 * the next round. A ping echo would pass a tile that
 * computes wrong; the vote does not. The kernel also reads a memory pattern
 * each agent keeps resident in its tile's RAM (kSelfTestCarve): an upset of
 * it is outvoted like a wrong computation. The agent writes the pattern anew
 * after each answer (a scrub), so a transient upset agrees again in the
 * tile's next round while a fault that stays is outvoted again and retired.
 * The supervisor's own tile takes its turn as a target: it computes its
 * digest itself, and outvoted disagreements_to_fail rounds in a row it
 * resets its own tile (it has no spare to move to).
 *
 * Retirement and spares: a tile past its reset cap (kActionCapped), or lost,
 * is retired: switched off (its switch still routes) and every movable role
 * slot it ran (the messaging role directory, udn::RoleDirectory) moves to the
 * nearest free spare: the supervisor writes the slot into the spare's boot
 * assignment (boot_slot, in DDR), switches it on (boot delay), applies the
 * move to its own directory and sends it to every running tile
 * (kMsgRoleMove), so senders follow without knowing tile numbers
 * (kRoleMoved). The spare's boot report closes the move (kRoleRestored);
 * the role takes over its state from where the role keeps it (the filter's
 * DDR checkpoint, the coordinator's DDR tables). A tile that boots is sent
 * every move made so far, as it starts from the boot directory.
 *
 * The supervisor's own tile has no monitor above it on the board: its agent
 * arms the hardware watchdog with reset on expiry, and the supervisor writes
 * kTileRebooted about itself when it starts after such a reset. A second
 * tile watches it too, so the watcher is never alone (a hung supervisor whose
 * own watchdog failed would otherwise go unnoticed): the agent of the
 * supervisor's tile sends that tile a heartbeat (kMsgAlive) each time it kicks
 * its own watchdog, that is while every watched task of the supervisor's tile
 * is within budget. The watcher's agent names a heartbeat missing for
 * watcher_timeout_ticks (kSupervisorSilent), resets the supervisor's tile
 * (kTileReset, at most max_watcher_resets over the mission) and writes
 * kTileRecovered at the first heartbeat after. The supervisor watches the
 * watcher like every other tile.
 */
#pragma once

#include "bsp_tile64/port.hpp"
#include "bsp_tile64/work.hpp"
#include "kernel/task_table.hpp"

#include <cstddef>
#include <cstdint>
#include <span>

namespace bsp {
struct ControlLayout;
}  // namespace bsp

namespace fdir {

/** Boot report (udn::kFtChanHealth): [0] kMsgBooted [1] tile [2] bsp::BootCause. */
/** tile_lost's cause for a tile cut off: its switch is declared failed (above every tile id). */
inline constexpr std::uint32_t kLostSwitchFailed = 0x100U;

inline constexpr std::uint32_t kMsgBooted = 0x424F4F54U;  // "BOOT"
inline constexpr std::uint32_t kBootedWords = 3U;

/** Self-test request (supervisor -> agent, kFtChanHealth): [0] kMsgSelfTest [1] round [2] seed. */
inline constexpr std::uint32_t kMsgSelfTest = 0x53545251U;  // "STRQ"
/** Self-test result (agent -> supervisor): [0] kMsgSelfTestResult [1] tile [2] round [3] digest. */
inline constexpr std::uint32_t kMsgSelfTestResult = 0x53545253U;  // "STRS"
inline constexpr std::uint32_t kSelfTestWords = 3U;
inline constexpr std::uint32_t kSelfTestResultWords = 4U;
/** Heartbeat of the supervisor's tile (its agent -> the watcher, kFtChanHealth): [0] kMsgAlive [1] tile [2] bsp::BootCause. */
inline constexpr std::uint32_t kMsgAlive = 0x414C5645U;  // "ALVE"
inline constexpr std::uint32_t kAliveWords = 3U;
/**
 * A coordinator's report of a worker whose results stay wrong (fdir/result_trust.hpp; coordinator ->
 * supervisor, kFtChanHealth): [0] kMsgResultsBad [1] coordinator tile [2] worker tile [3] kResultsReset
 * or kResultsReplace [4] the boot slot a replacing spare is to run (boot_slot) [5] the coordinator's
 * channel for the answer. A reset is written kTileReset with cause 2; a replacement switches the
 * worker off for good and a spare on with that boot slot (kRoleMoved, then kRoleRestored at its boot).
 */
inline constexpr std::uint32_t kMsgResultsBad = 0x52424144U;  // "RBAD"
inline constexpr std::uint32_t kResultsBadWords = 6U;
inline constexpr std::uint32_t kResultsReset = 1U;
inline constexpr std::uint32_t kResultsReplace = 2U;
/**
 * Power policy (-> the tile-health supervisor, kFtChanHealth): [0] kMsgPark
 * [1] the asking tile [2] the tile [3] 1 switch it off (park), 0 switch it on
 * (wake) [4] the channel of the answer. A parked tile is not watched and is
 * off by design for every endpoint and the network-health task (its switch
 * still routes); it is switched off kParkOffTicks after the others are told.
 * A woken tile is watched again from its boot report.
 */
inline constexpr std::uint32_t kMsgPark = 0x50524B52U;  // "PRKR"
inline constexpr std::uint32_t kParkWords = 5U;
/** The answer: [0] kMsgParkDone [1] tile [2] 1 off, 0 booted and watched again. */
inline constexpr std::uint32_t kMsgParkDone = 0x50524B44U;  // "PRKD"
inline constexpr std::uint32_t kParkDoneWords = 3U;
/** Ticks between telling the tiles of a park and switching the tile off (the notices arrive first). */
inline constexpr std::uint32_t kParkOffTicks = 20U;

/** The supervisor's answer to a replacement (-> the coordinator's channel): [0] kMsgReplaced [1] old tile [2] spare (kNoTile: none). */
inline constexpr std::uint32_t kMsgReplaced = 0x52504C44U;  // "RPLD"
inline constexpr std::uint32_t kReplacedWords = 3U;
/*
 * The health messages' fields, and their pack_ / unpack_ (tile_health_messages.cpp).
 * An unpack_ returns false, leaving its output as it was, unless the words are
 * exactly that message with every field in its documented range: tiles below
 * bsp::kMaxTiles, a boot cause of bsp::BootCause, channels below
 * udn::kFtAllChannels, flags 0 or 1.
 */
/** kMsgBooted and kMsgAlive: the sending tile and why it last booted. */
struct TileBootReport {
  bsp::TileId tile = 0U;
  bsp::BootCause cause = bsp::BootCause::kPowerOn;
};
struct SelfTestRequest {
  std::uint32_t round = 0U;
  std::uint32_t seed = 0U;
};
struct SelfTestResult {
  bsp::TileId tile = 0U;
  std::uint32_t round = 0U;
  std::uint32_t digest = 0U;
};
struct ResultsBad {
  bsp::TileId coordinator = 0U;
  bsp::TileId worker = 0U;
  bool replace = false;               ///< kResultsReplace (true) or kResultsReset
  std::uint32_t boot_slot = 0U;       ///< not kNoSlot
  std::uint32_t answer_channel = 0U;
};
struct ParkRequest {
  bsp::TileId asker = 0U;
  bsp::TileId tile = 0U;
  bool off = false;                   ///< park (true) or wake
  std::uint32_t answer_channel = 0U;
};
struct ParkDone {
  bsp::TileId tile = 0U;
  bool off = false;
};
struct Replaced {
  bsp::TileId old_tile = 0U;
  bsp::TileId spare = 0U;             ///< bsp::kNoTile: none
};
void pack_booted(const TileBootReport& r, std::span<std::uint32_t, kBootedWords> w) noexcept;
[[nodiscard]] bool unpack_booted(std::span<const std::uint32_t> w, TileBootReport& out) noexcept;
void pack_alive(const TileBootReport& r, std::span<std::uint32_t, kAliveWords> w) noexcept;
[[nodiscard]] bool unpack_alive(std::span<const std::uint32_t> w, TileBootReport& out) noexcept;
void pack_self_test(const SelfTestRequest& r, std::span<std::uint32_t, kSelfTestWords> w) noexcept;
[[nodiscard]] bool unpack_self_test(std::span<const std::uint32_t> w, SelfTestRequest& out) noexcept;
void pack_self_test_result(const SelfTestResult& r, std::span<std::uint32_t, kSelfTestResultWords> w) noexcept;
[[nodiscard]] bool unpack_self_test_result(std::span<const std::uint32_t> w, SelfTestResult& out) noexcept;
void pack_results_bad(const ResultsBad& r, std::span<std::uint32_t, kResultsBadWords> w) noexcept;
[[nodiscard]] bool unpack_results_bad(std::span<const std::uint32_t> w, ResultsBad& out) noexcept;
void pack_park(const ParkRequest& r, std::span<std::uint32_t, kParkWords> w) noexcept;
[[nodiscard]] bool unpack_park(std::span<const std::uint32_t> w, ParkRequest& out) noexcept;
void pack_park_done(const ParkDone& r, std::span<std::uint32_t, kParkDoneWords> w) noexcept;
[[nodiscard]] bool unpack_park_done(std::span<const std::uint32_t> w, ParkDone& out) noexcept;
void pack_replaced(const Replaced& r, std::span<std::uint32_t, kReplacedWords> w) noexcept;
[[nodiscard]] bool unpack_replaced(std::span<const std::uint32_t> w, Replaced& out) noexcept;

/** Publication channel of a self-test digest (bsp::publish_filter: where corrupted outputs are injected). */
inline constexpr std::uint32_t kSelfTestChannel = 7U;

/** Bytes of the self-test's memory pattern each agent keeps in its tile's RAM (carve kSelfTestCarve). */
inline constexpr std::size_t kSelfTestPatternBytes = 4096U;
/** Name of the pattern's carve (a fault plan's `carve` aims an upset at it). */
inline constexpr const char* kSelfTestCarve = "self_test";

/** Writes the fixed self-test pattern (the same on every tile) into @p pattern. */
void self_test_pattern_fill(std::span<std::uint8_t> pattern) noexcept;

/**
 * The self-test kernel: from @p seed, a 6x6 double-precision matrix product
 * with accumulation (the filter's arithmetic), integer multiply-accumulates
 * over a pseudo-random byte image (the correlator's), and a weighted sum of
 * the tile's resident memory pattern @p pattern (kSelfTestPatternBytes, kept
 * in the tile's RAM between rounds: an upset there reaches the digest); the
 * digest is a CRC-32C of the results. Every healthy tile computes the same
 * digest for the same seed. Charges @p work.
 */
std::uint32_t self_test_kernel(std::uint32_t seed, std::span<const std::uint8_t> pattern, bsp::Work& work) noexcept;

struct HealthAgentConfig {
  bsp::TileId supervisor = bsp::kNoTile;  ///< tile of the tile-health supervisor (boot reports, watchdog monitor)
  std::uint32_t watchdog_ticks = 20U;     ///< hardware watchdog timeout (>= 2 agent periods)
  bsp::TileId watcher = bsp::kNoTile;     ///< tile whose agent watches the supervisor's tile (kNoTile: none)
  /** A supervisor heartbeat missing this long is named and its tile reset (> watchdog_ticks + a boot). */
  std::uint32_t watcher_timeout_ticks = 40U;
  std::uint32_t max_watcher_resets = 3U;  ///< resets of the supervisor's tile by the watcher over the mission
};

/** Agent period: it looks at the check-ins and kicks every this many ticks. */
inline constexpr std::uint32_t kAgentPeriodTicks = 5U;

/** The health agent's task entry (arg: const HealthAgentConfig*). */
void health_agent_main(void* arg) noexcept;

/** The agent's task row for a role's table: just below the messaging service. */
constexpr k::TaskSpec health_agent_task_spec(HealthAgentConfig* cfg) noexcept {
  return k::TaskSpec{"health", &health_agent_main, cfg, 1, kAgentPeriodTicks, 0, 16U * 1024U,
                     k::Policy::kPreemptive, 0U};
}

/** No role slot (boot_slot of a tile that was never assigned one). */
inline constexpr std::uint32_t kNoSlot = 0xFFFF'FFFFU;

struct TileHealthConfig {
  std::uint64_t watched = 0U;              ///< tiles whose agents report here (role tiles)
  std::uint64_t spares = 0U;               ///< tiles off at boot that can take a role
  std::uint32_t movable_slots = 0U;        ///< role slots that move to a spare (bit per udn role slot)
  std::uint32_t max_resets = 3U;           ///< resets per tile over the mission (>= 1)
  std::uint32_t boot_timeout_ticks = 200U; ///< a reset tile reports within this or is lost
  std::uint32_t poll_ticks = 2U;           ///< looks at boot reports and timeouts at least this often
  std::uint32_t self_test_ticks = 50U;     ///< a self-test round this often (0: none)
  std::uint32_t self_test_wait_ticks = 40U;///< results of a round are voted this long after the requests
  std::uint32_t disagreements_to_fail = 2U;///< self-tests in a row a tile disagrees in before it is retired (>= 1)
};

/** The tile-health supervisor's task entry (arg: const TileHealthConfig*). */
void tile_health_task_main(void* arg) noexcept;

/**
 * The network-health task on the supervisor's tile names a silent core whose
 * switch still routes (kCoreSuspect, from the neighbours' pings and the
 * transits): the tile-health supervisor treats it as an expired watchdog
 * (a tile whose watchdog failed is still found). [task, on the supervisor's tile]
 */
void tile_health_core_suspect(bsp::TileId tile) noexcept;

/** What the supervisor has seen and done. [host: displays and tests] */
struct TileHealthView {
  std::uint32_t expiries = 0U;   ///< watchdog expiries taken
  std::uint32_t resets = 0U;     ///< resets commanded
  std::uint32_t recovered = 0U;  ///< reset tiles that reported back
  std::uint32_t rebooted = 0U;   ///< boots nobody commanded
  std::uint32_t lost = 0U;       ///< reset tiles that never reported
  std::uint32_t moves = 0U;      ///< roles moved to a spare
  std::uint32_t restored = 0U;   ///< moved roles whose spare reported
  std::uint64_t pending = 0U;    ///< tiles reset and not yet back
  std::uint64_t retired = 0U;    ///< tiles switched off and given up
  std::uint32_t self_tests = 0U; ///< rounds voted
  std::uint32_t self_tests_late = 0U; ///< rounds closed at their wait without all three answers
  std::uint32_t mismatches = 0U; ///< tiles outvoted
  std::uint64_t spares = 0U;     ///< spares still free
  std::uint64_t parked = 0U;     ///< tiles the power policy switched off (or is about to)
  std::uint32_t parks = 0U;      ///< tiles parked
  std::uint32_t wakes = 0U;      ///< parked tiles woken
};

/** Carves the boot assignments of the spares in DDR, all empty (after bsp::board_init). [host] @return false when full. */
[[nodiscard]] bool boot_slots_init() noexcept;

/** The role slot a supervisor assigned to @p tile before switching it on; kNoSlot for none. [task|host] */
std::uint32_t boot_slot(bsp::TileId tile) noexcept;

/** The view of the supervisor on @p tile (all zero when none runs there). [host] */
TileHealthView tile_health_view(bsp::TileId tile) noexcept;

/** Name of the supervisor's state carve, and its layout (bsp::ControlLayout: what an upset of it does). [host] */
inline constexpr const char* kTileHealthCarve = "tile_health";
const bsp::ControlLayout& tile_health_state_layout() noexcept;

}  // namespace fdir
