#include "core/so3.hpp"

#include <numbers>

namespace statebench::so3 {

Mat3 RightJacobian(const Vec3& phi) {
  const double theta_sq = phi.squaredNorm();
  const Mat3 phi_hat = Hat(phi);
  if (theta_sq < 1e-10) {
    return Mat3::Identity() - 0.5 * phi_hat + (1.0 / 6.0) * phi_hat * phi_hat;
  }
  const double theta = std::sqrt(theta_sq);
  return Mat3::Identity() - (1.0 - std::cos(theta)) / theta_sq * phi_hat +
         (theta - std::sin(theta)) / (theta_sq * theta) * phi_hat * phi_hat;
}

Mat3 RightJacobianInverse(const Vec3& phi) {
  const double theta_sq = phi.squaredNorm();
  const Mat3 phi_hat = Hat(phi);
  if (theta_sq < 1e-10) {
    return Mat3::Identity() + 0.5 * phi_hat + (1.0 / 12.0) * phi_hat * phi_hat;
  }
  const double theta = std::sqrt(theta_sq);
  return Mat3::Identity() + 0.5 * phi_hat +
         (1.0 / theta_sq - (1.0 + std::cos(theta)) / (2.0 * theta * std::sin(theta))) * phi_hat *
             phi_hat;
}

Mat3 LeftJacobian(const Vec3& phi) { return RightJacobian(-phi); }

Quat Interpolate(const Quat& q0, const Quat& q1, double alpha) {
  return (q0 * Exp<double>(alpha * Log<double>(q0.conjugate() * q1))).normalized();
}

Quat FromRollPitchYaw(double roll, double pitch, double yaw) {
  return Quat(Eigen::AngleAxisd(yaw, Vec3::UnitZ()) * Eigen::AngleAxisd(pitch, Vec3::UnitY()) *
              Eigen::AngleAxisd(roll, Vec3::UnitX()));
}

Vec3 ToRollPitchYaw(const Quat& q) {
  const Mat3 r = q.toRotationMatrix();
  const double pitch = std::asin(std::clamp(-r(2, 0), -1.0, 1.0));
  const double roll = std::atan2(r(2, 1), r(2, 2));
  const double yaw = std::atan2(r(1, 0), r(0, 0));
  return Vec3(roll, pitch, yaw);
}

double WrapAngle(double angle) {
  constexpr double kTwoPi = 2.0 * std::numbers::pi;
  double a = std::fmod(angle + std::numbers::pi, kTwoPi);
  if (a <= 0.0) a += kTwoPi;
  return a - std::numbers::pi;
}

}  // namespace statebench::so3
