/**
 * @file fault_injector.hpp
 * @brief The fault injector: the one place that breaks things, by plan or at random, with ground truth.
 *
 * Faults come from a time-ordered plan (fixed-capacity table) and from per-kind
 * random rates, drawn from the injector's own stream (seed, StreamId::kFaults),
 * so adding draws elsewhere never moves a fault. At each barrier the injector
 * turns the faults due in the coming quantum into board events on the target
 * tile at their exact cycle; when the event is delivered, the kind's handler
 * applies the fault and the log record gets its ground truth (what, where,
 * when; for an SEU the address and bit). Every injection also goes into the
 * trace hash.
 *
 * Network kinds have enum slots but no built-in handler: the network model
 * registers one with fault_register_handler() (a handler can apply at once,
 * e.g. a link failure, or arm itself for the next packet, as SDC does for the
 * next publication). Without a handler a fault is logged as kUnsupported.
 *
 * Configure after board_init() (which resets the injector with the board seed).
 */
#pragma once

#include "bsp_tile64/api/port.hpp"
#include "bsp_tile64/emu/rng.hpp"

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>

namespace bsp {

enum class FaultKind : std::uint8_t {
  kCoreHang = 0,      ///< the tile stops making progress (its watchdog keeps counting)
  kCoreReset = 1,     ///< crash: the tile is reset and boots again after the boot delay
  kSdc = 2,           ///< silent data corruption of the tile's next publication (publish_filter)
  kSeu = 3,           ///< single-event upset: one bit of the tile's RAM region flips
  kWatchdogFail = 4,  ///< the tile's watchdog stops expiring
  kPacketBitFlip = 5, ///< network model: a bit of a packet word in transit
  kSwitchFail = 6,    ///< network model: a tile's switch fails permanently
  kLinkFail = 7,      ///< network model: a link fails (param: direction)
  kCount = 8,
};

/** "Draw it": for offsets and bits chosen by the injector's stream at application time. */
inline constexpr std::uint64_t kRandomOffset = ~0ULL;
inline constexpr std::uint32_t kRandomBit = 0xFFFF'FFFFU;
/** SDC on whatever channel the tile publishes next. */
inline constexpr std::uint32_t kAnyChannel = 0xFFFF'FFFFU;

inline constexpr std::size_t kFaultPlanCapacity = 256U;
inline constexpr std::size_t kFaultLogCapacity = 1024U;
inline constexpr std::size_t kMaxArmedSdc = 16U;
/** Longest carve name an SEU can aim at, terminator included. */
inline constexpr std::size_t kCarveNameMax = 24U;

/** One fault to inject. */
struct FaultSpec {
  Cycles cycle = 0U;                ///< when (a plan entry in the past is applied at the next barrier)
  FaultKind kind = FaultKind::kCoreHang;
  TileId tile = 0U;                 ///< target tile
  std::uint32_t channel = kAnyChannel;  ///< SDC: publication channel
  std::uint64_t offset = kRandomOffset; ///< SEU: byte offset in the tile's region; network: word index
  std::uint32_t bit = kRandomBit;   ///< SEU: bit 0..7 of the byte; SDC: bit of the value; network: bit of the word
  std::uint64_t param = 0U;         ///< kind-specific (network kinds)
  /**
   * SDC: non-zero for a lasting corruption (a part that computes wrong from
   * then on, e.g. a damaged unit): instead of one bit flip, this is added to
   * the first double of every value published on the channel, and the fault
   * stays armed for the rest of the run (FaultRecord::hits counts the values).
   */
  double shift = 0.0;
  /**
   * SEU: the named carve of the tile's RAM it hits (bsp::region_carves, e.g.
   * "ekf"); offset then counts from the carve's start (random: anywhere in it).
   * Empty: the whole RAM. A carve the tile does not have: skipped.
   */
  std::array<char, kCarveNameMax> carve{};
  /**
   * SEU: where in the upset space the byte is, as a fraction in [0, 1): the
   * byte at that fraction of the tile's carves that are not stacks (in RAM
   * order), or of the named carve. Negative: drawn by the injector's stream
   * (which, seeded by the board, draws the same first byte in every run of a
   * seed: a campaign draws this instead). Not with an explicit offset.
   */
  double position = -1.0;
};

enum class FaultStatus : std::uint8_t {
  kScheduled,    ///< waiting for its cycle
  kApplied,      ///< took effect (ground truth filled in)
  kArmed,        ///< SDC (or a network kind) waiting for the data it corrupts
  kSkipped,      ///< could not apply (bad target, nothing carved, table full)
  kUnsupported,  ///< no handler registered for the kind
};

/** How an SEU was applied: the bit flipped, or the tile crashed, and why (ground truth). */
enum class UpsetModel : std::uint8_t {
  kNone,          ///< not an SEU, or not applied
  kFlipped,       ///< the bit flipped: data, or emulated state in control data (CarveUse, ControlLayout)
  kHostCrash,     ///< a host member of a control struct (a pointer, a host context): the tile crashed
  kControlCrash,  ///< control data whose layout is not declared: the tile crashed
  kStackCrash,    ///< a context's stack (aimed there, random upsets avoid them): the tile crashed
};

/** One injection and its ground truth. */
struct FaultRecord {
  FaultSpec spec;          ///< as planned, or as drawn for a random fault
  bool random;             ///< from the rates, not the plan
  FaultStatus status;
  Cycles applied_cycle;    ///< when it took effect (SDC: when the value was corrupted)
  std::uint64_t offset;    ///< SEU: byte offset in the region; SDC: byte offset in the value
  std::uint32_t bit;       ///< SEU: bit in that byte; SDC: bit index in the value
  std::uintptr_t address;  ///< SEU/SDC: address of the flipped byte
  const char* carve = nullptr;  ///< SEU: name of the carve it landed in (nullptr: none)
  std::uint64_t carve_offset = 0U;  ///< SEU: byte offset of the flipped byte in that carve
  /**
   * SEU: it landed on host state (a host member of control data, control
   * data with no declared layout, a stack: `upset` says which), where the
   * emulator keeps host addresses: nothing is flipped and the tile crashes
   * instead (reset as by a core_reset), the likely fate of a tile whose
   * control blocks took an upset. An upset of the emulated state in control
   * data flips the bit (not crashed).
   */
  bool crashed = false;
  UpsetModel upset = UpsetModel::kNone;  ///< SEU: how it was applied
  std::uint32_t hits = 0U;  ///< SDC with a shift: values it changed so far (applied_cycle: the first)
};

enum class FaultError : std::uint8_t { kOk, kFull, kBadTile, kBadKind, kBadRate };

/**
 * Applies a fault described by @p rec on its target tile, at rec.applied_cycle
 * (already set). May draw from @p rng. Returns the resulting status and fills
 * the ground-truth fields it knows. [isr-like: runs on the target tile's event]
 */
using FaultHandler = FaultStatus (*)(FaultRecord& rec, Rng& rng);

/** Adds a plan entry, kept in time order (equal times keep insertion order). [host] */
FaultError fault_plan_add(const FaultSpec& spec) noexcept;

/**
 * Sets the random rate of @p kind in faults per tile per emulated second (0 disables).
 * Draws the next random fault time from the injector's stream. [host]
 */
FaultError fault_set_rate(FaultKind kind, double per_tile_per_second) noexcept;

/** Installs the handler of @p kind (network model); replaces the built-in one. [host] */
FaultError fault_register_handler(FaultKind kind, FaultHandler handler) noexcept;

/** Every injection so far, in scheduling order. [host] */
std::span<const FaultRecord> fault_log() noexcept;

/** Injections lost because the log was full. [host] */
std::uint64_t fault_log_dropped() noexcept;

}  // namespace bsp
