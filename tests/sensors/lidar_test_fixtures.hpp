// Shared fixtures of the lidar tests: bare worlds (no generated objects) and error-free lidars.
#pragma once

#include <string>

#include "sensors/lidar_model_params.hpp"
#include "sensors/world_layout.hpp"

namespace statebench::sensors::testing {

inline WorldLayoutOptions BareLayoutOptions() {
  WorldLayoutOptions o;
  o.kerbs.enabled = false;
  o.buildings.enabled = false;
  o.poles.spacing_m = 0.0;
  o.trees.spacing_m = 0.0;
  o.parked_cars.probability = 0.0;
  return o;
}

// A lidar with exact ranges: no noise, no dropout, no reflectivity limit.
inline LidarModelParams ExactLidar(const std::string& model) {
  LidarModelValues v;
  v.model = model;
  v.sensor_id = "lidar_test";
  v.range_noise_sigma_m = 0.0;
  v.dropout_probability = 0.0;
  v.range_at_10pct_m = 0.0;
  return MakeLidarModelParams(v, "test");
}

}  // namespace statebench::sensors::testing
