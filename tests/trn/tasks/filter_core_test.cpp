/**
 * @file filter_core_test.cpp
 * @brief The filter as a step function of job records: a core saved after a job and loaded
 *        elsewhere (a TMR seed) runs the next records to the same bits as the original,
 *        match queue wrap included; damaged or out-of-range saves are refused.
 */
#include "trn/filter/filter_core.hpp"

#include "bsp_tile64/api/memory.hpp"
#include "bsp_tile64/emu/rng.hpp"
#include "tests/trn/filter/truth_sim.hpp"

#include <gtest/gtest.h>

#include <bit>
#include <cstdint>
#include <vector>

namespace {

using trn::tasks::CoreImage;
using trn::tasks::FilterCore;
using trn::tasks::JobRecord;

constexpr bsp::TileId kTileA = 40;
constexpr bsp::TileId kTileB = 41;
constexpr std::uint32_t kMatchesEvery = 3;  ///< jobs between two match batches
constexpr std::uint32_t kBatch = 60;        ///< matches per batch: more than a job applies, so the queue fills and wraps
constexpr std::uint32_t kLagJobs = 30;      ///< a batch arrives this many jobs after its image (0.3 s, as in flight)

/** A true pose the filter went through. */
struct Pose {
  double t_s;
  Eigen::Vector3d p;
  Eigen::Quaterniond q;
};

/** Matches of ground points under a past true pose, seen from it (bearings in the camera frame). */
void add_matches(JobRecord& r, const Pose& truth, const bsp::CameraModel& cam, std::uint32_t frame, bsp::Rng& rng) {
  Eigen::Matrix3d r_bc;
  for (int i = 0; i < 9; ++i) {
    r_bc(i / 3, i % 3) = cam.r_bc[i];
  }
  for (std::uint32_t k = 0; k < kBatch; ++k) {
    trn::Match m{};
    const Eigen::Vector3d p_l{truth.p.x() + rng.normal(0.0, 300.0), truth.p.y() + rng.normal(0.0, 300.0), 0.0};  // braces: draws in order
    const Eigen::Vector3d d_m = (p_l - truth.p).normalized();
    const Eigen::Vector3d w_c = r_bc.transpose() * (truth.q.conjugate() * d_m);
    for (int i = 0; i < 3; ++i) {
      m.w_c[i] = w_c(i);
      m.p_m[i] = p_l(i);
    }
    m.u_px = 512.0;
    m.v_px = 512.0;
    m.sigma_px = 0.5;
    m.quality = 0.9F;
    m.landmark = static_cast<std::uint16_t>(k);
    m.tile = 24;
    m.frame = frame;
    m.t_s = truth.t_s;
    std::array<std::uint32_t, trn::tasks::kMatchWords> w{};
    (void)fdir::msg::encode(trn::tasks::kMatchRecord, m, w);
    ASSERT_TRUE(trn::tasks::record_add_match(r, w));
  }
}

class FilterCore2 : public ::testing::Test {
 protected:
  void SetUp() override {
    ASSERT_EQ(bsp::region_reset(bsp::Region{kTileA}), bsp::MemError::kOk);
    ASSERT_EQ(bsp::region_reset(bsp::Region{kTileB}), bsp::MemError::kOk);
    cfg_.matches_per_job = 15U;
    ASSERT_TRUE(trn::tasks::core_set_up(a_, cfg_, bsp::Region{kTileA}));
    ASSERT_TRUE(trn::tasks::core_set_up(b_, cfg_, bsp::Region{kTileB}));
    bsp::Rng rng(5, bsp::StreamId::kTest, 1);
    cfg_.initial = filter_test::perturbed_estimate(truth_, rng, 20.0, 0.2, 1e-3);
    ASSERT_EQ(a_.ekf->init(cfg_.initial), trn::filter::FilterStatus::kOk);
  }

  /**
   * The records of @p n jobs from @p first: one IMU sample each and, every
   * kMatchesEvery jobs, a batch of matches of the image taken kLagJobs earlier.
   */
  std::vector<JobRecord> records(std::uint32_t first, std::uint32_t n) {
    std::vector<JobRecord> v(n);
    bsp::Rng rng(7, bsp::StreamId::kTest, first);
    for (std::uint32_t j = 0; j < n; ++j) {
      const std::uint32_t job = first + j;
      trn::tasks::record_begin(v[j], job);
      EXPECT_TRUE(trn::tasks::record_add_imu(v[j], truth_.next_imu()));
      poses_.push_back(Pose{truth_.t(), truth_.p(), truth_.q()});
      if (job % kMatchesEvery == 0U && job >= kLagJobs) {
        add_matches(v[j], poses_[job - kLagJobs], cfg_.camera, job - kLagJobs, rng);
      }
      bsp::Work w{};
      trn::tasks::record_seal(v[j], w);
    }
    return v;
  }

  std::uint32_t digest(FilterCore& c) {
    bsp::Work w{};
    return trn::tasks::core_digest(c, w);
  }

  filter_test::TruthSim truth_{5, true, trn::filter::FilterConfig{}.imu};
  std::vector<Pose> poses_;  ///< by job
  trn::tasks::FilterTaskConfig cfg_{};
  FilterCore a_{};
  FilterCore b_{};
  CoreImage image_{};
};

TEST_F(FilterCore2, ASavedCoreLoadedElsewhereRunsTheNextRecordsToTheSameBits) {
  for (const JobRecord& r : records(0, 70)) {
    trn::tasks::core_run(a_, r);
  }
  ASSERT_GT(a_.queue->count, 0U) << "the save carries queued matches";
  bsp::Work w{};
  trn::tasks::core_save(a_, image_, w);
  ASSERT_TRUE(trn::tasks::core_load(b_, image_, w));
  EXPECT_EQ(b_.queue->head, a_.queue->head) << "the ring position is state: the wrap splits a job's updates";
  EXPECT_EQ(digest(b_), digest(a_));
  bool wrapped = false;
  for (const JobRecord& r : records(70, 150)) {
    const std::uint32_t head_before = a_.queue->head;
    trn::tasks::core_run(a_, r);
    trn::tasks::core_run(b_, r);
    wrapped = wrapped || a_.queue->head < head_before;
    ASSERT_EQ(digest(b_), digest(a_)) << "job " << trn::tasks::record_job(r);
    trn::filter::NavOutputBytes oa{};
    trn::filter::NavOutputBytes ob{};
    trn::filter::write_nav_output(trn::tasks::core_output(a_), oa);
    trn::filter::write_nav_output(trn::tasks::core_output(b_), ob);
    ASSERT_EQ(oa, ob) << "job " << trn::tasks::record_job(r);
  }
  EXPECT_TRUE(wrapped) << "the queue's ring wrapped after the load";
  EXPECT_GT(a_.stats->matches_applied, 100U);
}

TEST_F(FilterCore2, TheDigestSeesTheQueueAndItsRingPosition) {
  for (const JobRecord& r : records(0, 40)) {
    trn::tasks::core_run(a_, r);
  }
  ASSERT_GT(a_.queue->count, 0U);
  const std::uint32_t d = digest(a_);
  a_.queue->m[a_.queue->head].u_px += 1.0;
  EXPECT_NE(digest(a_), d) << "a queued match";
  a_.queue->m[a_.queue->head].u_px -= 1.0;
  ASSERT_EQ(digest(a_), d);
  const trn::tasks::MatchQueue saved = *a_.queue;
  // The same matches one place further round the ring.
  for (std::uint32_t i = 0; i < saved.count; ++i) {
    a_.queue->m[(saved.head + 1U + i) % trn::tasks::kMatchQueueLen] = saved.m[(saved.head + i) % trn::tasks::kMatchQueueLen];
  }
  a_.queue->head = (saved.head + 1U) % trn::tasks::kMatchQueueLen;
  EXPECT_NE(digest(a_), d) << "the ring position";
}

TEST_F(FilterCore2, ASaveOutOfRangeIsRefused) {
  for (const JobRecord& r : records(0, 40)) {
    trn::tasks::core_run(a_, r);
  }
  bsp::Work w{};
  trn::tasks::core_save(a_, image_, w);
  CoreImage bad = image_;
  bad.queue[0] = trn::tasks::kMatchQueueLen;  // head
  EXPECT_FALSE(trn::tasks::core_load(b_, bad, w));
  bad = image_;
  bad.queue[1] = trn::tasks::kMatchQueueLen + 1U;  // count
  EXPECT_FALSE(trn::tasks::core_load(b_, bad, w));
  bad = image_;
  bad.block[40] ^= 0x10U;  // the state block's own CRC refuses it
  EXPECT_FALSE(trn::tasks::core_load(b_, bad, w));
  EXPECT_TRUE(trn::tasks::core_load(b_, image_, w));
}

// FDIR-FS-04 (unit): one flipped bit in any part of the EKF's settings is named by its part; built
// again, the settings are what they were and the state is kept: the core then runs the next records
// to the same bits as a copy that was never upset.
TEST_F(FilterCore2, AChangedPartOfTheSettingsIsNamedAndBuiltAgainWithTheStateKept) {
  for (const JobRecord& r : records(0, 40)) {
    trn::tasks::core_run(a_, r);
  }
  bsp::Work w{};
  EXPECT_EQ(trn::tasks::core_settings_changed(a_, w), 0U);
  EXPECT_GT(w.int_ops, 0U) << "the check is charged";
  trn::tasks::core_save(a_, image_, w);
  ASSERT_TRUE(trn::tasks::core_load(b_, image_, w));
  // The test plays the upset: a bit of each part in turn, in the EKF's RAM.
  auto* config = const_cast<trn::filter::FilterConfig*>(&a_.ekf->config());  // NOLINT(cppcoreguidelines-pro-type-const-cast)
  auto* camera = const_cast<trn::filter::CameraGeometry*>(&a_.ekf->camera());  // NOLINT(cppcoreguidelines-pro-type-const-cast)
  auto* noise = const_cast<trn::filter::Vec15*>(&a_.ekf->process_noise());  // NOLINT(cppcoreguidelines-pro-type-const-cast)
  // The settings are the first kEkfSettingsBytes of the EKF's carve (the join credits upsets there).
  const auto* base = static_cast<const unsigned char*>(static_cast<const void*>(a_.ekf));
  EXPECT_EQ(static_cast<const void*>(config), static_cast<const void*>(base));
  EXPECT_EQ(static_cast<const void*>(noise->data() + noise->size()),
            static_cast<const void*>(base + trn::tasks::kEkfSettingsBytes));
  const std::uint32_t before = digest(a_);
  const struct {
    double* value;
    unsigned bit;
    std::uint32_t part;
  } hits[] = {{&config->gate_chi2, 26U, trn::tasks::kSettingsConfig},
              {&camera->fy_px, 62U, trn::tasks::kSettingsCamera},
              {noise->data() + 14, 2U, trn::tasks::kSettingsProcessNoise}};
  for (const auto& h : hits) {
    *h.value = std::bit_cast<double>(std::bit_cast<std::uint64_t>(*h.value) ^ (std::uint64_t{1} << h.bit));
    EXPECT_EQ(trn::tasks::core_settings_changed(a_, w), h.part);
    ASSERT_TRUE(trn::tasks::core_reload_settings(a_, w));
    EXPECT_EQ(trn::tasks::core_settings_changed(a_, w), 0U) << "built again from the task's configuration";
    EXPECT_EQ(digest(a_), before) << "the state is kept";
  }
  for (const JobRecord& r : records(40, 40)) {
    trn::tasks::core_run(a_, r);
    trn::tasks::core_run(b_, r);
    ASSERT_EQ(digest(a_), digest(b_)) << "job " << trn::tasks::record_job(r);
  }
  // A digest taken when the settings were built that no longer matches (the digest itself upset) is
  // reported too: a rebuild costs one job, never a wrong state.
  a_.settings_crc[1] ^= 1U;
  EXPECT_EQ(trn::tasks::core_settings_changed(a_, w), trn::tasks::kSettingsCamera);
  ASSERT_TRUE(trn::tasks::core_reload_settings(a_, w));
  EXPECT_EQ(trn::tasks::core_settings_changed(a_, w), 0U);
}

}  // namespace
