// Issue 14: the factor graph starts with whatever sensors a vehicle has. A differential-drive
// robot with an IMU and wheel odometry only (body_velocity: vx, vy measured, vz not), on an
// analytic drive of 300 m with turns on the spot (differential_drive_trajectory.hpp): the
// estimator starts in a local frame (position 0, yaw 0), within 2 s, standing or moving, says so
// in its status and diagnostics, and drifts less than 1 % of the distance (aligned by the initial
// pose). An estimator that cannot start says what it waits for.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "core/yaml_node.hpp"
#include "estimator/ekf_options.hpp"
#include "estimator/ekf_single_track.hpp"
#include "estimator/factor_graph_estimator.hpp"
#include "robot_drive.hpp"

namespace statebench::est {
namespace {

using testing::DifferentialDriveTrajectory;
using testing::RobotDrive;
using testing::RobotRun;
using testing::RobotSetup;
using testing::RobotStream;
using testing::RobotStreamOptions;

RobotRun RunRobot(const DifferentialDriveTrajectory& traj, const std::vector<Measurement>& stream,
                  bool with_odometry) {
  FactorGraphEstimator estimator(RobotSetup(with_odometry), FactorGraphOptions{});
  return testing::RunRobot(estimator, traj, stream);
}

TEST(LocalFrameStart, DifferentialDriveStartsStillAndDriftsUnderOnePercent) {
  const DifferentialDriveTrajectory traj = RobotDrive(2.0);
  ASSERT_NEAR(traj.distance_m(), 300.0, 1e-9);
  RobotStreamOptions o;
  o.seed = 14;
  const RobotRun run = RunRobot(traj, RobotStream(traj, o), true);
  ASSERT_TRUE(run.first.has_value()) << run.diagnostics.waiting_for;
  const double start_s = ToSeconds(run.first->state.t_ns);
  std::printf(
      "differential drive, %.0f m in %.0f s: started at %.2f s (%s), tilt error %.4f rad; "
      "horizontal error at the end %.3f m (%.2f %% of the distance), max %.3f m; yaw error at "
      "the end %.4f rad, its sigma %.4f rad\n",
      traj.distance_m(), traj.duration_s(), start_s, run.diagnostics.initialization.c_str(),
      run.first_tilt_error_rad, run.end_error_m, 100.0 * run.end_error_m / traj.distance_m(),
      run.max_error_m, run.end_yaw_error_rad, run.end_yaw_sigma_rad);
  EXPECT_EQ(run.diagnostics.initialization, "static (local frame)");
  EXPECT_LT(start_s, 2.0);
  EXPECT_TRUE(run.diagnostics.waiting_for.empty());
  EXPECT_EQ(run.not_local, 0);
  EXPECT_LT(run.first->state.p_world.norm(), 0.01);  // 0 at the first state, propagated
  EXPECT_LT(run.first_tilt_error_rad, 0.01);
  EXPECT_LT(run.end_error_m, 0.01 * traj.distance_m());
  // The covariance says the truth: yaw is unobservable, its sigma grows with the gyro's.
  EXPECT_LT(std::abs(run.end_yaw_error_rad), 3.0 * run.end_yaw_sigma_rad);
  const SensorCounters& odometry = run.diagnostics.sensors.at("wheel_odom");
  EXPECT_GT(odometry.events.at("body_velocity_factors"), 2500u);
  // The standstills at the corners measure the gyro bias (zero-rate factors, about 9 per s).
  EXPECT_GT(odometry.events.at("zero_rate_factors"), 100u);
}

TEST(LocalFrameStart, DifferentialDriveStartsMovingFromOdometry) {
  const DifferentialDriveTrajectory traj = RobotDrive(0.0);
  RobotStreamOptions o;
  o.seed = 15;
  o.start_s = 12.0;  // the log begins on the first leg at 1.6 m/s, accelerating
  o.end_s = 60.0;
  const RobotRun run = RunRobot(traj, RobotStream(traj, o), true);
  ASSERT_TRUE(run.first.has_value()) << run.diagnostics.waiting_for;
  const double start_s = ToSeconds(run.first->state.t_ns) - o.start_s;
  std::printf(
      "moving start: %.2f s after the first sample (%s), tilt error %.4f rad, speed error %.3f "
      "m/s; %.0f m later the horizontal error is %.3f m (max %.3f m), yaw error %.4f rad, its "
      "sigma %.4f rad\n",
      start_s, run.diagnostics.initialization.c_str(), run.first_tilt_error_rad,
      run.first_speed_error_mps, run.distance_m, run.end_error_m, run.max_error_m,
      run.end_yaw_error_rad, run.end_yaw_sigma_rad);
  EXPECT_EQ(run.diagnostics.initialization, "moving (odometry, local frame)");
  EXPECT_LT(start_s, 2.0);
  EXPECT_EQ(run.not_local, 0);
  EXPECT_LT(run.first_tilt_error_rad, 0.01);
  EXPECT_LT(std::abs(run.first_speed_error_mps), 0.05);
  // Moving, the gyro's z bias is unknown (prior 0.01 rad/s): the yaw drifts until the first
  // standstill measures the bias, and the smoother then corrects what it still holds.
  EXPECT_LT(run.end_error_m, 0.01 * run.distance_m);
  EXPECT_LT(std::abs(run.end_yaw_error_rad), 3.0 * run.end_yaw_sigma_rad);
}

TEST(LocalFrameStart, NeverInitialisedSaysWhatItWaitsFor) {
  // A robot whose IMU vibrates (0.04 rad/s gyro std) and that has no odometry: neither a still
  // period nor a moving start can give its first state.
  const DifferentialDriveTrajectory traj = RobotDrive(10.0);
  RobotStreamOptions o;
  o.end_s = 8.0;
  o.extra_gyro_sigma_radps = 0.04;
  o.odometry = false;
  const RobotRun run = RunRobot(traj, RobotStream(traj, o), false);
  EXPECT_EQ(run.estimates, 0);
  EXPECT_FALSE(run.diagnostics.initialized);
  const std::string& why = run.diagnostics.waiting_for;
  std::printf("waiting for: %s\n", why.c_str());
  EXPECT_NE(why.find("no still period of 1 s (quietest window: gyro std 0.03"), std::string::npos)
      << why;
  EXPECT_NE(why.find("rad/s > 0.01)"), std::string::npos) << why;
  EXPECT_NE(why.find("no body-frame odometry in the setup"), std::string::npos) << why;
}

TEST(LocalFrameStart, EstimatorsWithGnssWithoutFixSayTheyWaitForOne) {
  // The same IMU data with a GNSS antenna in the setup that never delivers a fix.
  const DifferentialDriveTrajectory traj = RobotDrive(3.0);
  RobotStreamOptions o;
  o.end_s = 6.0;
  o.odometry = false;
  const std::vector<Measurement> stream = RobotStream(traj, o);
  const EstimatorSensorSetup setup = ParseEstimatorSensorSetup(YamlNode::LoadString(
      testing::RobotSetupYaml(false) +
          "  - {type: gnss, id: gnss, T_body_sensor: {translation: [0, 0, 1]}}\n",
      "robot_gnss_setup.yaml"));
  FactorGraphEstimator factor_graph(setup, FactorGraphOptions{});
  EkfSingleTrackEstimator ekf(setup, EkfOptions{});
  for (const Measurement& m : stream) {
    factor_graph.Add(m);
    ekf.Add(m);
  }
  // Standing still: the still period is there, the fix is not.
  EXPECT_EQ(factor_graph.diagnostics().waiting_for, "no GNSS fix");
  EXPECT_EQ(ekf.diagnostics().waiting_for, "no GNSS fix of gnss");
}

}  // namespace
}  // namespace statebench::est
