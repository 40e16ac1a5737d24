// EnuAlignment: a local track against ENU fixes gives the yaw and translation between the frames
// (exact without noise), sigmas that match the scatter of seeded noisy fits (the residuals
// reveal a covariance reported too small), and Apply moves a state and its covariance.
#include "estimator/enu_alignment.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "core/random.hpp"
#include "core/so3.hpp"
#include "core/state.hpp"

namespace statebench::est {
namespace {

// An L-shaped local track (20 m along x, then 10 m along y), one point per metre.
std::vector<Vec3> AlignmentTrack() {
  std::vector<Vec3> track;
  for (int k = 0; k <= 20; ++k) track.emplace_back(k, 0.0, 0.1 * k);
  for (int k = 1; k <= 10; ++k) track.emplace_back(20.0, k, 2.0);
  return track;
}

constexpr double kAlignYaw = 2.0;
const Vec3 kAlignTranslation(35.0, -20.0, 4.0);

Vec3 ToEnuExactly(const Vec3& p_local) {
  return Eigen::AngleAxisd(kAlignYaw, Vec3::UnitZ()) * p_local + kAlignTranslation;
}

TEST(EnuAlignment, RecoversTheFrameExactly) {
  EnuAlignment alignment;
  const std::vector<Vec3> track = AlignmentTrack();
  for (std::size_t k = 0; k < track.size(); ++k) {
    EXPECT_EQ(alignment.Solve().has_value(), static_cast<int>(k) >= EnuAlignment::kMinFixes);
    alignment.Add(FromSeconds(0.4 * k), track[k], ToEnuExactly(track[k]), 0.25 * Mat3::Identity());
  }
  const auto r = alignment.Solve();
  ASSERT_TRUE(r.has_value());
  EXPECT_NEAR(r->yaw_rad, kAlignYaw, 1e-12);
  EXPECT_LT((r->translation - kAlignTranslation).norm(), 1e-9);
  EXPECT_NEAR(r->sigma_h_m, 0.5, 1e-12);  // the reported sigma: no residuals
  EXPECT_EQ(r->fixes, static_cast<int>(track.size()));
}

TEST(EnuAlignment, SigmasMatchTheScatterWhenTheCovarianceIsUnderReported) {
  // True noise 1 m per horizontal axis, reported 0.5 m: the residuals give the sigma.
  const std::vector<Vec3> track = AlignmentTrack();
  auto rng = MakeRng(7, "enu_alignment_test");
  NormalSampler normal;
  double yaw_sq = 0.0, yaw_sigma_sq = 0.0, centroid_sq = 0.0, centroid_sigma_sq = 0.0;
  const int runs = 400;
  for (int run = 0; run < runs; ++run) {
    EnuAlignment alignment;
    Vec3 b = Vec3::Zero();
    for (std::size_t k = 0; k < track.size(); ++k) {
      const Vec3 noise(normal(rng), normal(rng), 2.0 * normal(rng));
      alignment.Add(FromSeconds(0.4 * k), track[k], ToEnuExactly(track[k]) + noise,
                    Vec3(0.25, 0.25, 1.0).asDiagonal());
      b += ToEnuExactly(track[k]);
    }
    b /= static_cast<double>(track.size());
    const auto r = alignment.Solve();
    ASSERT_TRUE(r.has_value());
    const double e = so3::WrapAngle(r->yaw_rad - kAlignYaw);
    yaw_sq += e * e;
    yaw_sigma_sq += r->yaw_sigma_rad * r->yaw_sigma_rad;
    centroid_sq += (r->centroid_enu - b).head<2>().squaredNorm();
    centroid_sigma_sq += r->centroid_sigma.head<2>().squaredNorm();
  }
  // RMS error against RMS sigma, within the spread of 400 runs (about +-7 % in sigma).
  EXPECT_NEAR(std::sqrt(yaw_sq / yaw_sigma_sq), 1.0, 0.12);
  EXPECT_NEAR(std::sqrt(centroid_sq / centroid_sigma_sq), 1.0, 0.12);
}

TEST(EnuAlignment, ApplyMovesTheStateAndAddsTheAlignmentUncertainty) {
  EnuAlignment::Result r;
  r.yaw_rad = kAlignYaw;
  r.translation = kAlignTranslation;
  r.yaw_sigma_rad = 0.01;
  r.centroid_enu = kAlignTranslation;
  r.centroid_sigma = Vec3(0.2, 0.2, 0.3);
  PropagatedState local;
  local.state.q_world_imu = so3::FromRollPitchYaw(0.02, -0.01, 0.3);
  local.state.p_world = Vec3(10.0, 0.0, 0.5);
  local.state.v_world = Vec3(1.0, 0.5, 0.0);
  local.covariance = 1e-4 * Mat15::Identity();
  const PropagatedState enu = r.Apply(local);
  EXPECT_LT((enu.state.p_world - ToEnuExactly(local.state.p_world)).norm(), 1e-12);
  EXPECT_LT((enu.state.v_world - ToEnuExactly(local.state.v_world) + kAlignTranslation).norm(),
            1e-12);
  EXPECT_NEAR(so3::ToRollPitchYaw(enu.state.q_world_imu).z(), so3::WrapAngle(0.3 + kAlignYaw),
              1e-12);
  // Horizontal position variance: its own, the centroid's and the yaw's at 10 m from it.
  const Mat3 P = enu.covariance.block<3, 3>(kPositionIndex, kPositionIndex);
  EXPECT_NEAR(P.trace(), 3e-4 + 0.2 * 0.2 * 2 + 0.3 * 0.3 + 100.0 * 1e-4, 1e-9);
  EXPECT_TRUE(enu.covariance.isApprox(enu.covariance.transpose()));
}

}  // namespace
}  // namespace statebench::est
