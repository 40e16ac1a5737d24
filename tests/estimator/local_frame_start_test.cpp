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

#include "core/random.hpp"
#include "core/so3.hpp"
#include "core/yaml_node.hpp"
#include "differential_drive_robot.hpp"
#include "estimator/ekf_options.hpp"
#include "estimator/ekf_single_track.hpp"
#include "estimator/factor_graph_estimator.hpp"

namespace statebench::est {
namespace {

using testing::DifferentialDriveTrajectory;
using testing::kRobotImuNoise;
using testing::RobotDrive;
using testing::RobotHeading;
using testing::RobotSetupYaml;
using testing::RobotStream;
using testing::RobotStreamOptions;

struct RobotRun {
  EstimatorDiagnostics diagnostics;
  std::optional<StateEstimate> first;  // the first estimate
  double first_tilt_error_rad = 0.0;
  double first_speed_error_mps = 0.0;
  double end_error_m = 0.0;  // horizontal, aligned by the initial pose
  double max_error_m = 0.0;
  double end_yaw_error_rad = 0.0;
  double end_yaw_sigma_rad = 0.0;
  double distance_m = 0.0;  // driven from the first estimate on
  int estimates = 0;
  int not_local = 0;  // estimates whose status is not `local`
};

// The estimate against the truth after aligning the first estimate's position and heading with
// the truth's (the local frame starts at 0 with yaw 0; tilt is not aligned: it is observable).
RobotRun RunRobot(const DifferentialDriveTrajectory& traj, const std::vector<Measurement>& stream,
                  bool with_odometry) {
  const EstimatorSensorSetup setup = ParseEstimatorSensorSetup(
      YamlNode::LoadString(RobotSetupYaml(with_odometry), "robot_setup.yaml"));
  FactorGraphEstimator estimator(setup, FactorGraphOptions{});
  RobotRun run;
  Quat q_align = Quat::Identity();
  Vec3 p_est0 = Vec3::Zero(), p_truth0 = Vec3::Zero(), p_truth_previous = Vec3::Zero();
  for (const Measurement& m : stream) {
    estimator.Add(m);
    const auto* imu = std::get_if<ImuSample>(&m);
    if (imu == nullptr) continue;
    const TimeNs t = imu->header.stamp_ns;
    const std::optional<StateEstimate> e = estimator.StateAt(t);
    if (!e) continue;
    const NavState truth = traj.State(t);
    ++run.estimates;
    run.not_local += e->status != EstimateStatus::kLocal;
    if (!run.first) {
      run.first = e;
      q_align = Eigen::AngleAxisd(
          RobotHeading(truth.q_world_imu) - RobotHeading(e->state.q_world_imu), Vec3::UnitZ());
      p_est0 = e->state.p_world;
      p_truth0 = truth.p_world;
      const Vec3 up_est = e->state.q_world_imu.conjugate() * Vec3::UnitZ();
      const Vec3 up_truth = truth.q_world_imu.conjugate() * Vec3::UnitZ();
      run.first_tilt_error_rad = std::acos(std::clamp(up_est.dot(up_truth), -1.0, 1.0));
      run.first_speed_error_mps = (e->state.v_world.norm() - truth.v_world.norm());
    }
    if (run.estimates > 1) run.distance_m += (truth.p_world - p_truth_previous).head<2>().norm();
    p_truth_previous = truth.p_world;
    const Vec3 p = q_align * (e->state.p_world - p_est0) + p_truth0;
    const double error = (p - truth.p_world).head<2>().norm();
    run.max_error_m = std::max(run.max_error_m, error);
    run.end_error_m = error;
    run.end_yaw_error_rad = so3::WrapAngle(RobotHeading(q_align * e->state.q_world_imu) -
                                           RobotHeading(truth.q_world_imu));
    // Yaw sigma: the world-z component of the rotation covariance (right perturbation).
    const Mat3 R = e->state.q_world_imu.toRotationMatrix();
    const Mat3 P_world =
        R * e->covariance.block<3, 3>(kRotationIndex, kRotationIndex) * R.transpose();
    run.end_yaw_sigma_rad = std::sqrt(P_world(2, 2));
  }
  run.diagnostics = estimator.diagnostics();
  return run;
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
      RobotSetupYaml(false) +
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
