// What the EKF says it lacks in a setup before it runs (issue 14: it ran with another
// vehicle's file and no speed input without a word).
#include "estimator/ekf_input_check.hpp"

#include <gtest/gtest.h>

#include <string>

#include "core/yaml_node.hpp"
#include "any_line_contains.hpp"
#include "ekf_test_drive.hpp"
#include "estimator/ekf_single_track.hpp"

namespace statebench::est {
namespace {

using testing::AnyContains;

TEST(EkfInputCheck, AFullSetupOfItsOwnVehicleHasNoWarningButTheSensorsItIgnores) {
  const std::vector<std::string> w =
      EkfInputWarnings(testing::MakeDriveSetup(), SingleTrackParams{});  // the quadricycle
  ASSERT_EQ(w.size(), 1u);
  EXPECT_NE(w[0].find("not used by this estimator: wheels (wheel_encoders)"), std::string::npos);
}

TEST(EkfInputCheck, NoSpeedNoSteeringIsSaid) {
  const std::vector<std::string> w =
      EkfInputWarnings(testing::MakeMinimalDriveSetup(), SingleTrackParams{});
  EXPECT_TRUE(AnyContains(w, "no speed input"));
  EXPECT_TRUE(AnyContains(w, "between GNSS fixes only"));
  EXPECT_TRUE(AnyContains(w, "no steering input"));
  EXPECT_FALSE(AnyContains(w, "no GNSS antenna"));
  // And the estimator reports them in its diagnostics from the start.
  EkfOptions options;
  const EkfSingleTrackEstimator ekf(testing::MakeMinimalDriveSetup(), options);
  EXPECT_EQ(ekf.diagnostics().warnings, w);
}

TEST(EkfInputCheck, BodyVelocityIsASpeedInput) {
  // A robot with wheel odometry as body_velocity and no GNSS: no "no speed input", no "not used",
  // but the local frame is said.
  const std::vector<std::string> w = EkfInputWarnings(
      ParseEstimatorSensorSetup(YamlNode::LoadString(
          "name: robot\nsensors:\n"
          "  - {type: imu, id: imu, T_body_sensor: {translation: [0, 0, 0.2]}}\n"
          "  - {type: body_velocity, id: wheel_odom, T_body_sensor: {translation: [0, 0, 0]}}\n",
          "robot.yaml")),
      SingleTrackParams{});
  EXPECT_FALSE(AnyContains(w, "no speed input"));
  EXPECT_FALSE(AnyContains(w, "not used by this estimator"));
  EXPECT_TRUE(AnyContains(w, "no GNSS antenna: a local frame"));
  EXPECT_TRUE(AnyContains(w, "no steering input"));
}

TEST(EkfInputCheck, NoGnssNoOdometryDriftsWithoutBound) {
  const std::vector<std::string> w =
      EkfInputWarnings(ParseEstimatorSensorSetup(YamlNode::LoadString(
                           "name: imu_only\nsensors:\n"
                           "  - {type: imu, id: imu, T_body_sensor: {translation: [0, 0, 0.2]}}\n",
                           "imu_only.yaml")),
                       SingleTrackParams{});
  EXPECT_TRUE(AnyContains(w, "no GNSS antenna"));
  EXPECT_TRUE(AnyContains(w,
                          "no speed input (speed_encoder or body_velocity): the speed comes "
                          "from the IMU's longitudinal acceleration alone"));
}

TEST(EkfInputCheck, AnotherVehiclesFileIsSuspected) {
  SingleTrackParams shuttle;  // axles 1.5 m from the centre of gravity
  shuttle.cg_to_front_axle_m = 1.5;
  shuttle.cg_to_rear_axle_m = 1.5;
  const std::vector<std::string> w = EkfInputWarnings(testing::MakeDriveSetup(), shuttle);
  EXPECT_TRUE(AnyContains(w, "'speed' is mounted at x = -0.76 m but the vehicle file's rear axle "
                             "is at x = -1.50 m"));
  EXPECT_TRUE(AnyContains(w, "'steering' is mounted at x = 0.93 m but the vehicle file's front "
                             "axle is at x = 1.50 m"));
  EXPECT_FALSE(AnyContains(w, "no speed input"));
}

}  // namespace
}  // namespace statebench::est
