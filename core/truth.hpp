// Exact ground truth of the vehicle, sampled from the vehicle model state (never differentiated).
#pragma once

#include <array>

#include "core/eigen_types.hpp"
#include "core/se3.hpp"
#include "core/time.hpp"

namespace statebench {

// Kinematics of one rigid frame: pose, velocities and accelerations.
struct FrameKinematics {
  SE3 T_world_frame;
  Vec3 v_world = Vec3::Zero();      // m/s
  Vec3 a_world = Vec3::Zero();      // m/s^2 (kinematic, gravity not included)
  Vec3 omega_frame = Vec3::Zero();  // rad/s, in the frame itself
  Vec3 alpha_frame = Vec3::Zero();  // rad/s^2, in the frame itself

  // Specific force an accelerometer at this frame measures: R^T (a - g).
  Vec3 SpecificForce() const;
  Vec3 VelocityInFrame() const { return T_world_frame.rotation().conjugate() * v_world; }

  // Exact kinematics of a frame rigidly mounted at T_frame_mount (lever-arm terms included):
  //   v_m = v + R (w x r),  a_m = a + R (alpha x r + w x (w x r)).
  FrameKinematics AtMount(const SE3& T_frame_mount) const;
};

// Vehicle body frame: FLU, origin on the road surface below the centre of gravity.
struct TruthSample {
  TimeNs t_ns = 0;
  FrameKinematics body;
  double steering_front_rad = 0.0;  // bicycle-equivalent road-wheel angle, positive left
  double steering_rear_rad = 0.0;   // zero for front-steered vehicles
  std::array<double, 4> wheel_omega_radps{};  // FL, FR, RL, RR
  double sideslip_rad = 0.0;        // atan2(v_y, v_x) of the body origin, in the body frame
  double distance_m = 0.0;          // path length travelled by the body origin
};

}  // namespace statebench
