#include "estimator/so3_manifold.hpp"

#include "core/so3.hpp"

namespace statebench::est {

Mat43 QuaternionPlusJacobian(const double* q_xyzw) {
  const Eigen::Map<const Vec3> v(q_xyzw);
  const double w = q_xyzw[3];
  Mat43 J;
  J.topRows<3>() = 0.5 * (w * Mat3::Identity() + so3::Hat<double>(v));
  J.bottomRows<1>() = -0.5 * v.transpose();
  return J;
}

Mat34 QuaternionMinusJacobian(const double* q_xyzw) {
  const Eigen::Map<const Vec3> v(q_xyzw);
  const double w = q_xyzw[3];
  Mat34 J;
  J.leftCols<3>() = 2.0 * (w * Mat3::Identity() - so3::Hat<double>(v));
  J.rightCols<1>() = -2.0 * v;
  return J;
}

bool RightQuaternionManifold::Plus(const double* x, const double* delta,
                                   double* x_plus_delta) const {
  const Eigen::Map<const Quat> q(x);
  const Eigen::Map<const Vec3> d(delta);
  Eigen::Map<Quat> out(x_plus_delta);
  out = (q * so3::Exp<double>(d)).normalized();
  return true;
}

bool RightQuaternionManifold::PlusJacobian(const double* x, double* jacobian) const {
  Eigen::Map<Mat43>{jacobian} = QuaternionPlusJacobian(x);
  return true;
}

bool RightQuaternionManifold::Minus(const double* y, const double* x, double* y_minus_x) const {
  const Eigen::Map<const Quat> qy(y);
  const Eigen::Map<const Quat> qx(x);
  Eigen::Map<Vec3>{y_minus_x} = so3::Log<double>(qx.conjugate() * qy);
  return true;
}

bool RightQuaternionManifold::MinusJacobian(const double* x, double* jacobian) const {
  Eigen::Map<Mat34>{jacobian} = QuaternionMinusJacobian(x);
  return true;
}

}  // namespace statebench::est
