/**
 * @file filter_tmr_test.cpp
 * @brief The voter's place in the stream and its held matches in DDR: what a restarted voter goes
 *        on from is refused when torn, upset or never written.
 */
#include "trn/tasks/filter/filter_tmr.hpp"

#include <gtest/gtest.h>

#include <memory>

namespace {

using trn::tasks::TmrVoter;
using trn::tasks::TmrHeldMatches;

TmrVoter sample_voter() {
  TmrVoter f{};
  f.serial = 7U;
  f.epoch = 2U;
  f.voting = 1U;
  f.record_job = 1799U;
  f.next_vote = 1798U;
  f.next_deliver = 1798U;
  f.delivered_any = 1U;
  f.outputs_delivered = 1798U;
  f.output_crc = 0xDEADBEEFU;
  f.last_imu = 1797U;
  f.have_imu = 1U;
  f.cmd_held = 1U;
  f.cmd = {1U, 2U, 3U, 4U, 5U};
  f.active_mask = 7U;
  f.held_serial = 3U;
  trn::tasks::tmr_voter_seal(f);
  return f;
}

TEST(TmrVoterPlace, ASealedPlaceChecksAndEveryFieldIsCovered) {
  const TmrVoter f = sample_voter();
  EXPECT_TRUE(trn::tasks::tmr_voter_ok(f));
  // Every word of the place counts: a flip anywhere in it is refused.
  constexpr std::size_t kWords = sizeof(TmrVoter) / sizeof(std::uint32_t) - 1U;  // all but the CRC
  for (std::size_t w = 0; w < kWords; ++w) {
    TmrVoter g = f;
    reinterpret_cast<std::uint32_t*>(&g)[w] ^= 0x10U;
    EXPECT_FALSE(trn::tasks::tmr_voter_ok(g)) << "word " << w;
  }
}

TEST(TmrVoterPlace, APlaceNeverWrittenOrTornIsRefused) {
  EXPECT_FALSE(trn::tasks::tmr_voter_ok(TmrVoter{})) << "serial 0: never written";
  TmrVoter f = sample_voter();
  f.crc = ~f.crc;  // what the voter leaves while it writes
  EXPECT_FALSE(trn::tasks::tmr_voter_ok(f));
}

TEST(TmrHeldMatches, HeldMatchesCheckAndAFlipInAHeldWordIsRefused) {
  auto h = std::make_unique<TmrHeldMatches>();
  h->serial = 4U;
  h->count = 12U;
  for (std::uint32_t i = 0; i < h->count; ++i) {
    h->job[i] = 615U;
    for (std::uint32_t k = 0; k < trn::tasks::kMatchWords; ++k) {
      h->words[std::size_t{i} * trn::tasks::kMatchWords + k] = i * 100U + k;
    }
  }
  bsp::Work work{};
  trn::tasks::tmr_held_seal(*h, work);
  EXPECT_TRUE(trn::tasks::tmr_held_ok(*h, work));
  EXPECT_GT(work.mem_words, 2U * 12U * trn::tasks::kMatchWords) << "sealing and checking are charged";
  h->words[5U * trn::tasks::kMatchWords + 3U] ^= 1U;
  EXPECT_FALSE(trn::tasks::tmr_held_ok(*h, work));
  h->words[5U * trn::tasks::kMatchWords + 3U] ^= 1U;
  h->job[11] = 616U;
  EXPECT_FALSE(trn::tasks::tmr_held_ok(*h, work));
  h->job[11] = 615U;
  h->count = trn::tasks::kHeldMatches + 1U;
  EXPECT_FALSE(trn::tasks::tmr_held_ok(*h, work)) << "a count past the area is refused, never read";
}

}  // namespace
