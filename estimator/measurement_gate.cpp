#include "estimator/measurement_gate.hpp"

#include <Eigen/Eigenvalues>
#include <cmath>

#include "core/so3.hpp"

namespace statebench::est {
namespace {

using Row3 = Eigen::RowVector3d;

Row3 YawGradient(const Vec3& b) {
  const double h2 = b.x() * b.x() + b.y() * b.y();
  return Row3(-b.y(), b.x(), 0.0) / h2;
}

Row3 PitchGradient(const Vec3& b) {
  const double h = b.head<2>().norm();
  return Row3(b.z() * b.x() / h, b.z() * b.y() / h, -h) / b.squaredNorm();
}

double Pitch(const Vec3& b) { return std::atan2(-b.z(), b.head<2>().norm()); }

}  // namespace

double LargestSigma(const Mat3& covariance) {
  const Eigen::SelfAdjointEigenSolver<Mat3> eig(0.5 * (covariance + covariance.transpose()),
                                                Eigen::EigenvaluesOnly);
  return std::sqrt(std::max(0.0, eig.eigenvalues().maxCoeff()));
}

GnssFixUse FixUse(const Mat3& covariance, double max_sigma, double max_vertical_sigma) {
  const Mat2 horizontal = covariance.topLeftCorner<2, 2>();
  if (!horizontal.allFinite()) return GnssFixUse::kFull;  // the fix's validation refuses it
  const Eigen::SelfAdjointEigenSolver<Mat2> eig(0.5 * (horizontal + horizontal.transpose()),
                                                Eigen::EigenvaluesOnly);
  if (!(std::sqrt(std::max(0.0, eig.eigenvalues().maxCoeff())) <= max_sigma)) {
    return GnssFixUse::kDiscarded;
  }
  const double vertical = covariance(2, 2);
  if (!(vertical > 0.0) || !std::isfinite(vertical) ||
      std::sqrt(vertical) > max_vertical_sigma) {
    return GnssFixUse::kHorizontalOnly;
  }
  return GnssFixUse::kFull;
}

Mat3 WithoutVertical(const Mat3& covariance) {
  Mat3 out = covariance;
  out.row(2).setZero();
  out.col(2).setZero();
  out(2, 2) = kUnusedVerticalVariance;
  return out;
}

double GnssMahalanobisSquared(const PropagatedState& predicted, const Vec3& p_imu_antenna,
                              const Vec3& p_enu, const Mat3& covariance_enu) {
  const NavState& x = predicted.state;
  const Mat3 R = x.q_world_imu.toRotationMatrix();
  const Vec3 y = p_enu - (x.p_world + R * p_imu_antenna);
  Eigen::Matrix<double, 3, 15> H = Eigen::Matrix<double, 3, 15>::Zero();
  H.block<3, 3>(0, kRotationIndex) = -R * so3::Hat(p_imu_antenna);
  H.block<3, 3>(0, kPositionIndex) = Mat3::Identity();
  const Mat3 S = H * predicted.covariance * H.transpose() + covariance_enu;
  return y.dot(S.ldlt().solve(y));
}

double GnssVelocityMahalanobisSquared(const PropagatedState& predicted, const Vec3& p_imu_antenna,
                                      const Vec3& gyro_raw, const GnssVelocity& velocity) {
  const NavState& x = predicted.state;
  const Mat3 R = x.q_world_imu.toRotationMatrix();
  const Vec3 u = (gyro_raw - x.gyro_bias).cross(p_imu_antenna);
  const Vec3 y = velocity.v_enu - (x.v_world + R * u);
  Eigen::Matrix<double, 3, 15> H = Eigen::Matrix<double, 3, 15>::Zero();
  H.block<3, 3>(0, kRotationIndex) = -R * so3::Hat(u);
  H.block<3, 3>(0, kVelocityIndex) = Mat3::Identity();
  H.block<3, 3>(0, kGyroBiasIndex) = R * so3::Hat(p_imu_antenna);
  const Mat3 S =
      H * predicted.covariance * H.transpose() + Mat3(velocity.sigma_enu.cwiseAbs2().asDiagonal());
  return y.dot(S.ldlt().solve(y));
}

double HeadingMahalanobisSquared(const PropagatedState& predicted, const Vec3& baseline_imu,
                                 const DualAntennaHeading& heading) {
  const Mat3 R = predicted.state.q_world_imu.toRotationMatrix();
  const Vec3 b = R * baseline_imu;
  const Mat3 db_dtheta = -R * so3::Hat(baseline_imu);
  const Mat3 P_rot = predicted.covariance.block<3, 3>(kRotationIndex, kRotationIndex);
  const Row3 H_yaw = YawGradient(b) * db_dtheta;
  const double yaw_error = so3::WrapAngle(heading.yaw_rad - std::atan2(b.y(), b.x()));
  const bool use_pitch = heading.pitch_sigma_rad > 0.0 && std::isfinite(heading.pitch_sigma_rad);
  if (!use_pitch) {
    const double s =
        H_yaw * P_rot * H_yaw.transpose() + heading.yaw_sigma_rad * heading.yaw_sigma_rad;
    return yaw_error * yaw_error / s;
  }
  Eigen::Matrix<double, 2, 3> H;
  H.row(0) = H_yaw;
  H.row(1) = PitchGradient(b) * db_dtheta;
  Mat2 S = H * P_rot * H.transpose();
  S(0, 0) += heading.yaw_sigma_rad * heading.yaw_sigma_rad;
  S(1, 1) += heading.pitch_sigma_rad * heading.pitch_sigma_rad;
  const Vec2 y(yaw_error, heading.pitch_rad - Pitch(b));
  return y.dot(S.ldlt().solve(y));
}

DualAntennaHeading HeadingFromFixes(const GnssPositionEnu& main, const GnssPositionEnu& aux,
                                    const std::string& heading_id) {
  const Vec3 b = aux.p_enu - main.p_enu;
  const Mat3 C = main.covariance + aux.covariance;
  DualAntennaHeading h;
  h.header = main.header;
  h.header.sensor_id = heading_id;
  h.yaw_rad = std::atan2(b.y(), b.x());
  h.pitch_rad = Pitch(b);
  const Row3 gy = YawGradient(b);
  const Row3 gp = PitchGradient(b);
  h.yaw_sigma_rad = std::sqrt(gy * C * gy.transpose());
  h.pitch_sigma_rad = std::sqrt(gp * C * gp.transpose());
  return h;
}

}  // namespace statebench::est
