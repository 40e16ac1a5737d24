// Analytic truth for sensor tests: a vehicle at rest, and one driving a level circle at constant
// speed (exact velocity, centripetal acceleration and yaw rate).
#pragma once

#include <cmath>
#include <numbers>

#include "core/so3.hpp"
#include "core/truth.hpp"

namespace statebench::sensors::testing {

inline TruthSample StaticTruth(TimeNs t_ns, const Vec3& p_world = Vec3::Zero(), double yaw = 0.0) {
  TruthSample s;
  s.t_ns = t_ns;
  s.body.T_world_frame = SE3(so3::FromRollPitchYaw(0.0, 0.0, yaw), p_world);
  return s;
}

struct Circle {
  double radius_m = 20.0;
  double speed_mps = 5.0;
  double wheel_radius_m = 0.28;
  double wheelbase_m = 1.69;
  Vec3 centre = Vec3::Zero();

  // Counter-clockwise, starting at centre + (R, 0, 0) heading north.
  TruthSample At(TimeNs t_ns) const {
    const double w = speed_mps / radius_m;
    const double theta = w * ToSeconds(t_ns);
    const Vec3 radial(std::cos(theta), std::sin(theta), 0.0);
    const Vec3 tangent(-std::sin(theta), std::cos(theta), 0.0);
    TruthSample s;
    s.t_ns = t_ns;
    s.body.T_world_frame = SE3(so3::FromRollPitchYaw(0.0, 0.0, theta + std::numbers::pi / 2),
                               centre + radius_m * radial);
    s.body.v_world = speed_mps * tangent;
    s.body.a_world = -speed_mps * w * radial;
    s.body.omega_frame = Vec3(0.0, 0.0, w);
    s.steering_front_rad = std::atan(wheelbase_m / radius_m);
    s.wheel_omega_radps.fill(speed_mps / wheel_radius_m);
    s.distance_m = speed_mps * ToSeconds(t_ns);
    return s;
  }
};

}  // namespace statebench::sensors::testing
