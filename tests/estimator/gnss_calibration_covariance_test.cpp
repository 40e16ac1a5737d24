#include "estimator/gnss_calibration_covariance.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

namespace statebench::est {
namespace {

// The covariance is what the calibration errors do: drawn mounts and clocks, pushed through the
// measurement, give the same second moments (Monte Carlo, 200k draws, within 2 %).
TEST(GnssCalibrationCovariance, PositionMatchesDrawnMountAndClockErrors) {
  GnssCalibrationUncertainty u;
  u.mount_translation_sigma_m = 0.01;
  u.mount_rotation_sigma_deg = 0.5;
  u.clock_offset_sigma_s = 0.004;
  const Quat q(Eigen::AngleAxisd(0.7, Vec3::UnitZ()) * Eigen::AngleAxisd(0.05, Vec3::UnitX()));
  const Vec3 v(8.0, -3.0, 0.2);
  const Vec3 lever(1.2, -0.3, 1.5);
  const Mat3 C = PositionCalibrationCovariance(u, q, v, lever);

  std::mt19937_64 rng(5);
  std::normal_distribution<double> normal;
  const auto draw = [&] { return Vec3(normal(rng), normal(rng), normal(rng)); };
  const double sr = u.mount_rotation_sigma_deg * M_PI / 180.0;
  Mat3 moments = Mat3::Zero();
  const int n = 200000;
  for (int k = 0; k < n; ++k) {
    // Antenna and IMU mounts translated, the IMU turned (the lever arm in its frame with it),
    // the fix taken dt later than its stamp says.
    const Vec3 dt_mounts = u.mount_translation_sigma_m * (draw() - draw());
    const Vec3 dtheta = sr * draw();
    const Quat turned = q * Quat(Eigen::AngleAxisd(dtheta.norm(), dtheta.normalized()));
    const double dt = u.clock_offset_sigma_s * normal(rng);
    const Vec3 e = dt_mounts + (turned * lever - q * lever) + v * dt;
    moments += e * e.transpose();
  }
  moments /= n;
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) {
      EXPECT_NEAR(moments(i, j), C(i, j), 0.02 * C.diagonal().maxCoeff()) << i << "," << j;
    }
  }
}

TEST(GnssCalibrationCovariance, TermsVanishWhenTheirSigmaIsZeroAndHeadingScalesWithBaseline) {
  GnssCalibrationUncertainty none{0.0, 0.0, 0.0};
  EXPECT_TRUE(PositionCalibrationCovariance(none, Quat::Identity(), Vec3(10, 0, 0), Vec3(1, 0, 1))
                  .isZero());
  GnssCalibrationUncertainty clock_only{0.0, 0.0, 0.01};
  const Mat3 C = PositionCalibrationCovariance(clock_only, Quat::Identity(), Vec3(10, 0, 0),
                                               Vec3(1, 0, 1));
  EXPECT_DOUBLE_EQ(C(0, 0), 0.01);  // (10 m/s x 0.01 s)^2
  EXPECT_DOUBLE_EQ(C(1, 1), 0.0);

  GnssCalibrationUncertainty mounts{0.01, 0.0, 0.0};
  const HeadingCalibrationVariance h2 = HeadingCalibration(mounts, Vec3(2.0, 0.0, 0.0));
  const HeadingCalibrationVariance h1 = HeadingCalibration(mounts, Vec3(1.0, 0.0, 0.0));
  EXPECT_DOUBLE_EQ(h2.yaw_rad2, 2.0 * 0.01 * 0.01 / 4.0);
  EXPECT_DOUBLE_EQ(h1.yaw_rad2, 4.0 * h2.yaw_rad2);
  GnssCalibrationUncertainty rotation{0.0, 0.2, 0.0};
  EXPECT_NEAR(HeadingCalibration(rotation, Vec3(2, 0, 0)).yaw_rad2,
              std::pow(0.2 * M_PI / 180.0, 2), 1e-15);
}

// The output's consider covariance: the position block is the fix's calibration covariance at
// the state, the rotation block the baseline's yaw variance about the world's vertical (no
// roll or pitch), nothing elsewhere; no baseline, no rotation block.
TEST(GnssCalibrationCovariance, ConsiderCovarianceIsYawAboutTheVerticalAndTheFixsPositionShare) {
  const GnssCalibrationUncertainty u;  // the defaults
  NavState state;
  state.q_world_imu =
      Quat(Eigen::AngleAxisd(1.1, Vec3::UnitZ()) * Eigen::AngleAxisd(0.2, Vec3::UnitY()));
  state.v_world = Vec3(4.0, 2.0, 0.0);
  const Vec3 lever(0.45, 0.0, 1.0);
  const Vec3 baseline(-1.25, 0.0, 0.0);
  const Mat15 C = CalibrationConsiderCovariance(u, state, lever, &baseline);
  const Mat3 position = C.block<3, 3>(3, 3);
  EXPECT_TRUE(position.isApprox(
      PositionCalibrationCovariance(u, state.q_world_imu, state.v_world, lever)));
  // Rotated to the world frame (left perturbation R d), the rotation block is yaw only.
  const Mat3 R = state.q_world_imu.toRotationMatrix();
  const Mat3 rotation = C.topLeftCorner<3, 3>();
  const Mat3 world = R * rotation * R.transpose();
  EXPECT_NEAR(world(2, 2), HeadingCalibration(u, baseline).yaw_rad2, 1e-15);
  EXPECT_NEAR(world.topLeftCorner(2, 2).norm(), 0.0, 1e-15);
  EXPECT_TRUE(C.bottomRows(9).isZero());
  const Mat15 without = CalibrationConsiderCovariance(u, state, lever, nullptr);
  EXPECT_TRUE(without.topLeftCorner(3, 3).isZero());
  // A baseline that measures pitch too: its variance about the horizontal axis
  // across the baseline, in world terms.
  const Mat15 paired = CalibrationConsiderCovariance(u, state, lever, &baseline, true);
  const Mat3 paired_rotation = paired.topLeftCorner<3, 3>();
  const Mat3 paired_world = R * paired_rotation * R.transpose();
  const Vec3 across = Vec3::UnitZ().cross(R * baseline).normalized();
  EXPECT_NEAR(across.dot(paired_world * across), HeadingCalibration(u, baseline).pitch_rad2, 1e-15);
  EXPECT_NEAR(paired_world(2, 2), HeadingCalibration(u, baseline).yaw_rad2, 1e-15);
}

// An IMU mounted level and straight: the motion constraints' share is the mount's rotation
// variance about the IMU's z (yaw) and y (pitch) axes, none about x; turned by 90 deg about z,
// the body's lateral axis is the IMU's x.
TEST(GnssCalibrationCovariance, MotionConstraintShareIsYawAndPitchAboutTheBodyAxes) {
  const GnssCalibrationUncertainty u;
  const double s2 = std::pow(u.mount_rotation_sigma_deg * M_PI / 180.0, 2);
  const Mat3 level = MotionConstraintConsiderCovariance(u, Quat::Identity());
  EXPECT_TRUE(level.isApprox(Vec3(0.0, s2, s2).asDiagonal().toDenseMatrix()));
  const Mat3 turned =
      MotionConstraintConsiderCovariance(u, Quat(Eigen::AngleAxisd(M_PI / 2, Vec3::UnitZ())));
  EXPECT_NEAR(turned(0, 0), s2, 1e-15);
  EXPECT_NEAR(turned(1, 1), 0.0, 1e-15);
  EXPECT_NEAR(turned(2, 2), s2, 1e-15);
}

}  // namespace
}  // namespace statebench::est
