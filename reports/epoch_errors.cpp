#include "reports/epoch_errors.hpp"

#include <cmath>

#include "core/so3.hpp"

namespace statebench::reports {

PoseErrors ErrorsOf(const NavState& s, const ReferenceState& r) {
  PoseErrors e;
  e.dp_world = s.p_world - r.T_world_frame.translation();
  const Vec3 rpy_e = so3::ToRollPitchYaw(s.q_world_imu);
  const Vec3 rpy_r = so3::ToRollPitchYaw(r.T_world_frame.rotation());
  for (int i = 0; i < 3; ++i) e.drpy[i] = so3::WrapAngle(rpy_e[i] - rpy_r[i]);
  e.dtheta = so3::Log<double>(s.q_world_imu.conjugate() * r.T_world_frame.rotation());
  e.dv_own_frame = s.q_world_imu.conjugate() * s.v_world -
                   r.T_world_frame.rotation().conjugate() * r.v_world;
  e.dv_world = s.v_world - r.v_world;
  return e;
}

std::optional<std::pair<double, double>> PoseNees(const PoseErrors& e, const Mat6& p6) {
  if (!p6.allFinite() || !(p6.diagonal().minCoeff() > 0.0)) return std::nullopt;
  const Eigen::LDLT<Mat6> ldlt(p6);
  const Eigen::LDLT<Mat3> ldlt3(p6.bottomRightCorner<3, 3>());
  if (ldlt.info() != Eigen::Success || !ldlt.isPositive()) return std::nullopt;
  Vec6 e6;
  e6 << e.dtheta, -e.dp_world;
  const double nees = e6.dot(ldlt.solve(e6));
  const double nees_position = e.dp_world.dot(ldlt3.solve(e.dp_world));
  if (!std::isfinite(nees) || !std::isfinite(nees_position)) return std::nullopt;
  return std::make_pair(nees, nees_position);
}

EpochErrors EpochErrorsOf(const NavState& s, EstimateStatus status, const Mat6& pose_covariance,
                          const Mat3& velocity_covariance, const ReferenceState& r) {
  EpochErrors out;
  out.t_ns = s.t_ns;
  out.status = status;
  out.errors = ErrorsOf(s, r);
  // Along / across the reference's heading (its body x axis projected on the ground).
  const double yaw = so3::ToRollPitchYaw(r.T_world_frame.rotation()).z();
  const Vec3 along(std::cos(yaw), std::sin(yaw), 0.0), across(-std::sin(yaw), std::cos(yaw), 0.0);
  out.along_m = along.dot(out.errors.dp_world);
  out.across_m = across.dot(out.errors.dp_world);
  const Mat3 P_pos = pose_covariance.bottomRightCorner<3, 3>();
  const auto sigma = [](const Vec3& u, const Mat3& P) { return std::sqrt(std::max(0.0, u.dot(P * u))); };
  for (int i = 0; i < 3; ++i) out.sigma_world[i] = std::sqrt(std::max(0.0, P_pos(i, i)));
  out.sigma_along_m = sigma(along, P_pos);
  out.sigma_across_m = sigma(across, P_pos);
  // Yaw error ~ the world-z component of R dtheta (right perturbation in the IMU frame):
  // the third row of R.
  const Mat3 R = s.q_world_imu.toRotationMatrix();
  out.sigma_yaw_rad = sigma(R.row(2).transpose(), pose_covariance.topLeftCorner<3, 3>());
  // Roll and pitch (z-y-x angles) of a right perturbation d: roll' = d_x + sin(r) tan(p) d_y +
  // cos(r) tan(p) d_z, pitch' = cos(r) d_y - sin(r) d_z.
  const Vec3 rpy = so3::ToRollPitchYaw(s.q_world_imu);
  const double sr = std::sin(rpy.x()), cr = std::cos(rpy.x()), tp = std::tan(rpy.y());
  out.sigma_roll_rad = sigma(Vec3(1.0, sr * tp, cr * tp), pose_covariance.topLeftCorner<3, 3>());
  out.sigma_pitch_rad = sigma(Vec3(0.0, cr, -sr), pose_covariance.topLeftCorner<3, 3>());
  // Longitudinal velocity ~ the body x axis in the world dotted with v (attitude error neglected).
  out.sigma_v_longitudinal_mps = sigma(R.col(0), velocity_covariance);
  if (const auto nees = PoseNees(out.errors, pose_covariance)) {
    out.nees_pose = nees->first;
    out.nees_position = nees->second;
  }
  return out;
}

}  // namespace statebench::reports
