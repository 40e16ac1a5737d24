// Metrics on hand-made trajectories with known answers.
#include "reports/trajectory_metrics.hpp"

#include <gtest/gtest.h>

#include "reports/metrics_json.hpp"

namespace statebench::reports {
namespace {

// Straight line along x at 10 m/s, sampled every 10 ms for `seconds`, heading `yaw`.
std::vector<ReferenceState> StraightReference(double seconds, double yaw = 0.0) {
  std::vector<ReferenceState> ref;
  const Quat q = so3::FromRollPitchYaw(0, 0, yaw);
  const Vec3 dir = q * Vec3::UnitX();
  for (int i = 0; i <= static_cast<int>(seconds * 100); ++i) {
    ReferenceState r;
    r.t_ns = i * 10 * kNsPerMillisecond;
    r.T_world_frame = SE3(q, dir * (0.1 * i));
    r.v_world = dir * 10.0;
    r.distance_m = 0.1 * i;
    ref.push_back(r);
  }
  return ref;
}

StateEstimate FromReference(const ReferenceState& r) {
  StateEstimate e;
  e.state.t_ns = r.t_ns;
  e.state.q_world_imu = r.T_world_frame.rotation();
  e.state.p_world = r.T_world_frame.translation();
  e.state.v_world = r.v_world;
  e.covariance = Mat15::Identity() * 0.01;
  return e;
}

TEST(TrajectoryMetrics, PerfectEstimateHasZeroError) {
  const auto ref = StraightReference(10.0);
  std::vector<StateEstimate> est;
  for (const auto& r : ref) est.push_back(FromReference(r));
  const TrajectoryMetrics m = ComputeTrajectoryMetrics(est, ref);
  EXPECT_EQ(m.compared, ref.size());
  EXPECT_DOUBLE_EQ(m.rmse_x_m, 0.0);
  EXPECT_DOUBLE_EQ(m.ape_translation_m.max, 0.0);
  EXPECT_NEAR(m.rpe_translation_m.rmse, 0.0, 1e-12);
  EXPECT_NEAR(m.distance_m, 100.0, 1e-9);
  EXPECT_DOUBLE_EQ(m.mean_pose_nees, 0.0);
}

TEST(TrajectoryMetrics, ConstantOffsetGivesKnownRmseApeAndNoRelativeError) {
  const auto ref = StraightReference(10.0);
  std::vector<StateEstimate> est;
  for (const auto& r : ref) {
    StateEstimate e = FromReference(r);
    e.state.p_world += Vec3(1.0, -2.0, 0.0);
    est.push_back(e);
  }
  const TrajectoryMetrics m = ComputeTrajectoryMetrics(est, ref);
  EXPECT_NEAR(m.rmse_x_m, 1.0, 1e-12);
  EXPECT_NEAR(m.rmse_y_m, 2.0, 1e-12);
  EXPECT_NEAR(m.ape_translation_m.rmse, std::sqrt(5.0), 1e-12);
  EXPECT_NEAR(m.ape_translation_m.median, std::sqrt(5.0), 1e-12);
  EXPECT_NEAR(m.ape_translation_m.std, 0.0, 1e-9);
  EXPECT_NEAR(m.rpe_translation_m.max, 0.0, 1e-9);
  EXPECT_NEAR(m.kitti_translation_percent, 0.0, 1e-9);
  // Position NEES with covariance 0.01 I: |e|^2 / 0.01 = 500.
  EXPECT_NEAR(m.mean_position_nees, 500.0, 1e-6);
  EXPECT_NEAR(m.mean_pose_nees, 500.0, 1e-6);
}

// Heading near +-pi: +3.1 versus -3.1 rad differ by 2 pi - 6.2 = 0.0832 rad, not 6.2 rad.
TEST(TrajectoryMetrics, YawErrorWrapsAroundPi) {
  const auto ref = StraightReference(2.0, 3.1);
  std::vector<StateEstimate> est;
  for (const auto& r : ref) {
    StateEstimate e = FromReference(r);
    e.state.q_world_imu = so3::FromRollPitchYaw(0, 0, -3.1);
    e.state.v_world = e.state.q_world_imu * Vec3(10.0, 0, 0);
    est.push_back(e);
  }
  const TrajectoryMetrics m = ComputeTrajectoryMetrics(est, ref);
  EXPECT_NEAR(m.rmse_yaw_rad, 2 * M_PI - 6.2, 1e-9);
  EXPECT_NEAR(m.ape_rotation_rad.max, 2 * M_PI - 6.2, 1e-9);
  EXPECT_NEAR(m.rmse_v_longitudinal_mps, 0.0, 1e-9);  // each velocity in its own frame
  EXPECT_NEAR(m.rmse_roll_rad, 0.0, 1e-12);
}

// An estimate whose travelled distance is 1 % too long: KITTI translation error 1 %, RPE over
// 10 m is 0.1 m, and an outage window reports error / distance.
TEST(TrajectoryMetrics, ScaleDriftGivesKnownRelativeErrorAndOutageDrift) {
  const auto ref = StraightReference(100.0);  // 1000 m
  std::vector<StateEstimate> est;
  for (const auto& r : ref) {
    StateEstimate e = FromReference(r);
    e.state.p_world *= 1.01;
    est.push_back(e);
  }
  MetricsOptions options;
  options.outages = {{FromSeconds(20.0), FromSeconds(30.0)}};
  const TrajectoryMetrics m = ComputeTrajectoryMetrics(est, ref, options);
  EXPECT_NEAR(m.kitti_translation_percent, 1.0, 1e-6);
  EXPECT_GT(m.kitti_segments, 100u);
  // Segments end at the first sample at least 10 m on: rounding can add one 0.1 m sample.
  EXPECT_NEAR(m.rpe_translation_m.mean, 0.1, 1e-4);
  ASSERT_EQ(m.outages.size(), 1u);
  EXPECT_NEAR(m.outages[0].distance_m, 100.0, 1e-6);
  EXPECT_NEAR(m.outages[0].error_end_m, 3.0, 1e-9);  // 1 % of 300 m at t = 30 s
  EXPECT_NEAR(m.outages[0].drift_per_metre, 0.03, 1e-9);
  const auto json = ToJson(m);
  EXPECT_NEAR(json["kitti"]["translation_percent"].get<double>(), 1.0, 1e-6);
  EXPECT_NEAR(json["outages"][0]["error_end_m"].get<double>(), 3.0, 1e-9);
}

// A rotation error about z of 0.1 rad with variance 0.01: NEES contribution 1.
TEST(TrajectoryMetrics, PoseNeesUsesRightPerturbationAndCovarianceBlocks) {
  const auto ref = StraightReference(1.0);
  std::vector<StateEstimate> est;
  for (const auto& r : ref) {
    StateEstimate e = FromReference(r);
    e.state.q_world_imu = r.T_world_frame.rotation() * so3::Exp<double>(Vec3(0, 0, -0.1));
    e.covariance = Mat15::Identity();
    e.covariance(2, 2) = 0.01;
    est.push_back(e);
  }
  const TrajectoryMetrics m = ComputeTrajectoryMetrics(est, ref);
  EXPECT_NEAR(m.mean_pose_nees, 1.0, 1e-9);
  EXPECT_NEAR(m.mean_position_nees, 0.0, 1e-12);
  EXPECT_EQ(m.nees_count, ref.size());
}

TEST(TrajectoryMetrics, InterpolatesReferenceAndSkipsOutsideSpan) {
  const auto ref = StraightReference(1.0);
  std::vector<StateEstimate> est;
  StateEstimate e = FromReference(ref[3]);
  e.state.t_ns += 5 * kNsPerMillisecond;  // between samples 3 and 4
  e.state.p_world = Vec3(0.35, 0, 0);
  est.push_back(e);
  StateEstimate late = FromReference(ref.back());
  late.state.t_ns += kNsPerSecond;
  est.push_back(late);
  const TrajectoryMetrics m = ComputeTrajectoryMetrics(est, ref);
  EXPECT_EQ(m.compared, 1u);
  EXPECT_EQ(m.skipped, 1u);
  EXPECT_NEAR(m.ape_translation_m.max, 0.0, 1e-12);
}

TEST(ErrorStatistics, KnownValues) {
  const ErrorStatistics s = ComputeStatistics({1.0, 2.0, 3.0, 4.0});
  EXPECT_DOUBLE_EQ(s.mean, 2.5);
  EXPECT_DOUBLE_EQ(s.median, 2.5);
  EXPECT_DOUBLE_EQ(s.max, 4.0);
  EXPECT_NEAR(s.rmse, std::sqrt(7.5), 1e-12);
  EXPECT_NEAR(s.std, std::sqrt(1.25), 1e-12);
}

}  // namespace
}  // namespace statebench::reports
