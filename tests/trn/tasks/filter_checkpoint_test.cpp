/**
 * @file filter_checkpoint_test.cpp
 * @brief The filter's DDR checkpoints (alternating slots, torn or upset slots refused, the older
 *        one used) and the I/O tile's IMU record (wrap, overwritten and future samples told apart).
 */
#include "trn/tasks/filter/filter_checkpoint.hpp"

#include "bsp_tile64/api/memory.hpp"
#include "tests/trn/filter/truth_sim.hpp"
#include "trn/filter/ekf.hpp"
#include "trn/tasks/io/imu_ring.hpp"

#include <gtest/gtest.h>

#include <cstring>

namespace {

using trn::filter::Ekf;
using trn::filter::FilterStatus;
using trn::tasks::CheckpointArea;
using trn::tasks::CheckpointRead;

Ekf g_ekf;

class FilterCheckpoint : public ::testing::Test {
 protected:
  void SetUp() override {
    ASSERT_EQ(bsp::region_reset(bsp::Region{bsp::Region::kDdr}), bsp::MemError::kOk);
    filter_test::TruthSim truth(5, true, trn::filter::FilterConfig{}.imu);
    bsp::Rng rng(5, bsp::StreamId::kTest, 3);
    ASSERT_EQ(g_ekf.configure(trn::filter::FilterConfig{}, bsp::CameraModel{}), FilterStatus::kOk);
    ASSERT_EQ(g_ekf.init(filter_test::perturbed_estimate(truth, rng, 50.0, 0.5, 2e-3)), FilterStatus::kOk);
    truth_ = truth;
  }

  /** Propagates the filter by @p n samples. */
  void advance(int n) {
    for (int i = 0; i < n; ++i) {
      const bsp::ImuSample s = truth_.next_imu();
      trn::filter::UpdateReport rep{};
      ASSERT_EQ(g_ekf.step(trn::filter::StepInput{&s, nullptr, 0}, rep), FilterStatus::kOk);
    }
  }

  filter_test::TruthSim truth_{5, true, trn::filter::FilterConfig{}.imu};
};

TEST_F(FilterCheckpoint, NoCheckpointIsFoundInAFreshArea) {
  CheckpointArea* a = trn::tasks::checkpoint_area();
  ASSERT_NE(a, nullptr);
  bsp::Work w{};
  const CheckpointRead r = trn::tasks::checkpoint_read(*a, w);
  EXPECT_FALSE(r.found);
  EXPECT_EQ(r.bad, 0U);
  EXPECT_EQ(trn::tasks::checkpoint_area(), a) << "a later start finds the same area by name";
}

TEST_F(FilterCheckpoint, TheNewestGoodSlotIsReadAndAnUpsetOneIsRefused) {
  CheckpointArea* a = trn::tasks::checkpoint_area();
  ASSERT_NE(a, nullptr);
  bsp::Work w{};
  advance(10);
  trn::tasks::checkpoint_write(*a, g_ekf.state(), 9U, 1U, 0U, w);
  const double t1 = g_ekf.state().t_s;
  advance(10);
  trn::tasks::checkpoint_write(*a, g_ekf.state(), 19U, 2U, 1U, w);
  const double t2 = g_ekf.state().t_s;
  EXPECT_GT(w.mem_words, 0U) << "the copies are charged";
  EXPECT_EQ(a->slot[0].seq, 1U);
  EXPECT_EQ(a->slot[1].seq, 2U) << "the slots alternate";
  CheckpointRead r = trn::tasks::checkpoint_read(*a, w);
  ASSERT_TRUE(r.found);
  EXPECT_EQ(r.seq, 2U);
  EXPECT_EQ(r.imu_seq, 19U);
  ASSERT_NE(r.state, nullptr);
  EXPECT_EQ(r.state->t_s, t2);
  // An upset in the newest block: refused by its checksum, the older slot is used.
  a->slot[1].block[100] ^= 0x10U;
  r = trn::tasks::checkpoint_read(*a, w);
  ASSERT_TRUE(r.found);
  EXPECT_EQ(r.seq, 1U);
  EXPECT_EQ(r.imu_seq, 9U);
  EXPECT_EQ(r.bad, 1U);
  EXPECT_EQ(r.bad_slot, 1U);
  ASSERT_NE(r.state, nullptr);
  EXPECT_EQ(r.state->t_s, t1);
  // A filter resumed from slot 0 writes its next checkpoint into the other one.
  ASSERT_EQ(r.slot, 0U);
  advance(10);
  trn::tasks::checkpoint_write(*a, g_ekf.state(), 29U, 3U, 1U - r.slot, w);
  EXPECT_EQ(a->slot[1].seq, 3U);
  EXPECT_EQ(a->slot[0].seq, 1U);
  // A torn write (the header's magic cleared first, the rest not done) is refused as well.
  a->slot[1].magic = 0U;
  r = trn::tasks::checkpoint_read(*a, w);
  ASSERT_TRUE(r.found);
  EXPECT_EQ(r.seq, 1U);
  EXPECT_EQ(r.bad, 1U);
  // A header upset (sequence number) is caught by the header CRC.
  a->slot[0].seq ^= 4U;
  r = trn::tasks::checkpoint_read(*a, w);
  EXPECT_FALSE(r.found);
  EXPECT_EQ(r.bad, 2U);
}

// The read leaves the state in the block reader's scratch (the filter task's set-up holds no 18 KiB state
// on its stack): the state found writes back to the slot's bytes, and a refused slot gives no state.
TEST_F(FilterCheckpoint, TheStateReadInPlaceIsTheSlotsState) {
  CheckpointArea* a = trn::tasks::checkpoint_area();
  ASSERT_NE(a, nullptr);
  bsp::Work w{};
  advance(10);
  trn::tasks::checkpoint_write(*a, g_ekf.state(), 9U, 1U, 0U, w);
  advance(10);
  trn::tasks::checkpoint_write(*a, g_ekf.state(), 19U, 2U, 1U, w);
  const CheckpointRead r = trn::tasks::checkpoint_read(*a, w);
  ASSERT_TRUE(r.found);
  ASSERT_NE(r.state, nullptr);
  EXPECT_EQ(r.seq, 2U);
  EXPECT_EQ(r.state->t_s, g_ekf.state().t_s);
  trn::filter::StateBlock again{};
  ASSERT_EQ(trn::filter::write_state_block(*r.state, again), trn::filter::BlockError::kOk);
  EXPECT_EQ(again, a->slot[1].block) << "the state read writes back to the same bytes";
  a->slot[0].seq ^= 4U;  // header upset
  a->slot[1].block[100] ^= 0x10U;  // block upset
  const CheckpointRead none = trn::tasks::checkpoint_read(*a, w);
  EXPECT_FALSE(none.found);
  EXPECT_EQ(none.state, nullptr);
  EXPECT_EQ(none.bad, 2U);
  trn::filter::BlockError e = trn::filter::BlockError::kOk;
  EXPECT_EQ(trn::filter::read_state_block_in_place(a->slot[1].block.data(), trn::filter::kStateBlockBytes, e), nullptr);
  EXPECT_EQ(e, trn::filter::BlockError::kBadChecksum);
  EXPECT_EQ(trn::filter::read_state_block_in_place(a->slot[1].block.data(), 7U, e), nullptr);
  EXPECT_EQ(e, trn::filter::BlockError::kBadSize);
}

TEST(ImuRing, SamplesAreFoundUntilOverwritten) {
  ASSERT_EQ(bsp::region_reset(bsp::Region{bsp::Region::kDdr}), bsp::MemError::kOk);
  trn::tasks::ImuRing* r = trn::tasks::imu_ring();
  ASSERT_NE(r, nullptr);
  bsp::ImuSample s{};
  EXPECT_EQ(trn::tasks::imu_ring_get(*r, 0U, s), trn::tasks::RingRead::kNotYet);
  for (std::uint32_t i = 0; i < trn::tasks::kImuRingLen + 10U; ++i) {
    bsp::ImuSample in{};
    in.seq = i;
    in.t_s = 0.01 * i;
    trn::tasks::imu_ring_put(*r, in);
  }
  ASSERT_EQ(trn::tasks::imu_ring_get(*r, trn::tasks::kImuRingLen + 9U, s), trn::tasks::RingRead::kOk);
  EXPECT_EQ(s.seq, trn::tasks::kImuRingLen + 9U);
  EXPECT_EQ(trn::tasks::imu_ring_get(*r, 10U, s), trn::tasks::RingRead::kOk);
  EXPECT_EQ(s.seq, 10U);
  EXPECT_EQ(trn::tasks::imu_ring_get(*r, 9U, s), trn::tasks::RingRead::kGone) << "overwritten by sample 9 + length";
  EXPECT_EQ(trn::tasks::imu_ring_oldest(*r), 10U);
  EXPECT_EQ(trn::tasks::imu_ring_get(*r, trn::tasks::kImuRingLen + 10U, s), trn::tasks::RingRead::kNotYet);
  EXPECT_EQ(trn::tasks::imu_ring(), r) << "a restarted I/O task takes the same record back";
}

}  // namespace
