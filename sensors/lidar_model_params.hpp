// Everything the lidar simulator needs for one lidar of a setup: its beam pattern, range limits,
// errors and mounting. Built from the plain values a sensor-setup entry carries.
#pragma once

#include <optional>
#include <string>
#include <string_view>

#include "core/se3.hpp"
#include "core/time.hpp"
#include "sensors/lidar_beam_model.hpp"

namespace statebench::sensors {

struct LidarModelParams {
  std::string sensor_id;
  LidarBeamModel beams;
  double min_range_m = 0.5;
  double max_range_m = 120.0;
  double range_noise_sigma_m = 0.01;  // Gaussian, along the beam
  double dropout_probability = 0.0;   // per return
  // Range at which a 10 % Lambertian target at normal incidence is still detected; the limit for
  // reflectivity rho and incidence cosine c is this * sqrt(rho c / 0.1) (received power ~
  // rho c / r^2). <= 0 disables the limit (only max_range_m applies).
  double range_at_10pct_m = 0.0;
  SE3 T_body_lidar;
  TimeNs latency_ns = 0;  // arrival = end of the sweep + latency
};

// The values of a setup entry; unset fields take the model's datasheet defaults:
//   hesai_xt32:     0.5-120 m, sigma 0.01 m, 80 m at 10 % reflectivity
//   velodyne_vlp16: 0.5-100 m, sigma 0.03 m, no reflectivity limit (no datasheet figure)
struct LidarModelValues {
  std::string model;  // hesai_xt32 | velodyne_vlp16
  std::string sensor_id;
  SE3 T_body_lidar;
  std::optional<double> min_range_m;
  std::optional<double> max_range_m;
  std::optional<double> range_noise_sigma_m;
  std::optional<double> dropout_probability;
  std::optional<double> range_at_10pct_m;
  std::optional<double> rotation_rate_hz;  // 10 (default) or 20; columns scale as 1/rate
  double latency_s = 0.0;
};

// Throws InputError naming `where` (e.g. "setup.yaml: sensors[2]") and the field on bad values.
LidarModelParams MakeLidarModelParams(const LidarModelValues& values, std::string_view where);

}  // namespace statebench::sensors
