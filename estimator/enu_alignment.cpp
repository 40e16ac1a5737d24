#include "estimator/enu_alignment.hpp"

#include <algorithm>
#include <cmath>

#include "core/state.hpp"

namespace statebench::est {

void EnuAlignment::Add(TimeNs t_ns, const Vec3& p_local, const Vec3& p_enu,
                       const Mat3& covariance_enu) {
  pairs_.push_back({t_ns, p_local, p_enu, 0.5 * (covariance_enu(0, 0) + covariance_enu(1, 1)),
                    covariance_enu(2, 2)});
  while (pairs_.front().t_ns < t_ns - FromSeconds(kHistoryS)) pairs_.pop_front();
}

std::optional<EnuAlignment::Result> EnuAlignment::Solve() const {
  const int n = size();
  if (n < kMinFixes) return std::nullopt;
  Vec3 a = Vec3::Zero(), b = Vec3::Zero();
  double reported_h = 0.0, reported_v = 0.0;
  for (const Pair& p : pairs_) {
    a += p.p_local;
    b += p.p_enu;
    reported_h += p.variance_h;
    reported_v += p.variance_v;
  }
  a /= n;
  b /= n;
  reported_h /= n;
  reported_v /= n;
  double dot = 0.0, cross = 0.0, spread = 0.0, span = 0.0;
  for (const Pair& p : pairs_) {
    const Vec2 d = (p.p_local - a).head<2>();
    const Vec2 e = (p.p_enu - b).head<2>();
    dot += d.dot(e);
    cross += d.x() * e.y() - d.y() * e.x();
    spread += d.squaredNorm();
    span = std::max(span, d.norm());
  }
  if (!(spread > 0.0)) return std::nullopt;
  Result r;
  r.yaw_rad = std::atan2(cross, dot);
  const Eigen::Rotation2Dd R(r.yaw_rad);
  double residual_h = 0.0, residual_v = 0.0;
  const double dz = b.z() - a.z();
  for (const Pair& p : pairs_) {
    residual_h += ((p.p_enu - b).head<2>() - R * (p.p_local - a).head<2>()).squaredNorm();
    const double rz = p.p_enu.z() - p.p_local.z() - dz;
    residual_v += rz * rz;
  }
  residual_h /= std::max(2 * n - 3, 1);
  residual_v /= std::max(n - 1, 1);
  r.residual_sigma_h_m = std::sqrt(residual_h);
  const double variance_h = std::max(reported_h, residual_h);
  r.sigma_h_m = std::sqrt(variance_h);
  r.yaw_sigma_rad = std::sqrt(variance_h / spread);
  r.translation.head<2>() = b.head<2>() - R * a.head<2>();
  r.translation.z() = dz;
  r.centroid_enu = b;
  const double sigma_b = std::sqrt(variance_h / n);
  r.centroid_sigma = Vec3(sigma_b, sigma_b, std::sqrt(std::max(reported_v, residual_v) / n));
  r.fixes = n;
  r.span_m = span;
  return r;
}

PropagatedState EnuAlignment::Result::Apply(const PropagatedState& local,
                                            double min_yaw_sigma_rad) const {
  const Quat q_yaw(Eigen::AngleAxisd(yaw_rad, Vec3::UnitZ()));
  const Mat3 R = q_yaw.toRotationMatrix();
  PropagatedState out = local;
  NavState& x = out.state;
  x.q_world_imu = (q_yaw * local.state.q_world_imu).normalized();
  x.p_world = R * local.state.p_world + translation;
  x.v_world = R * local.state.v_world;
  // Rotation error: right perturbation, unchanged by a rotation of the world; position and
  // velocity errors turn with the world.
  Mat15 A = Mat15::Identity();
  A.block<3, 3>(kPositionIndex, kPositionIndex) = R;
  A.block<3, 3>(kVelocityIndex, kVelocityIndex) = R;
  out.covariance = A * local.covariance * A.transpose();
  // The alignment's errors (yaw about the vertical, the centroid's x, y, z): a yaw error turns
  // the attitude (R^T z in the IMU frame), the position about the centroid and the velocity.
  const Vec3 z = Vec3::UnitZ();
  Eigen::Matrix<double, 15, 4> J = Eigen::Matrix<double, 15, 4>::Zero();
  J.block<3, 1>(kRotationIndex, 0) = x.q_world_imu.conjugate() * z;
  J.block<3, 1>(kPositionIndex, 0) = z.cross(x.p_world - centroid_enu);
  J.block<3, 1>(kVelocityIndex, 0) = z.cross(x.v_world);
  J.block<3, 3>(kPositionIndex, 1) = Mat3::Identity();
  const double yaw_sigma = std::max(yaw_sigma_rad, min_yaw_sigma_rad);
  const Vec4 variance(yaw_sigma * yaw_sigma, centroid_sigma.x() * centroid_sigma.x(),
                      centroid_sigma.y() * centroid_sigma.y(),
                      centroid_sigma.z() * centroid_sigma.z());
  out.covariance += J * variance.asDiagonal() * J.transpose();
  out.covariance = 0.5 * (out.covariance + out.covariance.transpose());
  return out;
}

}  // namespace statebench::est
