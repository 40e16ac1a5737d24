// The per-epoch errors and sigmas of errors.csv (reports/epoch_errors.hpp): the roll and pitch
// sigmas are the first-order spread of the angles under the rotation covariance, checked
// against finite differences of the angles on a tilted, turned attitude.
#include "reports/epoch_errors.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "core/so3.hpp"

namespace statebench::reports {
namespace {

TEST(EpochErrors, RollAndPitchSigmasAreTheAnglesSpreadUnderTheRotationCovariance) {
  NavState s;
  s.q_world_imu = so3::FromRollPitchYaw(0.3, -0.4, 2.0);
  ReferenceState r;
  r.T_world_frame = SE3(s.q_world_imu, Vec3::Zero());

  // A full rotation covariance: correlated axes, so a wrong Jacobian cannot hide.
  Mat3 L;
  L << 0.02, 0.0, 0.0,  //
      0.005, 0.03, 0.0,  //
      -0.004, 0.006, 0.01;
  Mat6 P = Mat6::Identity() * 1e-4;
  P.topLeftCorner<3, 3>() = L * L.transpose();

  // d(angle) / d(right perturbation) by central differences.
  Eigen::Matrix<double, 3, 3> J;
  const double h = 1e-6;
  for (int j = 0; j < 3; ++j) {
    const Vec3 d = Vec3::Unit(j) * h;
    const Vec3 plus = so3::ToRollPitchYaw(s.q_world_imu * so3::Exp<double>(d));
    const Vec3 minus = so3::ToRollPitchYaw(s.q_world_imu * so3::Exp<double>(Vec3(-d)));
    J.col(j) = (plus - minus) / (2.0 * h);
  }
  const Mat3 angles = J * P.topLeftCorner<3, 3>() * J.transpose();

  const EpochErrors e = EpochErrorsOf(s, EstimateStatus::kGlobal, P, Mat3::Identity(), r);
  EXPECT_NEAR(e.sigma_roll_rad, std::sqrt(angles(0, 0)), 1e-7);
  EXPECT_NEAR(e.sigma_pitch_rad, std::sqrt(angles(1, 1)), 1e-7);
  // The estimate equals the reference: no angle error.
  EXPECT_NEAR(e.errors.drpy.norm(), 0.0, 1e-12);
}

TEST(EpochErrors, RollAndPitchErrorsAreTheAnglesDifferences) {
  NavState s;
  s.q_world_imu = so3::FromRollPitchYaw(0.01, -0.02, 0.5);
  ReferenceState r;
  r.T_world_frame = SE3(so3::FromRollPitchYaw(0.015, -0.01, 0.5), Vec3::Zero());
  const EpochErrors e =
      EpochErrorsOf(s, EstimateStatus::kGlobal, Mat6::Identity(), Mat3::Identity(), r);
  EXPECT_NEAR(e.errors.drpy.x(), -0.005, 1e-12);
  EXPECT_NEAR(e.errors.drpy.y(), -0.01, 1e-12);
  EXPECT_NEAR(e.errors.drpy.z(), 0.0, 1e-12);
}

}  // namespace
}  // namespace statebench::reports
