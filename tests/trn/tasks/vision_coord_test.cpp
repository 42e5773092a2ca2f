/**
 * @file vision_coord_test.cpp
 * @brief The coordinator's weighing of a fine match by its frame's prior attitude.
 */
#include "trn/tasks/vision/vision_coord.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>

namespace {

using trn::tasks::weighed_sigma_px;

trn::vision::PosePrior prior_with_attitude_sigma(double per_axis_deg) {
  trn::vision::PosePrior p{};
  for (double& s : p.sigma_att_rad) {
    s = per_axis_deg * std::numbers::pi / 180.0;
  }
  return p;
}

TEST(WeighedSigma, GrowsWithThePriorsAttitudeSigmaInQuadrature) {
  const double k = trn::tasks::VisionCoordConfig{}.sigma_px_per_prior_deg;
  EXPECT_DOUBLE_EQ(k, 0.4) << "the flight's setting";
  // The frame at 1 s: 0.5 deg an axis (0.866 deg in all): 0.11 px becomes 0.36 px.
  const double loose = weighed_sigma_px(0.11, prior_with_attitude_sigma(0.5), k);
  EXPECT_NEAR(loose, std::hypot(0.11, 0.4 * 0.5 * std::sqrt(3.0)), 1e-12);
  EXPECT_GT(loose, 3.0 * 0.11);
  // The frame at 2 s: ~0.01 deg an axis, the correlation's sigma within 0.2 %.
  const double tight = weighed_sigma_px(0.11, prior_with_attitude_sigma(0.01), k);
  EXPECT_GT(tight, 0.11);
  EXPECT_LT(tight, 0.11 * 1.002);
  EXPECT_DOUBLE_EQ(weighed_sigma_px(0.11, prior_with_attitude_sigma(0.0), k), 0.11);
  EXPECT_NEAR(trn::tasks::prior_attitude_px(prior_with_attitude_sigma(0.5), k), 0.4 * 0.5 * std::sqrt(3.0), 1e-12);
}

TEST(WeighedSigma, OffOrWithoutAFiniteAttitudeSigmaTheCorrelationsSigmaStands) {
  EXPECT_DOUBLE_EQ(weighed_sigma_px(0.2, prior_with_attitude_sigma(1.0), 0.0), 0.2);
  EXPECT_DOUBLE_EQ(weighed_sigma_px(0.2, prior_with_attitude_sigma(1.0), -1.0), 0.2);
  trn::vision::PosePrior nan_prior = prior_with_attitude_sigma(1.0);
  nan_prior.sigma_att_rad[1] = std::numeric_limits<double>::quiet_NaN();
  EXPECT_DOUBLE_EQ(weighed_sigma_px(0.2, nan_prior, 0.4), 0.2);
  trn::vision::PosePrior inf_prior = prior_with_attitude_sigma(1.0);
  inf_prior.sigma_att_rad[2] = std::numeric_limits<double>::infinity();
  EXPECT_DOUBLE_EQ(weighed_sigma_px(0.2, inf_prior, 0.4), 0.2);
  EXPECT_EQ(trn::tasks::prior_attitude_px(inf_prior, 0.4), 0.0) << "nothing added";
}

}  // namespace
