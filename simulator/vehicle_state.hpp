// State of the planar vehicle model and the actuator commands that drive it.
//
// The planar states live in the horizontal (x, y) projection of the local ENU world; height,
// pitch and roll follow from the terrain (see body_kinematics.hpp). The body origin is the road
// point below the centre of gravity.
#pragma once

namespace statebench::sim {

struct VehicleState {
  double x_m = 0.0;             // body origin, east
  double y_m = 0.0;             // body origin, north
  double yaw_rad = 0.0;         // heading of the body x axis projected on the horizontal plane,
                                // counter-clockwise from east, not wrapped
  double u_mps = 0.0;           // horizontal velocity of the body origin along the heading
  double w_mps = 0.0;           // horizontal velocity of the body origin to the left
  double yaw_rate_radps = 0.0;  // d yaw / dt
  double steer_rad = 0.0;       // front road-wheel angle (bicycle), actuator state
  double force_n = 0.0;         // drive (+) / brake (-) force at the wheels, actuator state
  double distance_m = 0.0;      // 3D path length travelled by the body origin

  // x + h * dx, field by field (used by the RK4 integrator; dx holds time derivatives).
  VehicleState Plus(const VehicleState& dx, double h) const {
    return {x_m + h * dx.x_m,
            y_m + h * dx.y_m,
            yaw_rad + h * dx.yaw_rad,
            u_mps + h * dx.u_mps,
            w_mps + h * dx.w_mps,
            yaw_rate_radps + h * dx.yaw_rate_radps,
            steer_rad + h * dx.steer_rad,
            force_n + h * dx.force_n,
            distance_m + h * dx.distance_m};
  }
};

struct VehicleCommand {
  double steer_rad = 0.0;  // commanded front road-wheel angle
  double force_n = 0.0;    // commanded drive (+) / brake (-) force
};

}  // namespace statebench::sim
