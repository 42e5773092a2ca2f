/**
 * @file fault_plan.hpp
 * @brief Fault-plan files (TOML): timed faults of every kind the board and the network support, and random rates.
 *
 * A plan is validated like a scenario file: an unknown key, a key the fault's
 * kind does not use, a value of the wrong type or out of its range, a tile
 * outside the chip, a time before 0 or after the run, more entries than the
 * injector holds: each is an error naming the file, the entry, the key and the
 * allowed range (docs/FAULT_PLANS.md). The image loads the plan before boot,
 * prints the error with exit status 2, and after board_init() and
 * udn_net_init() hands it to the injector with arm_fault_plan().
 *
 * Host code: allocation and exceptions are fine here, never in the run.
 */
#pragma once

#include "bsp_tile64/faults/fault_injector.hpp"
#include "bsp_tile64/api/port.hpp"
#include "trn/tasks/tile_map.hpp"

#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace tools {

class EventLog;

inline constexpr std::size_t kFaultKinds = static_cast<std::size_t>(bsp::FaultKind::kCount);

/** One timed fault. Defaults mean "drawn by the injector" exactly as in bsp::FaultSpec. */
struct FaultPlanItem {
  double t_s = 0.0;  ///< emulated time of the injection, s
  bsp::FaultKind kind = bsp::FaultKind::kCoreHang;
  bsp::TileId tile = 0U;                      ///< target tile (packet_bit_flip: the sending tile)
  std::uint32_t channel = bsp::kAnyChannel;   ///< sdc: publication channel
  std::uint64_t offset = bsp::kRandomOffset;  ///< seu: byte offset in the tile's RAM (or in its carve); packet_bit_flip: word index
  std::string carve;                          ///< seu: the named carve it hits (empty: anywhere in the RAM)
  double position = -1.0;                     ///< seu: where in the upset space, [0, 1) (bsp::FaultSpec::position); negative: drawn
  std::uint32_t bit = bsp::kRandomBit;        ///< seu: 0..7; sdc: bit of the value; packet_bit_flip: 0..31
  std::uint64_t param = 0U;                   ///< link_fail: direction (bsp::UdnDir)
  double shift = 0.0;                         ///< sdc: a lasting error added to every value at the point (bsp::FaultSpec::shift)
  /**
   * Instead of a tile: a role of the tile map (trn::tasks::role_name, e.g.
   * "filter"), resolved to the tile that runs it when the fault is due (the
   * supervisor's role directory: a role that moved to a spare is hit there).
   */
  std::string role;
  std::uint32_t instance = 0U;  ///< role "vision": which of the vision tiles (0 .. 39)
};

/** A telecommand sent up at a time (the uplink to the I/O tile, forwarded to the role it is for). */
struct PlanCommand {
  double t_s = 0.0;
  std::string name;   ///< "filter_tmr" or "filter_simplex"
  std::uint32_t code = 0U;
};

struct FaultPlan {
  std::string name = "plan";
  std::vector<PlanCommand> commands;  ///< in file order
  std::vector<FaultPlanItem> items;  ///< in file order (the injector orders them by time)
  std::array<double, kFaultKinds> rates{};  ///< random faults per tile per emulated second, by kind
};

/** A parsed plan, or the message saying why there is none. */
struct FaultPlanResult {
  std::optional<FaultPlan> plan;
  std::string error;  ///< empty when plan is set; one line per problem
  bool ok() const { return plan.has_value(); }
};

/** Largest random rate accepted, per tile per second (well above any useful campaign). */
inline constexpr double kMaxFaultRate = 1.0;
/** Largest sdc bit index accepted: the bit wraps modulo the published value's size in bits. */
inline constexpr std::uint32_t kMaxSdcBit = 65535U;

/**
 * Parses TOML text; @p source names it in messages (a path, or "<built-in>").
 * Tiles must be below @p tile_count (at most @p dep's), times within
 * 0 .. @p max_time_s; roles and instances are those of @p dep, the chip's deployment.
 */
FaultPlanResult parse_fault_plan(std::string_view text, const std::string& source, std::uint32_t tile_count,
                                 double max_time_s,
                                 const trn::tasks::Deployment& dep = trn::tasks::kTile64Deployment);

/** Reads and parses a plan file; a missing or unreadable file is an error naming it. */
FaultPlanResult load_fault_plan(const std::string& path, const trn::tasks::Deployment& dep, double max_time_s);

/** The tiles the demonstration plan names by number (tile faults: the roles move, these do not). */
struct DemoTiles {
  bsp::TileId vision_coordinator;  ///< sends the work units of each frame
  bsp::TileId filter;              ///< sends the predicted pose to the vision side
  bsp::TileId vision_a;            ///< vision tiles: send their matches back (the first two)
  bsp::TileId vision_b;
  bsp::TileId failed_switch;       ///< a vision tile in the middle of the vision rows, whose switch fails
};

/** The demonstration's tiles on @p d's chip (on the TILE64: 1, 18, 24, 25 and 44). */
constexpr DemoTiles demo_tiles(const trn::tasks::Deployment& d) noexcept {
  const std::uint32_t first_row = d.vision_first / d.cols;
  const std::uint32_t mid_row = (first_row + d.rows - 1U) / 2U;
  return DemoTiles{trn::tasks::boot_tile(d, trn::tasks::Role::kVisionCoordinator),
                   trn::tasks::boot_tile(d, trn::tasks::Role::kFilter), d.vision_first,
                   static_cast<bsp::TileId>(d.vision_first + 1U), mid_row * d.cols + d.cols / 2U};
}
static_assert(demo_tiles(trn::tasks::kTile64Deployment).failed_switch == 44U, "the TILE64's demonstration");

/**
 * The built-in demonstration plan (`make run`): eight packet bit flips on tiles
 * that send fault-tolerant traffic, between 5 and 35 s, one switch failure of a
 * vision tile at 20 s, reliability raised at 10 s by telecommand (the filter
 * becomes TMR), with a corrupted output of replica 1 at 15 s, a hang of
 * replica 2 at 26 s and of the voter at 30.5 s.
 */
FaultPlan demo_fault_plan(const trn::tasks::Deployment& dep);

/** Longest time in the demonstration plan, s (a run shorter than this misses its last faults). */
double demo_fault_plan_end_s();

/**
 * Hands the plan to the injector: fault_plan_add() per item at
 * round(t_s * @p clock_hz) cycles, then fault_set_rate() for each nonzero rate
 * in kind order (so the injector's stream is drawn the same way every run).
 * Call after board_init() (which empties the injector). Network kinds need the
 * handlers that udn_net_init() registers before the run starts. Items that
 * name a role are held back and added by a barrier hook two quanta before
 * their time, with the tile that runs the role then (one that no tile runs is
 * added for no tile and logged as skipped).
 * @return false with a message naming the item if the injector refuses one.
 */
bool arm_fault_plan(const FaultPlan& plan, double clock_hz, std::string& error);

/**
 * The roles a fault plan (and a campaign) can aim at by name, in the order error messages list
 * them: the tile that runs the role when the fault is due is hit.
 */
std::vector<std::string> fault_plan_role_names();

/** "core_hang", "core_reset", "sdc", "seu", "watchdog_fail", "packet_bit_flip", "switch_fail", "link_fail". */
std::string fault_kind_name(bsp::FaultKind k);

/** The kind named @p name (as fault_kind_name writes it); nullopt for an unknown name. */
std::optional<bsp::FaultKind> fault_kind_from_name(std::string_view name);

/** "east", "west", "north", "south" for a link direction (bsp::UdnDir value); "?" otherwise. */
std::string link_direction_name(std::uint64_t dir);

/** The plan as a TOML file that parses back to the same plan (the run folder keeps a copy). */
std::string format_fault_plan(const FaultPlan& plan);

/** One line of ground truth for an injector record: kind, where, what was hit, planned or random. */
std::string describe_fault(const bsp::FaultRecord& r);

/**
 * Adds one event per injector record to @p log: INJECT for a fault that took
 * effect (at its applied time), INFO for one still armed, skipped or
 * unsupported (at its planned time).
 * @return the number of INJECT events added.
 */
std::size_t log_injections(std::span<const bsp::FaultRecord> records, double clock_hz, EventLog& log);

}  // namespace tools
