#include "estimator/measurement_gate.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "core/so3.hpp"

namespace statebench::est {
namespace {

PropagatedState SomeGateState() {
  PropagatedState s;
  s.state.q_world_imu = so3::FromRollPitchYaw(0.05, -0.1, 0.7);
  s.state.p_world = Vec3(3.0, -2.0, 1.0);
  Vec15 sigma;
  sigma << 0.01, 0.02, 0.05, 0.1, 0.2, 0.3, Vec3::Constant(0.1), Vec6::Constant(0.01);
  s.covariance = sigma.cwiseAbs2().asDiagonal();
  s.covariance(kRotationIndex + 2, kPositionIndex) =
      s.covariance(kPositionIndex, kRotationIndex + 2) = 0.5 * 0.05 * 0.1;
  return s;
}

// Numeric Jacobian (on the rotation and position of the state) of a measurement function.
template <int M, typename H>
Eigen::Matrix<double, M, 15> NumericJacobian(const NavState& x, H h) {
  Eigen::Matrix<double, M, 15> J = Eigen::Matrix<double, M, 15>::Zero();
  const double eps = 1e-7;
  for (int i = 0; i < 6; ++i) {
    NavState a = x, b = x;
    Vec3 d = Vec3::Zero();
    d(i % 3) = eps;
    if (i < 3) {
      a.q_world_imu = x.q_world_imu * so3::Exp<double>(d);
      b.q_world_imu = x.q_world_imu * so3::Exp<double>(Vec3(-d));
    } else {
      a.p_world += d;
      b.p_world -= d;
    }
    J.col(i) = (h(a) - h(b)) / (2 * eps);
  }
  return J;
}

TEST(MeasurementGate, GnssDistanceUsesTheLeverArmThroughTheOrientation) {
  const PropagatedState s = SomeGateState();
  const Vec3 lever(1.2, -0.3, 1.5);
  const Mat3 C = Vec3(0.04, 0.05, 0.09).asDiagonal();
  const auto antenna = [&](const NavState& x) -> Vec3 { return x.p_world + x.q_world_imu * lever; };
  const Eigen::Matrix<double, 3, 15> H = NumericJacobian<3>(s.state, antenna);
  const Vec3 y(0.3, -0.2, 0.4);
  const Vec3 z = antenna(s.state) + y;
  const Mat3 S = H * s.covariance * H.transpose() + C;
  EXPECT_NEAR(GnssMahalanobisSquared(s, lever, z, C), y.dot(S.inverse() * y), 1e-6);
  PropagatedState exact = s;
  exact.covariance.setZero();
  EXPECT_NEAR(GnssMahalanobisSquared(exact, lever, z, C), y.dot(C.inverse() * y), 1e-9);
}

TEST(MeasurementGate, HeadingDistanceMatchesNumericJacobian) {
  const PropagatedState s = SomeGateState();
  const Vec3 baseline(2.0, 0.1, -0.05);
  const auto angles = [&](const NavState& x) -> Vec2 {
    const Vec3 b = x.q_world_imu * baseline;
    return Vec2(std::atan2(b.y(), b.x()), std::atan2(-b.z(), b.head<2>().norm()));
  };
  const Eigen::Matrix<double, 2, 15> H = NumericJacobian<2>(s.state, angles);
  DualAntennaHeading h;
  h.yaw_sigma_rad = 0.01;
  h.pitch_sigma_rad = 0.02;
  const Vec2 truth = angles(s.state);
  const Vec2 y(0.03, -0.02);
  h.yaw_rad = so3::WrapAngle(truth.x() + y.x());
  h.pitch_rad = truth.y() + y.y();
  Mat2 S = H * s.covariance * H.transpose();
  S(0, 0) += 1e-4;
  S(1, 1) += 4e-4;
  EXPECT_NEAR(HeadingMahalanobisSquared(s, baseline, h), y.dot(S.inverse() * y), 1e-6);
  h.pitch_sigma_rad = 0.0;  // yaw only
  EXPECT_NEAR(HeadingMahalanobisSquared(s, baseline, h), y.x() * y.x() / (S(0, 0)), 1e-6);
}

TEST(MeasurementGate, HeadingFromTwoFixes) {
  GnssPositionEnu main, aux;
  main.p_enu = Vec3(10.0, 5.0, 1.0);
  aux.p_enu = main.p_enu + Vec3(std::cos(0.6), std::sin(0.6), 0.0) * 1.25 + Vec3(0, 0, -0.1);
  main.covariance = aux.covariance = 1e-4 * Mat3::Identity();
  main.header.stamp_ns = 42;
  const DualAntennaHeading h = HeadingFromFixes(main, aux, "pair");
  EXPECT_EQ(h.header.sensor_id, "pair");
  EXPECT_EQ(h.header.stamp_ns, 42);
  EXPECT_NEAR(h.yaw_rad, 0.6, 1e-12);
  EXPECT_NEAR(h.pitch_rad, std::atan2(0.1, 1.25), 1e-12);
  EXPECT_NEAR(h.yaw_sigma_rad, std::sqrt(2e-4) / 1.25, 1e-12);
  const double length = std::hypot(1.25, 0.1);
  EXPECT_NEAR(h.pitch_sigma_rad, std::sqrt(2e-4) / length, 1e-12);
}

TEST(MeasurementGate, LargestSigma) {
  EXPECT_DOUBLE_EQ(LargestSigma(Vec3(1.0, 9.0, 4.0).asDiagonal().toDenseMatrix()), 3.0);
}

TEST(MeasurementGate, FixUseTestsTheHorizontalAndTheVerticalApart) {
  EXPECT_EQ(FixUse(Vec3(1.0, 1.0, 4.0).asDiagonal(), 5.0, 5.0), GnssFixUse::kFull);
  EXPECT_EQ(FixUse(Vec3(1.0, 1.0, 36.0).asDiagonal(), 5.0, 5.0), GnssFixUse::kHorizontalOnly);
  EXPECT_EQ(FixUse(Vec3(1.0, 1.0, 0.0).asDiagonal(), 5.0, 5.0), GnssFixUse::kHorizontalOnly);
  Mat3 no_height = Mat3::Identity();
  no_height(2, 2) = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(FixUse(no_height, 5.0, 5.0), GnssFixUse::kHorizontalOnly);
  EXPECT_EQ(FixUse(Vec3(36.0, 1.0, 1.0).asDiagonal(), 5.0, 5.0), GnssFixUse::kDiscarded);
  // A horizontal ellipse's major axis, not its diagonal, is tested.
  Mat3 tilted = Vec3(20.0, 20.0, 1.0).asDiagonal();
  tilted(0, 1) = tilted(1, 0) = 10.0;  // eigenvalues 10 and 30: sigma 5.48 m
  EXPECT_EQ(FixUse(tilted, 5.0, 5.0), GnssFixUse::kDiscarded);
  const Mat3 w = WithoutVertical(tilted);
  EXPECT_TRUE((w.topLeftCorner<2, 2>() == tilted.topLeftCorner<2, 2>()));
  EXPECT_EQ(w(2, 2), kUnusedVerticalVariance);
  EXPECT_EQ(w(0, 2), 0.0);
  EXPECT_EQ(w(2, 1), 0.0);
}

}  // namespace
}  // namespace statebench::est
