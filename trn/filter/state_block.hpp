/**
 * @file state_block.hpp
 * @brief The filter state as a fixed-size, versioned, checksummed byte block (TMR state transfer).
 *
 * Layout, little-endian, no padding (offsets in bytes):
 *    0 u32 magic 0x464E5254 ("TRNF")   4 u32 version (1)
 *    8 u32 block size (2020)           12 u32 reserved, 0
 *   16 u32 initialized (0/1)           20 u32 last_imu_ok (0/1)
 *   24 f64 t_s                         32 f64 t_last_update_s
 *   40 u64 propagations                48 10 x u32 counters (FilterCounters order)
 *   88 16 x f64 nominal: p[3] v[3] q(w,x,y,z) b_g[3] b_a[3]
 *  216 225 x f64 covariance, row-major
 * 2016 u32 CRC-32 of bytes [0, 2016)
 */
#pragma once

#include "trn/filter/filter_state.hpp"

#include <array>
#include <cstdint>

namespace trn::filter {

inline constexpr std::uint32_t kStateMagic = 0x464E5254U;
inline constexpr std::uint32_t kStateVersion = 1U;
inline constexpr std::uint32_t kStateBlockBytes = 16U + 8U + 16U + 8U + 40U + 128U + 1800U + 4U;

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
 * Checks in order: size, magic, version, checksum, content.
 */
BlockError read_state_block(const std::uint8_t* data, std::uint32_t n, FilterState& out) noexcept;

}  // namespace trn::filter
