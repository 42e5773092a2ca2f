/**
 * @file filter_checkpoint.hpp
 * @brief The navigation filter's checkpoints in shared DDR: its whole state every few jobs, in
 *        two alternating slots, so a restarted or moved filter resumes instead of starting over.
 *
 * A slot is the filter's state block (trn/filter/state_block.hpp, with its own
 * checksum) under a header: magic, the checkpoint's sequence number, the last
 * IMU sample the state has integrated, the digest of the writer's whole state
 * when a TMR replica wrote it (core_digest: what its output for that job
 * carried to the vote; 0 from a simplex filter), and a CRC-32C over the header
 * words. A filter whose TMR lost its majority goes on alone from a checkpoint
 * whose digest the vote agreed on (VotedCheckpoint), never from one only its
 * writer vouches for.
 * A writer first clears the slot's magic, then writes the block, then the
 * header, alternating between the slots from the one after the checkpoint it
 * resumed from (so the good checkpoint it read is never the one overwritten):
 * a torn or upset slot fails its checks and the other one is used. The area is carved
 * once by name and found by any later start, on any tile.
 */
#pragma once

#include "bsp_tile64/api/memory.hpp"
#include "bsp_tile64/api/work.hpp"
#include "trn/filter/filter_state.hpp"
#include "trn/filter/state_block.hpp"

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>

namespace trn::tasks {

inline constexpr std::uint32_t kCheckpointMagic = 0x434B5054U;  // "CKPT"

struct CheckpointSlot {
  std::uint32_t magic = 0U;
  std::uint32_t seq = 0U;      ///< checkpoint number, +1 per write (0: never written)
  std::uint32_t imu_seq = 0U;  ///< last IMU sample integrated into the state
  std::uint32_t digest = 0U;   ///< the writer's state digest after the checkpoint's job (0: not a replica's)
  std::uint32_t crc = 0U;      ///< CRC-32C of magic, seq, imu_seq, digest
  filter::StateBlock block{};
};

struct CheckpointArea {
  std::array<CheckpointSlot, 2> slot{};
};

/** The area in DDR (carved on first use, taken back after); nullptr if DDR is full. [task] */
CheckpointArea* checkpoint_area() noexcept;

/**
 * Writes @p s (which has integrated IMU sample @p imu_seq) as checkpoint @p seq
 * into slot @p slot (0 or 1; the writer alternates), with the writer's state
 * digest @p digest (0: none); charges @p work.
 */
void checkpoint_write(CheckpointArea& a, const filter::FilterState& s, std::uint32_t imu_seq, std::uint32_t seq,
                      std::uint32_t slot, bsp::Work& work, std::uint32_t digest = 0U) noexcept;

/** A checkpoint the TMR vote confirmed: its number and the voted state digest of its job (seq 0: none). */
struct VotedCheckpoint {
  std::uint32_t seq = 0U;
  std::uint32_t digest = 0U;
};
inline constexpr std::array kVotedCheckpointFields{BSP_CONTROL_STATE(VotedCheckpoint, seq),
                                                   BSP_CONTROL_STATE(VotedCheckpoint, digest)};
inline constexpr bsp::ControlLayout kVotedCheckpointLayout{kVotedCheckpointFields, sizeof(VotedCheckpoint),
                                                           alignof(VotedCheckpoint)};
static_assert(bsp::control_layout_ok(kVotedCheckpointLayout), "every member of VotedCheckpoint");

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

/**
 * Finds the newest good checkpoint and leaves its state in the reader's scratch (no state on the
 * stack). With @p voted not empty, only a checkpoint whose number and digest are one of them will do.
 */
CheckpointRead checkpoint_read(const CheckpointArea& a, bsp::Work& work,
                               std::span<const VotedCheckpoint> voted = {}) noexcept;

}  // namespace trn::tasks
