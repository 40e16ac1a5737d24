// Longitudinal controller: tracks SUMO's speed profile along the path.
//
//   a_cmd = a_ref + k_v (v_ref - u) + k_s clamp(s_ref - s, +-e_max)     (feed-forward + PD)
// limited to [-a_dec, a_acc], to k_v (v_max - u) from above, and from below to -u / tau_stop:
// braking fades out as the vehicle comes to rest (it stops with zero deceleration, as a
// careful driver does, instead of jerking to a halt) and it never reverses. The drive force
// adds the resistances and the slope, F_cmd = m a_cmd + F_res(u) - m g_u, so that the
// model's u' follows a_cmd after the actuator lag.
#pragma once

#include "simulator/vehicle_model.hpp"

namespace statebench::sim {

struct SpeedControllerOptions {
  double speed_gain_1ps = 1.0;         // k_v
  double distance_gain_1ps2 = 0.25;    // k_s
  double max_distance_error_m = 3.0;   // e_max
  double stop_time_constant_s = 0.35;  // tau_stop, >= 4 x the drive lag for no overshoot
};

// Reference along the smoothed path (already mapped from SUMO's arc length).
struct SpeedReference {
  double s_m = 0.0;
  double v_mps = 0.0;
  double a_mps2 = 0.0;
};

class SpeedController {
 public:
  explicit SpeedController(SpeedControllerOptions options = {}) : options_(options) {}

  // Drive/brake force command for the vehicle at `x` whose body origin is at path arc length
  // s_m, with slope_gravity_u_mps2 the forward component of VehicleModel::SlopeGravity.
  double ForceCommand(const VehicleModel& model, const VehicleState& x, double s_m,
                      const SpeedReference& reference, double slope_gravity_u_mps2) const;

 private:
  SpeedControllerOptions options_;
};

}  // namespace statebench::sim
