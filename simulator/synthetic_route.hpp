// A synthetic urban-like drive without SUMO, for tests and benchmarks: a route polyline with
// right-angle corners (left and right turns), a hilly terrain with grade and cross slope, and
// a SUMO-like speed profile at 10 Hz (accelerate, cruise, slow for corners, stop and go).
//
// The profile imitates what SUMO hands over: at each 0.1 s step a constant acceleration, so
// s(t) and v(t) are piecewise quadratic / linear and a(t) is piecewise constant with jumps.
#pragma once

#include <vector>

#include "core/eigen_types.hpp"

namespace statebench::sim {

// One SUMO-like reference sample; between samples the acceleration is constant.
struct ReferenceSample {
  double t_s = 0.0;
  double s_m = 0.0;  // arc length of the body origin along the raw route polyline
  double v_mps = 0.0;
  double a_mps2 = 0.0;  // held until the next sample
};

struct SyntheticRouteOptions {
  double cruise_speed_mps = 8.0;
  double corner_speed_mps = 3.5;
  double corner_zone_m = 12.0;  // speed limit applies this far before and after a corner
  double acceleration_mps2 = 1.0;
  double deceleration_mps2 = 1.5;
  std::vector<double> stops_m = {200.0, 500.0};  // raw arc lengths where the car stops
  double stop_duration_s = 6.0;
  double start_s_m = 5.0;
  double duration_s = 120.0;  // the profile ends earlier if the route does
  bool hilly = true;          // false: flat ground at z = 0
};

struct SyntheticRoute {
  std::vector<Vec3> polyline;              // the ego's lane centre line (SUMO-like)
  std::vector<std::vector<Vec3>> network;  // lane shapes of the whole network
  std::vector<ReferenceSample> profile;    // every 0.1 s
};

SyntheticRoute MakeSyntheticRoute(const SyntheticRouteOptions& options = {});

// Reference at time t_s (constant acceleration between samples; held after the last one).
ReferenceSample SampleProfile(const std::vector<ReferenceSample>& profile, double t_s);

}  // namespace statebench::sim
