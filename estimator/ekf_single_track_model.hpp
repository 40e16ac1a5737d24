// The EKF baseline's vehicle model: a single-track (bicycle) model in the plane, blended from the
// kinematic bicycle model at low speed (well posed at standstill) to the linear dynamic
// single-track model (cornering stiffnesses, mass, yaw inertia) above blend_high_speed_mps.
// State (8): x, y (m, ENU, body origin), yaw psi (rad), body-frame vx, vy (m/s), yaw rate r
// (rad/s), yaw gyro bias bg (rad/s), longitudinal accelerometer bias ba (m/s^2). Inputs: the
// longitudinal specific force at the IMU and the front road-wheel angle.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "core/eigen_types.hpp"
#include "core/time.hpp"
#include "estimator/ekf_options.hpp"

namespace statebench::est::ekf {

constexpr int kN = 8;
enum : int { kX = 0, kY, kPsi, kVx, kVy, kR, kBg, kBa };
using VecN = Eigen::Matrix<double, kN, 1>;
using MatN = Eigen::Matrix<double, kN, kN>;

class SingleTrackModel {
 public:
  // Without a steering encoder r is a random walk and vy relaxes to 0. `options` must outlive
  // the model.
  SingleTrackModel(const EkfOptions& options, const Vec3& p_body_imu, bool has_steering)
      : options_(options), p_body_imu_(p_body_imu), has_steering_(has_steering) {}

  // ds/dt for specific force ax (body x, at the IMU) and front road-wheel angle delta.
  VecN Derivative(const VecN& s, double ax, double delta) const;
  // d Derivative / ds by central differences.
  MatN DerivativeJacobian(const VecN& s, double ax, double delta) const;

 private:
  const EkfOptions& options_;
  Vec3 p_body_imu_;
  bool has_steering_;
};

// Rotation of the body frame in the world frame for the planar yaw psi (roll = pitch = 0).
inline Mat3 YawRotation(double psi) {
  return Eigen::AngleAxisd(psi, Vec3::UnitZ()).toRotationMatrix();
}

// The filter at one stamp with the inputs held from it on (the EKF's history for StateAt).
struct Snapshot {
  TimeNs t_ns = 0;
  VecN x = VecN::Zero();
  MatN P = MatN::Zero();
  double z = 0.0, Pz = 0.0;  // altitude, filtered apart
  double accel_x = 0.0, steering = 0.0;
};

}  // namespace statebench::est::ekf
