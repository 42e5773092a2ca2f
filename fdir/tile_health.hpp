/**
 * @file tile_health.hpp
 * @brief Core health, level 2: the tile-health supervisor that takes the watchdog interrupt,
 *        resets a silent tile and sees it back, votes self-tests, retires tiles and moves their roles.
 *
 * Level 1, on every tile: the health agent (fdir/health_agent.hpp).
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
 * nearest free spare (or the one spare kept for its slot, slot_spare): the
 * supervisor writes the slot into the spare's boot
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

#include "bsp_tile64/api/port.hpp"
#include "fdir/health_agent.hpp"
#include "fdir/health_messages.hpp"
#include "kernel/task_table.hpp"
#include "udn/endpoint.hpp"

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>

namespace bsp {
struct ControlLayout;
}  // namespace bsp

namespace fdir {

/** tile_lost's cause for a tile cut off: its switch is declared failed (above every tile id). */
inline constexpr std::uint32_t kLostSwitchFailed = 0x100U;

/** No role slot has a spare of its own. */
constexpr std::array<bsp::TileId, udn::kRoleSlots> no_slot_spares() noexcept {
  std::array<bsp::TileId, udn::kRoleSlots> a{};
  for (bsp::TileId& t : a) {
    t = bsp::kNoTile;
  }
  return a;
}

struct TileHealthConfig {
  std::uint64_t watched = 0U;              ///< tiles whose agents report here (role tiles)
  std::uint64_t spares = 0U;               ///< tiles off at boot that can take a role
  std::uint32_t movable_slots = 0U;        ///< role slots that move to a spare (bit per udn role slot)
  /**
   * Per role slot, the one spare it moves to (kNoTile: the nearest free one):
   * a role wired to its tile, as the I/O role is to the devices, moves only
   * to the tile its second attachment is on. Such a spare is kept for its
   * slot; with it gone (taken, or its switch failed) the role's tile is kept
   * and reset, as a role that does not move.
   */
  std::array<bsp::TileId, udn::kRoleSlots> slot_spare = no_slot_spares();
  std::uint32_t max_resets = 3U;           ///< resets per tile over the mission (>= 1)
  std::uint32_t boot_timeout_ticks = 200U; ///< a reset tile reports within this or is lost
  std::uint32_t poll_ticks = 2U;           ///< looks at boot reports and timeouts at least this often
  std::uint32_t self_test_ticks = 50U;     ///< a self-test round this often (0: none)
  std::uint32_t self_test_wait_ticks = 40U;///< results of a round are voted this long after the requests
  std::uint32_t disagreements_to_fail = 2U;///< self-tests in a row a tile disagrees in before it is retired (>= 1)
  /**
   * The supervisor's own role slot (kRoleSlots or more: none). A spare whose
   * boot slot is this one is the standby its watcher switched on: it takes
   * the supervisor's state from the ledger and moves the slot to itself.
   */
  std::uint32_t own_slot = 0xFFFF'FFFFU;
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

/**
 * The supervisor's tile this standby took the role over from (kNoTile: none):
 * its watcher found it silent after a reset, to it and to the tiles beside
 * it, so the network-health task on the same tile puts its switch in the map.
 * [task, on the supervisor's tile]
 */
bsp::TileId tile_health_replaced() noexcept;

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

/**
 * Assigns role slot @p slot to spare @p tile before it is switched on (the
 * supervisor's watcher does so for the standby). [task]
 * @return false before boot_slots_init or for a tile off the chip.
 */
[[nodiscard]] bool boot_slot_assign(bsp::TileId tile, std::uint32_t slot) noexcept;

/**
 * Applies the role moves the supervisor's ledger holds to the current tile's
 * endpoint (older ones are refused): a tile that boots starts from the boot
 * directory, and its boot report must reach the supervisor where it is now.
 * [task, endpoint open]
 */
void ledger_roles_apply() noexcept;

/** The view of the supervisor on @p tile (all zero when none runs there). [host] */
TileHealthView tile_health_view(bsp::TileId tile) noexcept;

/** Name of the supervisor's state carve, and its layout (bsp::ControlLayout: what an upset of it does). [host] */
inline constexpr const char* kTileHealthCarve = "tile_health";
const bsp::ControlLayout& tile_health_state_layout() noexcept;

}  // namespace fdir
