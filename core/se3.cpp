#include "core/se3.hpp"

namespace statebench {

SE3 SE3::Exp(const Vec6& xi) {
  const Vec3 rho = xi.head<3>();
  const Vec3 phi = xi.tail<3>();
  return SE3(so3::Exp<double>(phi), so3::LeftJacobian(phi) * rho);
}

Vec6 SE3::Log() const {
  const Vec3 phi = so3::Log<double>(q_);
  // Jl^-1(phi) = Jr^-1(-phi).
  Vec6 xi;
  xi << so3::RightJacobianInverse(-phi) * t_, phi;
  return xi;
}

Eigen::Matrix4d SE3::Matrix() const {
  Eigen::Matrix4d m = Eigen::Matrix4d::Identity();
  m.topLeftCorner<3, 3>() = RotationMatrix();
  m.topRightCorner<3, 1>() = t_;
  return m;
}

SE3 SE3::Inverse() const {
  const Quat q_inv = q_.conjugate();
  return SE3(q_inv, -(q_inv * t_));
}

SE3 SE3::Interpolate(const SE3& t0, const SE3& t1, double alpha) {
  return t0 * SE3::Exp(alpha * (t0.Inverse() * t1).Log());
}

}  // namespace statebench
