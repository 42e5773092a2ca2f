/**
 * @file filter_checkpoint.hpp
 * @brief The navigation filter's checkpoints in shared DDR: its whole state every few jobs, in
 *        two alternating slots, so a restarted or moved filter resumes instead of starting over.
 *
 * A slot is the filter's state block (trn/filter/state_block.hpp, with its own
 * checksum) under a header: magic, the checkpoint's sequence number, the last
 * IMU sample the state has integrated, and a CRC-32C over the header words.
 * A writer first clears the slot's magic, then writes the block, then the
 * header, alternating between the slots from the one after the checkpoint it
 * resumed from (so the good checkpoint it read is never the one overwritten):
 * a torn or upset slot fails its checks and the other one is used. The area is carved
 * once by name and found by any later start, on any tile.
 */
#pragma once

#include "bsp_tile64/api/work.hpp"
#include "trn/filter/filter_state.hpp"
#include "trn/filter/state_block.hpp"

#include <array>
#include <cstdint>

namespace trn::tasks {

inline constexpr std::uint32_t kCheckpointMagic = 0x434B5054U;  // "CKPT"

struct CheckpointSlot {
  std::uint32_t magic = 0U;
  std::uint32_t seq = 0U;      ///< checkpoint number, +1 per write (0: never written)
  std::uint32_t imu_seq = 0U;  ///< last IMU sample integrated into the state
  std::uint32_t crc = 0U;      ///< CRC-32C of magic, seq, imu_seq
  filter::StateBlock block{};
};

struct CheckpointArea {
  std::array<CheckpointSlot, 2> slot{};
};

/** The area in DDR (carved on first use, taken back after); nullptr if DDR is full. [task] */
CheckpointArea* checkpoint_area() noexcept;

/**
 * Writes @p s (which has integrated IMU sample @p imu_seq) as checkpoint @p seq
 * into slot @p slot (0 or 1; the writer alternates); charges @p work.
 */
void checkpoint_write(CheckpointArea& a, const filter::FilterState& s, std::uint32_t imu_seq, std::uint32_t seq,
                      std::uint32_t slot, bsp::Work& work) noexcept;

/** What checkpoint_read found. */
struct CheckpointRead {
  bool found = false;        ///< a good slot was read into the state
  std::uint32_t seq = 0U;
  std::uint32_t imu_seq = 0U;
  std::uint32_t slot = 0U;   ///< the slot read (when found)
  std::uint32_t bad = 0U;    ///< slots written (magic present) that failed a check
  std::uint32_t bad_slot = 0U;  ///< index of the last one
  /// When found: the state read, in the state block reader's static scratch (read_state_block_in_place():
  /// use it before any kernel or board call).
  const filter::FilterState* state = nullptr;
};

/** Finds the newest good checkpoint and leaves its state in the reader's scratch (no state on the stack). */
CheckpointRead checkpoint_read(const CheckpointArea& a, bsp::Work& work) noexcept;

}  // namespace trn::tasks
