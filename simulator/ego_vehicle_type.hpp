// The ego's SUMO vType: its size and limits, filled by the run loop from the vehicle file
// (simulator/vehicle_params.hpp). SUMO drives it with sigma 0 and speed factor 1, so its speed
// profile is the car-following model's deterministic answer to lights, leaders and limits.
#pragma once

#include <string>

#include "simulator/vehicle_params.hpp"

namespace statebench::sim {

struct EgoVehicleType {
  double length_m = 2.34;
  double width_m = 1.24;
  double height_m = 1.45;
  double max_speed_mps = 12.5;
  double max_accel_mps2 = 2.0;
  double max_decel_mps2 = 4.0;        // comfortable braking used by the car-following model
  double emergency_decel_mps2 = 7.0;  // physical limit
  double min_gap_m = 2.0;             // standstill gap to the leader

  // False with a reason when a value is not positive or decelerations are inconsistent.
  bool IsValid(std::string* why) const {
    const auto fail = [&](const char* what) {
      if (why != nullptr) *why = what;
      return false;
    };
    if (!(length_m > 0 && width_m > 0 && height_m > 0)) return fail("dimensions must be positive");
    if (!(max_speed_mps > 0)) return fail("max_speed_mps must be positive");
    if (!(max_accel_mps2 > 0 && max_decel_mps2 > 0)) return fail("accel/decel must be positive");
    if (emergency_decel_mps2 < max_decel_mps2) return fail("emergency decel below max decel");
    if (!(min_gap_m >= 0)) return fail("min_gap_m must not be negative");
    return true;
  }
};

// The vType of a vehicle file: its body box, speed and acceleration limits; comfortable
// braking = its service-brake deceleration, emergency braking = mu * g (tyre limit).
EgoVehicleType EgoVehicleTypeFor(const VehicleParams& vehicle);

}  // namespace statebench::sim
