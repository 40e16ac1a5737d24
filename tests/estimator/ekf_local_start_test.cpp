// Issue 14: the EKF runs without GNSS (odometry + IMU), as robot_localization's does. The
// differential-drive robot of robot_drive.hpp (IMU + wheel odometry as body_velocity, 300 m with
// turns on the spot): the EKF starts in a local frame (the IMU at 0, yaw 0) within 2 s, standing
// or moving, says so in its status and diagnostics, and its horizontal drift stays under 2 % of
// the distance (the single-track EKF is the baseline; the factor graph holds 1 %,
// local_frame_start_test.cpp). Seeds 11-15.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "any_line_contains.hpp"
#include "core/geodetic.hpp"
#include "ekf_test_drive.hpp"
#include "estimator/ekf_options.hpp"
#include "estimator/ekf_single_track.hpp"
#include "robot_drive.hpp"

namespace statebench::est {
namespace {

using testing::DifferentialDriveTrajectory;
using testing::RobotDrive;
using testing::RobotRun;
using testing::RobotSetup;
using testing::RobotStream;
using testing::RobotStreamOptions;

using testing::AnyContains;

TEST(EkfLocalStart, DifferentialDriveStartsStillAndDriftsUnderTwoPercent) {
  const DifferentialDriveTrajectory traj = RobotDrive(2.0);
  double worst_percent = 0.0;
  for (std::uint64_t seed = 11; seed <= 15; ++seed) {
    RobotStreamOptions o;
    o.seed = seed;
    EkfSingleTrackEstimator ekf(RobotSetup(true), EkfOptions{});
    const RobotRun run = testing::RunRobot(ekf, traj, RobotStream(traj, o));
    ASSERT_TRUE(run.first.has_value()) << run.diagnostics.waiting_for;
    const double start_s = ToSeconds(run.first->state.t_ns);
    const double percent = 100.0 * run.end_error_m / traj.distance_m();
    worst_percent = std::max(worst_percent, percent);
    const SensorCounters& odometry = run.diagnostics.sensors.at("wheel_odom");
    const auto standstill = odometry.events.find("zero_rate_updates");
    const std::uint64_t standstill_updates =
        standstill == odometry.events.end() ? 0 : standstill->second;
    std::printf(
        "ekf, seed %d: started at %.2f s (%s); horizontal error at the end %.3f m (%.2f %% of "
        "%.0f m), max %.3f m; yaw error at the end %.4f rad, its sigma %.4f rad; %llu standstill "
        "updates\n",
        static_cast<int>(seed), start_s, run.diagnostics.initialization.c_str(), run.end_error_m,
        percent, traj.distance_m(), run.max_error_m, run.end_yaw_error_rad, run.end_yaw_sigma_rad,
        static_cast<unsigned long long>(standstill_updates));
    EXPECT_EQ(run.diagnostics.initialization, "static (local frame)");
    EXPECT_LT(start_s, 2.0);
    EXPECT_TRUE(run.diagnostics.waiting_for.empty());
    EXPECT_EQ(run.not_local, 0);
    EXPECT_LT(run.first->state.p_world.norm(), 0.01);  // the IMU at 0 at the first state
    EXPECT_LT(run.end_error_m, 0.02 * traj.distance_m()) << "seed " << seed;
    EXPECT_GT(odometry.accepted, 2500u);
    // The standstills at the corners measure the gyro's z bias (123-126 updates on seeds 11-15).
    EXPECT_GT(standstill_updates, 100u);
    EXPECT_TRUE(AnyContains(run.diagnostics.warnings, "no GNSS antenna"));
    EXPECT_FALSE(AnyContains(run.diagnostics.warnings, "no speed input"));
  }
  std::printf("ekf local start, seeds 11-15: worst drift %.2f %% of the distance\n", worst_percent);
}

TEST(EkfLocalStart, DifferentialDriveStartsMovingFromOdometry) {
  const DifferentialDriveTrajectory traj = RobotDrive(0.0);
  for (std::uint64_t seed = 11; seed <= 15; ++seed) {
    RobotStreamOptions o;
    o.seed = seed;
    o.start_s = 12.0;  // the log begins on the first leg at 1.6 m/s, accelerating
    o.end_s = 60.0;
    EkfSingleTrackEstimator ekf(RobotSetup(true), EkfOptions{});
    const RobotRun run = testing::RunRobot(ekf, traj, RobotStream(traj, o));
    ASSERT_TRUE(run.first.has_value()) << run.diagnostics.waiting_for;
    const double start_s = ToSeconds(run.first->state.t_ns) - o.start_s;
    std::printf(
        "ekf moving start, seed %d: %.2f s after the first sample (%s), speed error %.3f m/s; "
        "%.0f m later the horizontal error is %.3f m (max %.3f m)\n",
        static_cast<int>(seed), start_s, run.diagnostics.initialization.c_str(),
        run.first_speed_error_mps, run.distance_m, run.end_error_m, run.max_error_m);
    EXPECT_EQ(run.diagnostics.initialization, "moving (odometry, local frame)");
    EXPECT_LT(start_s, 2.0);
    EXPECT_EQ(run.not_local, 0);
    EXPECT_LT(std::abs(run.first_speed_error_mps), 0.05);
    EXPECT_LT(run.end_error_m, 0.02 * run.distance_m) << "seed " << seed;
  }
}

TEST(EkfLocalStart, OutputInTheLocalFrame) {
  // The WGS84 columns: the local frame placed at latitude, longitude and height 0.
  const DifferentialDriveTrajectory traj = RobotDrive(2.0);
  RobotStreamOptions o;
  o.seed = 12;
  o.end_s = 20.0;
  EkfSingleTrackEstimator ekf(RobotSetup(true), EkfOptions{});
  TimeNs newest = 0;
  for (const Measurement& m : RobotStream(traj, o)) {
    ekf.Add(m);
    if (std::holds_alternative<ImuSample>(m)) newest = HeaderOf(m).stamp_ns;
  }
  const std::optional<StateEstimate> e = ekf.StateAt(newest);
  ASSERT_TRUE(e.has_value());
  EXPECT_EQ(e->status, EstimateStatus::kLocal);
  EXPECT_FALSE(ekf.origin().has_value());  // no ENU origin: the frame is local
  const GeodeticPoint g = LocalEnuFrame(GeodeticPoint{0.0, 0.0, 0.0}).ToGeodetic(e->state.p_world);
  EXPECT_DOUBLE_EQ(e->latitude_deg, g.latitude_deg);
  EXPECT_DOUBLE_EQ(e->longitude_deg, g.longitude_deg);
  EXPECT_DOUBLE_EQ(e->altitude_m, g.altitude_m);
  EXPECT_GT(e->state.p_world.head<2>().norm(), 1.0);  // it drove
}

TEST(EkfLocalStart, NeverInitialisedSaysWhatItWaitsFor) {
  // A vibrating IMU (0.04 rad/s gyro std) and no odometry: no still period, no moving start.
  const DifferentialDriveTrajectory traj = RobotDrive(10.0);
  RobotStreamOptions o;
  o.end_s = 8.0;
  o.extra_gyro_sigma_radps = 0.04;
  o.odometry = false;
  EkfSingleTrackEstimator ekf(RobotSetup(false), EkfOptions{});
  const RobotRun run = testing::RunRobot(ekf, traj, RobotStream(traj, o));
  EXPECT_EQ(run.estimates, 0);
  EXPECT_FALSE(run.diagnostics.initialized);
  const std::string& why = run.diagnostics.waiting_for;
  EXPECT_NE(why.find("no still period of 1 s (quietest window: gyro std"), std::string::npos)
      << why;
  EXPECT_NE(why.find("no body-frame odometry in the setup"), std::string::npos) << why;
  EXPECT_TRUE(AnyContains(run.diagnostics.warnings, "no speed input"));
}

TEST(EkfLocalStart, CarWithSpeedAndSteeringEncodersStartsMoving) {
  // The single-track drive of ekf_test_drive.hpp (8 m/s on a circle, noisy gyro and speed
  // encoder) without its GNSS: the speed encoder is the moving start's odometry.
  testing::DriveOptions o;
  o.duration_s = 30.0;
  o.gyro_sigma_radps = 0.002;
  o.accel_sigma_mps2 = 0.02;
  o.speed_sigma_mps = 0.02;
  EkfOptions options;
  testing::Drive d = testing::MakeDrive(options.vehicle, o);
  std::erase_if(d.stream, [](const Measurement& m) { return std::holds_alternative<GnssFix>(m); });
  const EstimatorSensorSetup setup = ParseEstimatorSensorSetup(YamlNode::LoadString(
      "name: car\nsensors:\n"
      "  - {type: imu, id: imu, T_body_sensor: {translation: [0, 0, 0.5]}}\n"
      "  - {type: speed_encoder, id: speed, T_body_sensor: {translation: [-0.76, 0, 0.27]}}\n"
      "  - {type: steering_encoder, id: steering, T_body_sensor: {translation: [0.93, 0, 0]}}\n",
      "car.yaml"));
  EkfSingleTrackEstimator ekf(setup, options);
  std::optional<StateEstimate> first, last;
  testing::PlanarTruth truth0, truth_last;
  for (const Measurement& m : d.stream) {
    ekf.Add(m);
    const auto* imu = std::get_if<ImuSample>(&m);
    if (imu == nullptr) continue;
    const std::optional<StateEstimate> e = ekf.StateAt(imu->header.stamp_ns);
    if (!e) continue;
    const testing::PlanarTruth& t =
        d.truth[static_cast<std::size_t>(imu->header.stamp_ns / 10'000'000)];
    EXPECT_EQ(e->status, EstimateStatus::kLocal);
    if (!first) {
      first = e;
      truth0 = t;
    }
    last = e;
    truth_last = t;
  }
  ASSERT_TRUE(first.has_value()) << ekf.diagnostics().waiting_for;
  EXPECT_EQ(ekf.diagnostics().initialization, "moving (odometry, local frame)");
  EXPECT_LT(ToSeconds(first->state.t_ns), 2.0);
  EXPECT_NEAR(first->state.v_world.norm(), testing::TruthImuVelocity(truth0).norm(), 0.05);
  // The truth's displacement since the start, in the start's body frame, against the estimate's
  // (the local frame: the IMU at 0 and the body's x axis along x at the start).
  const Mat2 R0 = Eigen::Rotation2Dd(truth0.psi).toRotationMatrix();
  const Vec2 truth_moved =
      R0.transpose() *
      (testing::TruthImuPosition(truth_last) - testing::TruthImuPosition(truth0)).head<2>();
  const double error_m = (last->state.p_world.head<2>() - truth_moved).norm();
  const double distance_m = 8.0 * ToSeconds(last->state.t_ns - first->state.t_ns);
  std::printf("car without GNSS: started at %.2f s, %.3f m off after %.0f m\n",
              ToSeconds(first->state.t_ns), error_m, distance_m);
  EXPECT_LT(error_m, 0.02 * distance_m);
}

}  // namespace
}  // namespace statebench::est
