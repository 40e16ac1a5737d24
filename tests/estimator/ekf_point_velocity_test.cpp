// The EKF's odometry measurement model (ekf_point_velocity.hpp): the velocity of a point of the
// planar vehicle in a sensor frame, checked against the rigid-body formula and its Jacobian
// against central differences.
#include "estimator/ekf_point_velocity.hpp"

#include <gtest/gtest.h>

#include "core/so3.hpp"

namespace statebench::est::ekf {
namespace {

VecN SomeState() {
  VecN x;
  x << 12.0, -4.0, 2.6, 3.1, -0.25, 0.45, 0.003, -0.02;  // x, y, psi, vx, vy, r, bg, ba
  return x;
}

TEST(EkfPointVelocity, IsTheRigidBodyVelocityInTheSensorFrame) {
  const VecN x = SomeState();
  const Mat3 R_body_sensor = so3::FromRollPitchYaw(0.1, -0.2, 0.7).toRotationMatrix();
  const Vec3 p(0.3, -0.2, 0.4);
  // v_point = v_origin + omega x p, in the world frame, seen from the sensor's frame.
  const Mat3 R_world_body = YawRotation(x[kPsi]);
  const Vec3 v_world = R_world_body * (Vec3(x[kVx], x[kVy], 0.0) + Vec3(0.0, 0.0, x[kR]).cross(p));
  const Vec3 expected = (R_world_body * R_body_sensor).transpose() * v_world;
  const PointVelocity v = PredictPointVelocity(x, R_body_sensor, p);
  EXPECT_LT((v.v_sensor - expected).norm(), 1e-12);
  // A speed encoder (sensor axes = body axes) measures vx - r p_y.
  const PointVelocity speed = PredictPointVelocity(x, Mat3::Identity(), p);
  EXPECT_DOUBLE_EQ(speed.v_sensor.x(), x[kVx] - x[kR] * p.y());
  EXPECT_EQ(speed.H(0, kVx), 1.0);
  EXPECT_EQ(speed.H(0, kR), -p.y());
}

TEST(EkfPointVelocity, JacobianMatchesCentralDifferences) {
  const Mat3 R_body_sensor = so3::FromRollPitchYaw(-0.3, 0.15, -1.2).toRotationMatrix();
  const Vec3 p(-0.7, 0.25, 0.1);
  for (const double r : {0.0, 0.45, -1.3}) {
    VecN x = SomeState();
    x[kR] = r;
    const PointVelocity v = PredictPointVelocity(x, R_body_sensor, p);
    Eigen::Matrix<double, 3, kN> numeric;
    const double h = 1e-6;
    for (int i = 0; i < kN; ++i) {
      VecN plus = x, minus = x;
      plus[i] += h;
      minus[i] -= h;
      numeric.col(i) = (PredictPointVelocity(plus, R_body_sensor, p).v_sensor -
                        PredictPointVelocity(minus, R_body_sensor, p).v_sensor) /
                       (2.0 * h);
    }
    EXPECT_LT((v.H - numeric).cwiseAbs().maxCoeff(), 1e-8) << "r = " << r << "\n" << v.H;
    // Only vx, vy and r enter.
    for (const int i : {kX, kY, kPsi, kBg, kBa}) EXPECT_TRUE(v.H.col(i).isZero()) << i;
  }
}

}  // namespace
}  // namespace statebench::est::ekf
