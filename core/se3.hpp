// Rigid transforms. SE3 T_a_b maps points from frame b to frame a: p_a = T_a_b * p_b.
//
// Tangent vectors are ordered (rho, phi): translation part first, rotation second, with
//   Exp(rho, phi) = (Exp_SO3(phi), Jl(phi) rho),   Jl the SO(3) left Jacobian.
#pragma once

#include <cmath>

#include "core/eigen_types.hpp"
#include "core/so3.hpp"

namespace statebench {

class SE3 {
 public:
  SE3() : q_(Quat::Identity()), t_(Vec3::Zero()) {}
  // Normalises q unless it already is of unit norm to rounding, so that a stored quaternion
  // read back gives the identical transform.
  SE3(const Quat& q, const Vec3& t) : q_(NormalizedIfNeeded(q)), t_(t) {}
  SE3(const Mat3& r, const Vec3& t) : q_(Quat(r).normalized()), t_(t) {}

  static SE3 Identity() { return SE3(); }
  static SE3 Exp(const Vec6& xi);  // xi = (rho, phi)
  Vec6 Log() const;

  const Quat& rotation() const { return q_; }
  const Vec3& translation() const { return t_; }
  Mat3 RotationMatrix() const { return q_.toRotationMatrix(); }
  Eigen::Matrix4d Matrix() const;

  SE3 Inverse() const;
  SE3 operator*(const SE3& other) const { return SE3(q_ * other.q_, t_ + q_ * other.t_); }
  Vec3 operator*(const Vec3& p) const { return q_ * p + t_; }

  // Geodesic interpolation T0 * Exp(alpha * Log(T0^-1 T1)).
  static SE3 Interpolate(const SE3& t0, const SE3& t1, double alpha);

 private:
  static Quat NormalizedIfNeeded(const Quat& q) {
    return std::abs(q.squaredNorm() - 1.0) > 1e-15 ? q.normalized() : q;
  }

  Quat q_;
  Vec3 t_;
};

}  // namespace statebench
