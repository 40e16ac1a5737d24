#include "simulator/speed_controller.hpp"

#include <algorithm>

namespace statebench::sim {

double SpeedController::ForceCommand(const VehicleModel& model, const VehicleState& x, double s_m,
                                     const SpeedReference& reference,
                                     double slope_gravity_u_mps2) const {
  const VehicleParams& p = model.params();
  const double u = x.u_mps;
  const double e_s = std::clamp(reference.s_m - s_m, -options_.max_distance_error_m,
                                options_.max_distance_error_m);
  double a = reference.a_mps2 + options_.speed_gain_1ps * (reference.v_mps - u) +
             options_.distance_gain_1ps2 * e_s;
  a = std::min({a, p.max_acceleration_mps2, options_.speed_gain_1ps * (p.max_speed_mps - u)});
  a = std::max({a, -p.max_deceleration_mps2, -u / options_.stop_time_constant_s});
  return p.mass_kg * (a - slope_gravity_u_mps2) + model.Resistance(u);
}

}  // namespace statebench::sim
