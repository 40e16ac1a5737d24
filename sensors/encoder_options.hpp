// Error parameters of the vehicle encoders.
//
// Radius error e: the tyre's true rolling radius is (1 + e) times the nominal radius that the
// vehicle model (truth) and the estimator use, so for the same ground speed the wheel turns
// 1 / (1 + e) times as fast and an encoder read with the nominal radius under-reads by that
// factor.
#pragma once

#include <array>

namespace statebench::sensors {

// Four wheel-speed encoders (FL, FR, RL, RR). Each counts ticks of its wheel's angle; the speed
// of a sample is (ticks in the sample interval) * (2 pi / ticks_per_rev) / interval.
struct WheelEncoderOptions {
  int ticks_per_rev = 100;
  std::array<double, 4> radius_error{};
};

// A vehicle speed encoder at its mount (e.g. the rear-axle centre): counts ticks of the distance
// travelled along the mount's x axis; speed = ticks * distance_per_tick_m / interval (signed).
struct SpeedEncoderOptions {
  double distance_per_tick_m = 0.01;
  double radius_error = 0.0;
};

// Steering encoder: reads Q(delta + offset + noise), delta the front road-wheel angle
// (bicycle-equivalent), Q rounding to the resolution.
struct SteeringEncoderOptions {
  double resolution_rad = 0.0;  // 0 = continuous
  double offset_rad = 0.0;
  double noise_sigma_rad = 0.0;
};

}  // namespace statebench::sensors
