// SO(3) helpers on unit quaternions (Hamilton, Eigen convention).
//
// Exp maps a rotation vector phi (axis * angle, rad) to a rotation; Log is its inverse with the
// angle in [0, pi]. Perturbations are on the right: R(phi + dphi) ~= R(phi) Exp(Jr(phi) dphi).
// Right Jacobian (Forster et al., TRO 2017, eq. 8):
//   Jr(phi) = I - (1 - cos t)/t^2 [phi]x + (t - sin t)/t^3 [phi]x^2,   t = |phi|.
// The templates accept ceres::Jet so factors can use them under automatic differentiation.
#pragma once

#include <cmath>

#include "core/eigen_types.hpp"

namespace statebench::so3 {

template <typename T>
Eigen::Matrix<T, 3, 3> Hat(const Eigen::Matrix<T, 3, 1>& v) {
  Eigen::Matrix<T, 3, 3> m;
  m << T(0), -v.z(), v.y(), v.z(), T(0), -v.x(), -v.y(), v.x(), T(0);
  return m;
}

template <typename T>
Eigen::Matrix<T, 3, 1> Vee(const Eigen::Matrix<T, 3, 3>& m) {
  return Eigen::Matrix<T, 3, 1>(m(2, 1), m(0, 2), m(1, 0));
}

template <typename T>
Eigen::Quaternion<T> Exp(const Eigen::Matrix<T, 3, 1>& phi) {
  using std::cos;
  using std::sin;
  using std::sqrt;
  const T theta_sq = phi.squaredNorm();
  if (theta_sq < T(1e-10)) {
    // Taylor expansion: avoids 0/0 and keeps derivatives finite for Jets.
    const T w = T(1) - theta_sq / T(8);
    const Eigen::Matrix<T, 3, 1> xyz = phi * (T(0.5) - theta_sq / T(48));
    return Eigen::Quaternion<T>(w, xyz.x(), xyz.y(), xyz.z()).normalized();
  }
  const T theta = sqrt(theta_sq);
  const T half = theta / T(2);
  const Eigen::Matrix<T, 3, 1> xyz = phi * (sin(half) / theta);
  return Eigen::Quaternion<T>(cos(half), xyz.x(), xyz.y(), xyz.z());
}

template <typename T>
Eigen::Matrix<T, 3, 1> Log(const Eigen::Quaternion<T>& q_in) {
  using std::atan2;
  using std::sqrt;
  // q and -q are the same rotation; pick w >= 0 so the angle is in [0, pi].
  Eigen::Quaternion<T> q = q_in;
  if (q.w() < T(0)) q.coeffs() = -q.coeffs();
  const Eigen::Matrix<T, 3, 1> xyz = q.vec();
  const T n_sq = xyz.squaredNorm();
  if (n_sq < T(1e-10)) {
    // theta/sin(theta/2) ~= 2/w * (1 - n^2 / (3 w^2))
    const T w = q.w();
    return xyz * (T(2) / w - T(2) * n_sq / (T(3) * w * w * w));
  }
  const T n = sqrt(n_sq);
  const T theta = T(2) * atan2(n, q.w());
  return xyz * (theta / n);
}

template <typename T>
Eigen::Matrix<T, 3, 3> ExpMatrix(const Eigen::Matrix<T, 3, 1>& phi) {
  return Exp(phi).toRotationMatrix();
}

// Right Jacobian of SO(3); see the header comment.
Mat3 RightJacobian(const Vec3& phi);
// Inverse of the right Jacobian:
//   Jr^-1(phi) = I + 1/2 [phi]x + (1/t^2 - (1 + cos t)/(2 t sin t)) [phi]x^2.
Mat3 RightJacobianInverse(const Vec3& phi);
// Left Jacobian, Jl(phi) = Jr(-phi).
Mat3 LeftJacobian(const Vec3& phi);

// Geodesic interpolation: q0 * Exp(alpha * Log(q0^-1 q1)), alpha in [0, 1].
Quat Interpolate(const Quat& q0, const Quat& q1, double alpha);

// Roll-pitch-yaw (Z-Y-X intrinsic, R = Rz(yaw) Ry(pitch) Rx(roll)) conversions.
Quat FromRollPitchYaw(double roll, double pitch, double yaw);
Vec3 ToRollPitchYaw(const Quat& q);  // (roll, pitch, yaw), yaw in (-pi, pi]

// Wraps an angle to (-pi, pi].
double WrapAngle(double angle);

}  // namespace statebench::so3
