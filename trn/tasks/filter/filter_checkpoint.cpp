/**
 * @file filter_checkpoint.cpp
 * @brief The filter's DDR checkpoints (see filter_checkpoint.hpp).
 */
#include "trn/tasks/filter/filter_checkpoint.hpp"

#include "trn/tasks/vision/vision_shared.hpp"
#include "udn/crc32c.hpp"

namespace trn::tasks {
namespace {

std::uint32_t header_crc(const CheckpointSlot& s) noexcept {
  const std::array<std::uint32_t, 4> w{s.magic, s.seq, s.imu_seq, s.digest};
  return udn::crc32c_words(w);
}

bool header_ok(const CheckpointSlot& s) noexcept {
  return s.magic == kCheckpointMagic && s.seq != 0U && s.crc == header_crc(s);
}

/** True if @p voted is empty or names slot @p s's number and digest. */
bool vouched(const CheckpointSlot& s, std::span<const VotedCheckpoint> voted) noexcept {
  if (voted.empty()) {
    return true;
  }
  for (const VotedCheckpoint& v : voted) {
    if (v.seq != 0U && v.seq == s.seq && v.digest == s.digest) {
      return true;
    }
  }
  return false;
}

/** Copying and checking a block: a load and a store per word, the CRC's few operations per byte. */
bsp::Work block_work() noexcept {
  bsp::Work w{};
  w.mem_words = 2ULL * filter::kStateBlockBytes / 4U;
  w.int_ops = 4ULL * filter::kStateBlockBytes;
  return w;
}

}  // namespace

CheckpointArea* checkpoint_area() noexcept {
  return reinterpret_cast<CheckpointArea*>(  // NOLINT(cppcoreguidelines-pro-type-reinterpret-cast): carve bytes
      ddr_carve_named("filter_ckpt", sizeof(CheckpointArea), alignof(CheckpointArea)));
}

void checkpoint_write(CheckpointArea& a, const filter::FilterState& s, std::uint32_t imu_seq, std::uint32_t seq,
                      std::uint32_t slot_index, bsp::Work& work, std::uint32_t digest) noexcept {
  CheckpointSlot& slot = a.slot[slot_index % a.slot.size()];
  slot.magic = 0U;
  (void)filter::write_state_block(s, slot.block);
  slot.seq = seq;
  slot.imu_seq = imu_seq;
  slot.digest = digest;
  slot.magic = kCheckpointMagic;
  slot.crc = header_crc(slot);
  const bsp::Work w = block_work();
  work.mem_words += w.mem_words;
  work.int_ops += w.int_ops;
}

CheckpointRead checkpoint_read(const CheckpointArea& a, bsp::Work& work,
                               std::span<const VotedCheckpoint> voted) noexcept {
  CheckpointRead r{};
  // Newest first: slot order by sequence number.
  const bool first_is_1 = a.slot[1].seq > a.slot[0].seq;
  for (std::uint32_t k = 0; k < 2U && !r.found; ++k) {
    const std::uint32_t i = first_is_1 ? 1U - k : k;
    const CheckpointSlot& s = a.slot[i];
    if ((s.magic == 0U && s.seq == 0U) || (header_ok(s) && !vouched(s, voted))) {
      continue;  // never written, or not one the vote confirmed
    }
    const bsp::Work w = block_work();
    work.mem_words += w.mem_words;
    work.int_ops += w.int_ops;
    filter::BlockError e = filter::BlockError::kOk;
    const filter::FilterState* st =
        header_ok(s) ? filter::read_state_block_in_place(s.block.data(), filter::kStateBlockBytes, e) : nullptr;
    if (st == nullptr) {
      ++r.bad;
      r.bad_slot = i;
      continue;
    }
    r.found = true;
    r.state = st;
    r.slot = i;
    r.seq = s.seq;
    r.imu_seq = s.imu_seq;
  }
  return r;
}

}  // namespace trn::tasks
