/**
 * @file serialization_test.cpp
 * @brief The state block round-trips bit for bit, every corruption is rejected, and filters fed
 *        the same inputs (including one restored from a block) publish bit-identical outputs.
 */
#include "tests/trn/filter/truth_sim.hpp"
#include "trn/filter/byte_io.hpp"
#include "trn/filter/ekf.hpp"
#include "trn/filter/nav_output.hpp"
#include "trn/filter/state_block.hpp"

#include <gtest/gtest.h>

#include <array>
#include <cstring>
#include <limits>

namespace {

using trn::filter::BlockError;
using trn::filter::Ekf;
using trn::filter::FilterStatus;
using trn::filter::StateBlock;

Ekf g_a;
Ekf g_b;
Ekf g_c;
trn::filter::FilterState g_state;
StateBlock g_block1;
StateBlock g_block2;
std::array<trn::Match, 60> g_matches{};

/** Drives @p ekf (and the truth) for @p frames frames of 100 samples and 60 matches. */
void drive(filter_test::TruthSim& truth, bsp::Rng& rng, int frames, Ekf* const* filters, int n_filters) {
  const bsp::CameraModel cam{};
  for (int f = 0; f < frames; ++f) {
    for (int k = 0; k < 100; ++k) {
      const bsp::ImuSample s = truth.next_imu();
      const bool last = k == 99;
      if (last) {
        truth.make_matches(rng, cam, 60, 0.5, g_matches.data());
      }
      trn::filter::StepInput in{&s, last ? g_matches.data() : nullptr, last ? 60U : 0U};
      std::array<trn::filter::NavOutputBytes, 3> out{};
      for (int i = 0; i < n_filters; ++i) {
        trn::filter::UpdateReport rep;
        ASSERT_EQ(filters[i]->step(in, rep), FilterStatus::kOk);
        trn::filter::write_nav_output(trn::filter::make_nav_output(filters[i]->state(), filters[i]->config()),
                                      out[static_cast<std::size_t>(i)]);
        ASSERT_EQ(std::memcmp(out[0].data(), out[static_cast<std::size_t>(i)].data(), out[0].size()), 0)
            << "filter " << i << " frame " << f << " sample " << k;
      }
    }
  }
}

void start(Ekf& e, std::uint64_t seed) {
  filter_test::TruthSim truth(seed, true, trn::filter::FilterConfig{}.imu);
  bsp::Rng rng(seed, bsp::StreamId::kTest, 6);
  ASSERT_EQ(e.configure(trn::filter::FilterConfig{}, bsp::CameraModel{}), FilterStatus::kOk);
  ASSERT_EQ(e.init(filter_test::perturbed_estimate(truth, rng, 50.0, 0.5, 2e-3)), FilterStatus::kOk);
}

TEST(FilterSerialization, TwoFiltersFedTheSameInputsPublishIdenticalBytes) {
  constexpr std::uint64_t kSeed = 41;
  SCOPED_TRACE(testing::Message() << "seed " << kSeed);
  start(g_a, kSeed);
  start(g_b, kSeed);
  filter_test::TruthSim truth(kSeed, true, trn::filter::FilterConfig{}.imu);
  bsp::Rng rng(kSeed, bsp::StreamId::kTest, 7);
  Ekf* const filters[2] = {&g_a, &g_b};
  drive(truth, rng, 3, filters, 2);
  EXPECT_GT(g_a.state().c.accepted, 100U);
  ASSERT_EQ(trn::filter::write_state_block(g_a.state(), g_block1), BlockError::kOk);
  ASSERT_EQ(trn::filter::write_state_block(g_b.state(), g_block2), BlockError::kOk);
  EXPECT_EQ(g_block1, g_block2);
  const trn::filter::NavOutput o = trn::filter::make_nav_output(g_a.state(), g_a.config());
  EXPECT_EQ(o.flags & trn::filter::kNavValid, trn::filter::kNavValid);
}

TEST(FilterSerialization, RoundTripIsBitExactAndARestoredSpareStaysInStep) {
  constexpr std::uint64_t kSeed = 43;
  SCOPED_TRACE(testing::Message() << "seed " << kSeed);
  start(g_a, kSeed);
  filter_test::TruthSim truth(kSeed, true, trn::filter::FilterConfig{}.imu);
  bsp::Rng rng(kSeed, bsp::StreamId::kTest, 8);
  Ekf* const one[1] = {&g_a};
  drive(truth, rng, 2, one, 1);
  ASSERT_EQ(trn::filter::write_state_block(g_a.state(), g_block1), BlockError::kOk);
  ASSERT_EQ(trn::filter::read_state_block(g_block1.data(), trn::filter::kStateBlockBytes, g_state), BlockError::kOk);
  ASSERT_EQ(trn::filter::write_state_block(g_state, g_block2), BlockError::kOk);
  EXPECT_EQ(g_block1, g_block2);
  // A spare configured from the same table and given the block continues in lock step.
  ASSERT_EQ(g_c.configure(trn::filter::FilterConfig{}, bsp::CameraModel{}), FilterStatus::kOk);
  ASSERT_EQ(g_c.restore(g_state), FilterStatus::kOk);
  Ekf* const two[2] = {&g_a, &g_c};
  drive(truth, rng, 2, two, 2);
}

TEST(FilterSerialization, EverySingleBitFlipAndBadHeaderIsRejected) {
  start(g_a, 45);
  for (int k = 0; k < 50; ++k) {  // some history, so its entries are not all zero
    ASSERT_EQ(g_a.propagate(bsp::ImuSample{static_cast<std::uint32_t>(k), 0, 0.01 * (k + 1), {}, {}}),
              FilterStatus::kOk);
  }
  ASSERT_EQ(trn::filter::write_state_block(g_a.state(), g_block1), BlockError::kOk);
  g_state = trn::filter::FilterState{};
  // Every bit of everything before the history entries, of the first entry and of
  // the CRC; one bit of every other byte (all 147552 flips take 12 s: the CRC of
  // 18 KB per read; CRC-32 detects any single-bit error at any length anyway).
  constexpr std::uint32_t kExhaustive = 2056U + trn::filter::kHistoryEntryBytes;
  std::uint32_t flips = 0;
  for (std::uint32_t byte = 0; byte < trn::filter::kStateBlockBytes; ++byte) {
    const bool all = byte < kExhaustive || byte + 4U >= trn::filter::kStateBlockBytes;
    for (std::uint32_t bit = all ? 0U : byte % 8U; bit < (all ? 8U : byte % 8U + 1U); ++bit) {
      g_block2 = g_block1;
      g_block2[byte] ^= static_cast<std::uint8_t>(1U << bit);
      ASSERT_NE(trn::filter::read_state_block(g_block2.data(), trn::filter::kStateBlockBytes, g_state),
                BlockError::kOk)
          << "byte " << byte << " bit " << bit;
      ++flips;
    }
  }
  EXPECT_EQ(flips, 8U * (kExhaustive + 4U) + (trn::filter::kStateBlockBytes - kExhaustive - 4U));
  EXPECT_EQ(g_state.initialized, 0U);  // a refused block leaves the target as it was
  EXPECT_EQ(trn::filter::read_state_block(g_block1.data(), trn::filter::kStateBlockBytes - 1U, g_state),
            BlockError::kBadSize);
  EXPECT_EQ(trn::filter::read_state_block(nullptr, trn::filter::kStateBlockBytes, g_state), BlockError::kBadSize);
  g_block2 = g_block1;
  g_block2[0] ^= 0xFFU;
  EXPECT_EQ(trn::filter::read_state_block(g_block2.data(), trn::filter::kStateBlockBytes, g_state),
            BlockError::kBadMagic);
  for (const std::uint8_t version : {std::uint8_t{1U}, std::uint8_t{3U}}) {  // version 1 had no history
    g_block2 = g_block1;
    g_block2[4] = version;
    EXPECT_EQ(trn::filter::read_state_block(g_block2.data(), trn::filter::kStateBlockBytes, g_state),
              BlockError::kBadVersion);
  }
  g_block2 = g_block1;
  g_block2[100] ^= 0x10U;
  EXPECT_EQ(trn::filter::read_state_block(g_block2.data(), trn::filter::kStateBlockBytes, g_state),
            BlockError::kBadChecksum);
}

TEST(FilterSerialization, ARestoredSpareAppliesLaggedMatchesExactlyAsTheOriginal) {
  constexpr std::uint64_t kSeed = 44;
  SCOPED_TRACE(testing::Message() << "seed " << kSeed);
  start(g_a, kSeed);
  filter_test::TruthSim truth(kSeed, true, trn::filter::FilterConfig{}.imu);
  bsp::Rng rng(kSeed, bsp::StreamId::kTest, 18);
  Ekf* const one[1] = {&g_a};
  drive(truth, rng, 1, one, 1);
  // The image is taken; the spare is started from a block 0.4 s later, before the batch arrives.
  truth.make_matches(rng, bsp::CameraModel{}, 60, 0.5, g_matches.data());
  for (int k = 0; k < 40; ++k) {
    ASSERT_EQ(g_a.propagate(truth.next_imu()), FilterStatus::kOk);
  }
  ASSERT_EQ(trn::filter::write_state_block(g_a.state(), g_block1), BlockError::kOk);
  ASSERT_EQ(trn::filter::read_state_block(g_block1.data(), trn::filter::kStateBlockBytes, g_state), BlockError::kOk);
  ASSERT_EQ(g_c.configure(trn::filter::FilterConfig{}, bsp::CameraModel{}), FilterStatus::kOk);
  ASSERT_EQ(g_c.restore(g_state), FilterStatus::kOk);
  EXPECT_EQ(g_c.state().hist.count, 141U);
  for (int k = 0; k < 60; ++k) {  // batch applied 15 per period from 0.4 s to 0.43 s after the image
    const bsp::ImuSample s = truth.next_imu();
    const std::uint32_t first = 15U * static_cast<std::uint32_t>(k);
    const bool apply = k < 4;
    trn::filter::StepInput in{&s, apply ? g_matches.data() + first : nullptr, apply ? 15U : 0U};
    std::array<trn::filter::NavOutputBytes, 2> out{};
    Ekf* const pair[2] = {&g_a, &g_c};
    for (int i = 0; i < 2; ++i) {
      trn::filter::UpdateReport rep;
      ASSERT_EQ(pair[i]->step(in, rep), FilterStatus::kOk);
      if (apply) {
        EXPECT_EQ(rep.rejected_stale, 0U);
        EXPECT_GE(rep.accepted, 14U);
      }
      trn::filter::write_nav_output(trn::filter::make_nav_output(pair[i]->state(), pair[i]->config()),
                                    out[static_cast<std::size_t>(i)]);
    }
    ASSERT_EQ(out[0], out[1]) << "sample " << k;
  }
  ASSERT_EQ(trn::filter::write_state_block(g_a.state(), g_block1), BlockError::kOk);
  ASSERT_EQ(trn::filter::write_state_block(g_c.state(), g_block2), BlockError::kOk);
  EXPECT_EQ(g_block1, g_block2);
}

TEST(FilterSerialization, WellFormedBlockWithNonFiniteContentIsRejected) {
  start(g_a, 47);
  g_state = g_a.state();
  g_state.p(3, 3) = std::numeric_limits<double>::quiet_NaN();
  ASSERT_EQ(trn::filter::write_state_block(g_state, g_block1), BlockError::kOk);
  EXPECT_EQ(trn::filter::read_state_block(g_block1.data(), trn::filter::kStateBlockBytes, g_state),
            BlockError::kBadContent);
  EXPECT_EQ(g_a.restore(g_state), FilterStatus::kBadInput);
  g_state = g_a.state();
  g_state.initialized = 7U;
  ASSERT_EQ(trn::filter::write_state_block(g_state, g_block1), BlockError::kOk);
  EXPECT_EQ(trn::filter::read_state_block(g_block1.data(), trn::filter::kStateBlockBytes, g_state),
            BlockError::kBadContent);
  // A history out of time order, or one that does not end at the state's time.
  for (int k = 0; k < 3; ++k) {
    ASSERT_EQ(g_a.propagate(bsp::ImuSample{static_cast<std::uint32_t>(k), 0, 0.01 * (k + 1), {}, {}}),
              FilterStatus::kOk);
  }
  g_state = g_a.state();
  g_state.hist.e[1].t_s = 0.5;
  ASSERT_EQ(trn::filter::write_state_block(g_state, g_block1), BlockError::kOk);
  EXPECT_EQ(trn::filter::read_state_block(g_block1.data(), trn::filter::kStateBlockBytes, g_state),
            BlockError::kBadContent);
  EXPECT_EQ(g_a.restore(g_state), FilterStatus::kBadInput);
  g_state = g_a.state();
  g_state.t_s += 0.01;
  EXPECT_EQ(g_a.restore(g_state), FilterStatus::kBadInput);
  g_state = g_a.state();
  g_state.hist.e[2].q_wxyz[0] = 2.0;
  EXPECT_EQ(g_a.restore(g_state), FilterStatus::kBadInput);
  g_state = g_a.state();
  EXPECT_EQ(g_a.restore(g_state), FilterStatus::kOk);
}

// Found by tests/fuzz/state_block_fuzz.cpp: a block whose checksum is right but whose history
// entries past its count are not zero was taken, so two different blocks gave one state.
TEST(FilterSerialization, BlockWithAnUnusedHistoryEntryNotZeroIsRejected) {
  start(g_a, 48);
  for (int k = 0; k < 3; ++k) {
    ASSERT_EQ(g_a.propagate(bsp::ImuSample{static_cast<std::uint32_t>(k), 0, 0.01 * (k + 1), {}, {}}),
              FilterStatus::kOk);
  }
  ASSERT_LT(g_a.state().hist.count, 200U);
  ASSERT_EQ(trn::filter::write_state_block(g_a.state(), g_block1), BlockError::kOk);
  const std::uint32_t crc_at = trn::filter::kStateBlockBytes - 4U;
  const std::uint32_t entry200 = 2056U + 200U * trn::filter::kHistoryEntryBytes;
  for (const std::uint32_t at : {entry200, entry200 + 7U, crc_at - 1U}) {
    g_block2 = g_block1;
    g_block2[at] = 0x40U;
    const std::uint32_t crc = trn::filter::crc32(g_block2.data(), crc_at);
    for (std::uint32_t i = 0; i < 4U; ++i) {
      g_block2[crc_at + i] = static_cast<std::uint8_t>(crc >> (8U * i));
    }
    g_state = g_a.state();
    EXPECT_EQ(trn::filter::read_state_block(g_block2.data(), trn::filter::kStateBlockBytes, g_state),
              BlockError::kBadContent)
        << "byte " << at;
    EXPECT_EQ(g_state.t_s, g_a.state().t_s);
  }
  EXPECT_EQ(trn::filter::read_state_block(g_block1.data(), trn::filter::kStateBlockBytes, g_state), BlockError::kOk);
}

TEST(FilterSerialization, OutputBytesFollowTheDocumentedLayout) {
  start(g_a, 49);
  const trn::filter::NavOutput o = trn::filter::make_nav_output(g_a.state(), g_a.config());
  trn::filter::NavOutputBytes b{};
  trn::filter::write_nav_output(o, b);
  EXPECT_EQ(b[0], 0x54U);  // "TRNV" little-endian
  EXPECT_EQ(b[3], 0x56U);
  double x = 0.0;
  std::memcpy(&x, &b[24], sizeof x);
  EXPECT_EQ(x, o.p_m[0]);
  std::uint32_t flags = 0;
  std::memcpy(&flags, &b[224], sizeof flags);
  EXPECT_EQ(flags, o.flags);
  EXPECT_EQ(o.flags & trn::filter::kNavImuOk, 0U);  // nothing integrated yet
  EXPECT_EQ(o.flags & trn::filter::kNavValid, 0U);
  EXPECT_NE(o.flags & trn::filter::kNavInitialized, 0U);
  for (int i = 0; i < 3; ++i) {
    EXPECT_EQ(o.pos_var_world[i], o.var_diag[i]) << "a map taken as exact (the default) adds nothing";
  }
}

// The map's tie error is shared by every landmark, so no match shows it: the filter's covariance stays
// relative to the map and the solution adds the tie variance to the position it reports against the world.
TEST(FilterSerialization, TheWorldVarianceAddsTheMapTieToThePosition) {
  start(g_a, 49);
  trn::filter::FilterConfig cfg{};
  cfg.map_tie_sigma_m[0] = 0.34;
  cfg.map_tie_sigma_m[1] = 0.34;
  cfg.map_tie_sigma_m[2] = 0.23;
  ASSERT_EQ(trn::filter::check_config(cfg), trn::filter::ConfigError::kOk);
  const trn::filter::NavOutput o = trn::filter::make_nav_output(g_a.state(), cfg);
  for (int i = 0; i < 3; ++i) {
    EXPECT_EQ(o.pos_var_world[i], o.var_diag[i] + cfg.map_tie_sigma_m[i] * cfg.map_tie_sigma_m[i]) << i;
    EXPECT_EQ(o.var_diag[i], g_a.state().p(i, i)) << "the map-relative variance is the filter's own";
  }
  trn::filter::NavOutputBytes b{};
  trn::filter::write_nav_output(o, b);
  double z = 0.0;
  std::memcpy(&z, &b[256], sizeof z);
  EXPECT_EQ(z, o.pos_var_world[2]) << "offset 240 + 2 x 8 of the documented layout";
  std::uint32_t version = 0;
  std::memcpy(&version, &b[4], sizeof version);
  EXPECT_EQ(version, 2U);
  for (const double bad : {-0.1, std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::infinity()}) {
    trn::filter::FilterConfig c = cfg;
    c.map_tie_sigma_m[2] = bad;
    EXPECT_EQ(trn::filter::check_config(c), trn::filter::ConfigError::kBadLimit) << bad;
  }
}

// The records' CRC-32 takes four bytes at a time and the last one to three singly: the standard check
// value, at compile time too, and every length and start within a word against the bit-by-bit definition.
constexpr std::array<std::uint8_t, 9> kCheckBytes = {'1', '2', '3', '4', '5', '6', '7', '8', '9'};
static_assert(trn::filter::crc32(kCheckBytes.data(), 9U) == 0xCBF43926U);

TEST(FilterSerialization, TheRecordCrcIsCrc32AtEveryLength) {
  const auto reference = [](const std::uint8_t* d, std::uint32_t n) {
    std::uint32_t c = 0xFFFFFFFFU;
    for (std::uint32_t i = 0; i < n; ++i) {
      c ^= d[i];
      for (int k = 0; k < 8; ++k) {
        c = (c & 1U) != 0U ? (c >> 1U) ^ 0xEDB88320U : c >> 1U;
      }
    }
    return ~c;
  };
  std::array<std::uint8_t, 160> buf{};
  std::uint32_t x = 0x12345678U;
  for (auto& b : buf) {
    x = x * 1664525U + 1013904223U;
    b = static_cast<std::uint8_t>(x >> 24U);
  }
  for (std::uint32_t start = 0; start < 4U; ++start) {
    for (std::uint32_t n = 0; n + start <= buf.size(); ++n) {
      ASSERT_EQ(trn::filter::crc32(buf.data() + start, n), reference(buf.data() + start, n))
          << "start " << start << " n " << n;
    }
  }
}

}  // namespace
