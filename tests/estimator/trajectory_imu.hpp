// What the analytic test trajectories (helix_trajectory.hpp, vehicle_trajectory.hpp, the car of
// imu_preintegration_accuracy_test.cpp) have in common: given a trajectory type with
// Orientation(t) (R_world_imu), Position(t), Velocity(t), Acceleration(t) (world, m, m/s, m/s^2)
// and Gyro(t) (IMU frame, rad/s), the specific force, the navigation state, noise-free IMU samples
// and the error of preintegrated deltas against the exact ones.
#pragma once

#include <algorithm>

#include "core/eigen_types.hpp"
#include "core/measurements.hpp"
#include "core/so3.hpp"
#include "core/state.hpp"
#include "core/time.hpp"
#include "estimator/imu_preintegration.hpp"

namespace statebench::est::testing {

// Specific force in the IMU frame: R^T (a - g).
template <typename Trajectory>
Vec3 SpecificForce(const Trajectory& trajectory, double t) {
  return trajectory.Orientation(t).conjugate() * (trajectory.Acceleration(t) - kGravityWorld);
}

template <typename Trajectory>
NavState StateOf(const Trajectory& trajectory, TimeNs t_ns) {
  const double t = ToSeconds(t_ns);
  NavState s;
  s.t_ns = t_ns;
  s.q_world_imu = trajectory.Orientation(t);
  s.p_world = trajectory.Position(t);
  s.v_world = trajectory.Velocity(t);
  return s;
}

// The IMU sample at t_ns, noise-free, with constant sensor biases added.
template <typename Trajectory>
ImuSample SampleOf(const Trajectory& trajectory, TimeNs t_ns, const Vec3& gyro_bias = Vec3::Zero(),
                   const Vec3& accel_bias = Vec3::Zero()) {
  ImuSample s;
  s.header.stamp_ns = t_ns;
  s.gyro = trajectory.Gyro(ToSeconds(t_ns)) + gyro_bias;
  s.accel = trajectory.Accel(ToSeconds(t_ns)) + accel_bias;
  return s;
}

struct DeltaErrors {
  double rotation = 0.0;  // rad
  double velocity = 0.0;  // m/s
  double position = 0.0;  // m
  double Max() const { return std::max({rotation, velocity, position}); }
};

// Difference between the preintegrated deltas and the exact deltas of the truth states at the
// interval's ends.
template <typename Trajectory>
DeltaErrors PreintegrationErrors(const Trajectory& trajectory, const ImuPreintegration& pim) {
  const NavState si = trajectory.State(pim.start_ns());
  const NavState sj = trajectory.State(pim.end_ns());
  const double dt = ToSeconds(sj.t_ns - si.t_ns);
  const Quat qi_inv = si.q_world_imu.conjugate();
  const Quat dq_true = qi_inv * sj.q_world_imu;
  const Vec3 dv_true = qi_inv * (sj.v_world - si.v_world - kGravityWorld * dt);
  const Vec3 dp_true =
      qi_inv * (sj.p_world - si.p_world - si.v_world * dt - 0.5 * kGravityWorld * dt * dt);
  DeltaErrors e;
  e.rotation = so3::Log<double>(dq_true.conjugate() * pim.delta_q()).norm();
  e.velocity = (pim.delta_v() - dv_true).norm();
  e.position = (pim.delta_p() - dp_true).norm();
  return e;
}

}  // namespace statebench::est::testing
