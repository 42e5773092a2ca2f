/**
 * @file state_block.hpp
 * @brief The filter state as a fixed-size, versioned, checksummed byte block (TMR state transfer).
 *
 * Layout, little-endian, no padding (offsets in bytes):
 *    0 u32 magic 0x464E5254 ("TRNF")   4 u32 version (2)
 *    8 u32 block size (18444)          12 u32 reserved, 0
 *   16 u32 initialized (0/1)           20 u32 last_imu_ok (0/1)
 *   24 f64 t_s                         32 f64 t_last_update_s
 *   40 u64 propagations                48 12 x u32 counters (FilterCounters order)
 *   96 16 x f64 nominal: p[3] v[3] q(w,x,y,z) b_g[3] b_a[3]
 *  224 225 x f64 covariance, row-major
 * 2024 u32 history entries n (0..256) 2028 u32 reserved, 0
 * 2032 3 x f64 reference velocity
 * 2056 256 x (f64 t, f64 p[3], f64 q(w,x,y,z)) pose history, oldest first; entries n.. are zero
 *18440 u32 CRC-32 of bytes [0, 18440)
 * Version 1 (2020 bytes, no history, ten counters) is refused: a replica
 * without the history could not apply a lagged match as the others do.
 */
#pragma once

#include "trn/filter/filter_state.hpp"

#include <array>
#include <cstdint>

namespace trn::filter {

inline constexpr std::uint32_t kStateMagic = 0x464E5254U;
inline constexpr std::uint32_t kStateVersion = 2U;
inline constexpr std::uint32_t kHistoryEntryBytes = 64U;
inline constexpr std::uint32_t kStateBlockBytes =
    16U + 8U + 16U + 8U + 48U + 128U + 1800U + 8U + 24U + kHistoryLen * kHistoryEntryBytes + 4U;
static_assert(kStateBlockBytes == 18444U, "the documented layout");

using StateBlock = std::array<std::uint8_t, kStateBlockBytes>;

enum class BlockError : std::uint8_t {
  kOk,
  kBadSize,      ///< wrong number of bytes
  kBadMagic,
  kBadVersion,
  kBadChecksum,
  kBadContent,   ///< checksum fine but a field is out of range (flags, non-finite numbers)
};

/** Writes @p s into @p out. Always kOk for a FilterState (the size is fixed). */
BlockError write_state_block(const FilterState& s, StateBlock& out) noexcept;

/**
 * Reads a block of @p n bytes into @p out. On any error @p out is left as it was.
 * Checks in order: size, magic, version, checksum, content (flags, finite
 * numbers, unit quaternions, a history ordered in time that ends at t_s,
 * entries past the history's count all zero bits).
 * The history is placed oldest first from ring index 0. Not reentrant (one
 * static scratch state).
 */
BlockError read_state_block(const std::uint8_t* data, std::uint32_t n, FilterState& out) noexcept;

/**
 * Reads and checks a block like read_state_block() but leaves the state in the
 * module's static scratch and returns it (nullptr on any error, @p err says
 * which): a caller that restores from it needs no 18 KiB FilterState on its
 * stack. The scratch serves every tile, so the state must be used before the
 * caller makes any kernel or board call (a switch to another tile), and is
 * overwritten by the next read.
 */
const FilterState* read_state_block_in_place(const std::uint8_t* data, std::uint32_t n, BlockError& err) noexcept;

}  // namespace trn::filter
