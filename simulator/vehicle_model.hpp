// Single-track (bicycle) vehicle model with tyre slip, front and rear steering, drive/brake
// force and grade, blended into the kinematic single-track model at low speed.
//
// Dynamic branch (heading frame: u forward, w left, r yaw rate, all horizontal):
//   alpha_f = delta_f - atan2(w + lf r, u),  alpha_r = delta_r - atan2(w - lr r, u)
//   F_y = mu F_z tanh(C alpha / (mu F_z))       (saturates at the friction limit)
//   F_z,f = m g lr / L - F h / L,  F_z,r = m g lf / L + F h / L   (longitudinal load transfer)
//   m (u' - r w) = sum of wheel forces along x - F_res(u) + m g_u
//   m (w' + r u) = sum of wheel forces along y + m g_w
//   Iz r'        = lf F_y,front(body) - lr F_y,rear(body)
// with the drive force F split over the axles by the drive layout (braking by static load),
// each axle force acting along its wheel, delta_r = -k delta_f, F_res rolling + aerodynamic
// resistance, and (g_u, g_w) the horizontal part of gravity along the slope,
// -g grad h / (1 + |grad h|^2), in the heading frame.
//
// Kinematic branch (no tyre slip; the lateral velocity along the car is linear in x):
//   tan(delta(x)) = A + B x,   A = (lr tan df + lf tan dr) / L,   B = (tan df - tan dr) / L,
//   w -> u A, r -> u B  (their time derivatives, plus a relaxation (u A - w) / tau so that
//   states coming from the dynamic branch converge to the no-slip values).
//
// The state derivative is lambda(u) dynamic + (1 - lambda(u)) kinematic with lambda a C2
// smootherstep from 0 below kinematic_below_mps to 1 above dynamic_above_mps: well-posed at
// standstill and in reverse (kinematic), accelerations continuous in time.
//
// Actuators are states: steering follows its command through a first-order lag with a smooth
// rate limit, d' = rate_max tanh((d_cmd - d) / (tau rate_max)); the force through a lag.
#pragma once

#include <array>
#include <memory>

#include "core/eigen_types.hpp"
#include "simulator/terrain.hpp"
#include "simulator/vehicle_params.hpp"
#include "simulator/vehicle_state.hpp"

namespace statebench::sim {

struct VehicleModelOptions {
  double kinematic_below_mps = 1.0;
  double dynamic_above_mps = 3.0;
  double relaxation_time_s = 0.05;
  double air_density_kgpm3 = 1.2;
};

// Wheel order in every per-wheel array: front left, front right, rear left, rear right.
class VehicleModel {
 public:
  VehicleModel(VehicleParams params, std::shared_ptr<const Terrain> terrain,
               VehicleModelOptions options = {});

  // Time derivative of the state under a command (held constant over an integration step or
  // given as a function of the state by the caller).
  VehicleState Derivative(const VehicleState& x, const VehicleCommand& command) const;
  // Same with the terrain gradient at (x.x_m, x.y_m) already evaluated by the caller.
  VehicleState Derivative(const VehicleState& x, const VehicleCommand& command,
                          const Vec2& terrain_gradient) const;

  double RearSteer(double front_steer_rad) const {
    return -params_.rear_steering_ratio * front_steer_rad;
  }
  // Kinematic curvature B of the path of the reference point (no lateral slip there).
  double KinematicCurvature(double front_steer_rad) const;
  // Front angle giving kinematic curvature kappa (inverse of KinematicCurvature), unclamped.
  double SteerForCurvature(double kappa_1pm) const;
  // x of the body point whose velocity has no lateral component in the kinematic limit:
  // the rear axle for front steering, the centre for symmetric 4-wheel steering.
  double ReferencePointX() const { return reference_x_m_; }
  // Ackermann road-wheel angle of each wheel for a front (bicycle) angle.
  std::array<double, 4> WheelAngles(double front_steer_rad) const;
  // Contact point of each wheel in the body frame (on the road plane, z = 0).
  const std::array<Vec3, 4>& WheelContacts() const { return wheel_contacts_; }

  double BlendWeight(double u_mps) const;
  // Rolling plus aerodynamic resistance at speed u (signed like u), N.
  double Resistance(double u_mps) const;
  // Horizontal part of gravity along the slope in the heading frame (forward, left), m/s^2,
  // for the terrain gradient at the vehicle.
  static Vec2 SlopeGravity(double yaw_rad, const Vec2& terrain_gradient);
  Vec2 SlopeGravity(const VehicleState& x) const;

  const VehicleParams& params() const { return params_; }
  const Terrain& terrain() const { return *terrain_; }
  const std::shared_ptr<const Terrain>& terrain_ptr() const { return terrain_; }
  const VehicleModelOptions& options() const { return options_; }

 private:
  VehicleParams params_;
  std::shared_ptr<const Terrain> terrain_;
  VehicleModelOptions options_;
  double reference_x_m_ = 0.0;
  std::array<Vec3, 4> wheel_contacts_;
};

}  // namespace statebench::sim
