// The output-step metric (reports/output_step.hpp): against the truth through the trajectory
// scorer (metrics.json) and truth-free against the output's own motion (diagnostics.json), on a
// synthetic turning drive whose estimate follows the truth with a constant offset except for
// known jumps.
#include "reports/output_step.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "core/so3.hpp"
#include "reports/trajectory_scorer.hpp"

namespace statebench::reports {
namespace {

constexpr double kDt = 0.01;
constexpr double kSpeed = 10.0;     // m/s
constexpr double kYawRate = 0.2;    // rad/s

ReferenceState TruthAt(int k) {
  const double t = kDt * k;
  const double yaw = kYawRate * t;
  ReferenceState r;
  r.t_ns = FromSeconds(t);
  // A circle of radius v / w, started at the origin heading east.
  const double radius = kSpeed / kYawRate;
  r.T_world_frame = SE3(so3::FromRollPitchYaw(0.0, 0.0, yaw),
                        Vec3(radius * std::sin(yaw), radius * (1.0 - std::cos(yaw)), 0.0));
  r.v_world = Vec3(kSpeed * std::cos(yaw), kSpeed * std::sin(yaw), 0.0);
  r.distance_m = kSpeed * t;
  return r;
}

// The truth shifted by `offset` (world) and rotated by `yaw_offset`; velocity exact.
NavState EstimateAt(int k, const Vec3& offset, double yaw_offset) {
  const ReferenceState r = TruthAt(k);
  NavState s;
  s.t_ns = r.t_ns;
  s.p_world = r.T_world_frame.translation() + offset;
  s.q_world_imu = so3::FromRollPitchYaw(0.0, 0.0, yaw_offset) * r.T_world_frame.rotation();
  s.v_world = r.v_world;
  return s;
}

// The gyro of the drive (constant yaw rate), the same at every sample.
Vec3 GyroAt(int) { return Vec3(0.0, 0.0, kYawRate); }

TEST(OutputStep, AgainstTheTruthAConstantOffsetIsNoStepAndAJumpIsOne) {
  const Vec3 offset(0.3, -0.2, 0.1);
  const OutputStepErrors none =
      StepAgainstReference(EstimateAt(10, offset, 0.01), EstimateAt(11, offset, 0.01),
                           TruthAt(10), TruthAt(11));
  EXPECT_LT(none.position_m, 1e-9);
  EXPECT_LT(none.yaw_rad, 1e-9);
  const OutputStepErrors jump =
      StepAgainstReference(EstimateAt(10, offset, 0.01),
                           EstimateAt(11, offset + Vec3(0.03, 0.04, 0.0), -0.02), TruthAt(10),
                           TruthAt(11));
  EXPECT_NEAR(jump.position_m, 0.05, 1e-9);
  EXPECT_NEAR(jump.yaw_rad, 0.03, 1e-9);
}

TEST(OutputStep, TruthFreeStepMeasuresTheJumpBeyondTheOwnMotion) {
  // The estimate's own velocity and the gyro explain a consistent output to O(dt^3).
  const Vec3 offset(1.0, 2.0, 0.0);
  const OutputStepErrors none = StepAgainstOwnMotion(EstimateAt(20, offset, 0.0),
                                                     EstimateAt(21, offset, 0.0), GyroAt(20),
                                                     GyroAt(21));
  EXPECT_LT(none.position_m, 1e-6);  // the trapezoid leaves v w^2 dt^3 / 12 ~ 3e-8 m here
  EXPECT_LT(none.yaw_rad, 1e-9);
  const OutputStepErrors jump = StepAgainstOwnMotion(
      EstimateAt(20, offset, 0.0), EstimateAt(21, offset + Vec3(0.0, 0.2, 0.0), 0.01),
      GyroAt(20), GyroAt(21));
  EXPECT_NEAR(jump.position_m, 0.2, 1e-5);
  EXPECT_NEAR(jump.yaw_rad, 0.01, 1e-9);
  // The gyro bias of the estimate is taken out of the raw rate.
  NavState biased = EstimateAt(21, offset, 0.0);
  biased.gyro_bias = Vec3(0.0, 0.0, 0.5);
  const OutputStepErrors b = StepAgainstOwnMotion(EstimateAt(20, offset, 0.0), biased,
                                                  GyroAt(20) + biased.gyro_bias,
                                                  GyroAt(21) + biased.gyro_bias);
  EXPECT_LT(b.yaw_rad, 1e-9);
}

// 10 s at 100 Hz with an offset that jumps by 0.2 m (and 0.02 rad) every 0.5 s: 19 of 999
// steps (1.9 %) are jumps, so p99 and max see them and the median does not. Both definitions
// agree.
TEST(OutputStep, StatisticsOfARunWithJumpsEverySecond) {
  TrajectoryScorer scorer;
  OwnMotionStepMeter meter;
  for (int k = 0; k < 1000; ++k) {
    const int jumps = k / 50;
    const NavState e = EstimateAt(k, Vec3(0.2 * jumps, 0.0, 0.0), 0.02 * jumps);
    StateEstimate estimate;
    estimate.state = e;
    estimate.covariance = Mat15::Identity();
    scorer.Add(estimate, TruthAt(k));
    meter.Add(e, GyroAt(k));
  }
  const OutputSteps truth = scorer.Finish().output_step;
  const OutputSteps own = meter.Summary();
  for (const OutputSteps& s : {truth, own}) {
    EXPECT_EQ(s.position_m.count, 999u);
    EXPECT_EQ(s.yaw_rad.count, 999u);
    EXPECT_LT(s.position_m.p50, 1e-5);
    EXPECT_NEAR(s.position_m.p99, 0.2, 1e-3);
    EXPECT_NEAR(s.position_m.max, 0.2, 1e-5);
    EXPECT_LT(s.yaw_rad.p50, 1e-9);
    EXPECT_NEAR(s.yaw_rad.p99, 0.02, 1e-4);
    EXPECT_NEAR(s.yaw_rad.max, 0.02, 1e-9);
  }
}

// An epoch without an estimate breaks the chain: the pair across the gap is no step.
TEST(OutputStep, AGapIsNotAStep) {
  TrajectoryScorer scorer;
  OwnMotionStepMeter meter;
  for (int k = 0; k < 200; ++k) {
    if (k >= 100 && k < 150) {  // 0.5 s without an estimate; it comes back 1 m off
      scorer.Break();
      meter.Break();
      continue;
    }
    const NavState e = EstimateAt(k, Vec3(k < 100 ? 0.0 : 1.0, 0.0, 0.0), 0.0);
    StateEstimate estimate;
    estimate.state = e;
    scorer.Add(estimate, TruthAt(k));
    meter.Add(e, GyroAt(k));
  }
  const OutputSteps truth = scorer.Finish().output_step;
  EXPECT_EQ(truth.position_m.count, 99u + 49u);
  EXPECT_LT(truth.position_m.max, 1e-9);
  EXPECT_EQ(meter.Summary().position_m.count, 99u + 49u);
  EXPECT_LT(meter.Summary().position_m.max, 1e-5);
}

}  // namespace
}  // namespace statebench::reports
