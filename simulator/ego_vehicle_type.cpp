#include "simulator/ego_vehicle_type.hpp"

#include <algorithm>

#include "core/state.hpp"

namespace statebench::sim {

EgoVehicleType EgoVehicleTypeFor(const VehicleParams& vehicle) {
  EgoVehicleType type;
  type.length_m = vehicle.body.length_m;
  type.width_m = vehicle.body.width_m;
  type.height_m = vehicle.body.height_m;
  type.max_speed_mps = vehicle.max_speed_mps;
  type.max_accel_mps2 = vehicle.max_acceleration_mps2;
  type.max_decel_mps2 = vehicle.max_deceleration_mps2;
  type.emergency_decel_mps2 =
      std::max(vehicle.max_deceleration_mps2, vehicle.friction_coefficient * kGravity);
  return type;
}

}  // namespace statebench::sim
