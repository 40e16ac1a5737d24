// The `mismatch:` field of a scenario (docs/scenarios.md): how the vehicle the simulator drives
// differs from what the estimators are told, as a real vehicle differs from its datasheets and
// drawings (shared/REFERENCE.md, "Real units are not their datasheet").
//
//   mismatch:
//     imu_spread: 0.3                 # each unit's noise densities and bias random walks:
//                                     # datasheet x U(1 - s, 1 + s), per triad and quantity
//     gnss_covariance_scale: [0.5, 2.0]   # reported / true variance, log-uniform per receiver
//     gnss_slow_error_scale: [0.5, 2.0]   # the slow error's variance (gauss_markov fraction):
//                                         # the setup's x log-uniform, per receiver
//     mount_translation_sigma_m: 0.01     # each sensor's true mount: the setup's, moved by
//     mount_rotation_sigma_deg: 0.2       #   N(0, sigma) per axis (translation and rotation)
//     clock_offset_sigma_s: 0.003         # each non-IMU sensor's clock: N(0, sigma) off the IMU's
//     vehicle_mass_spread: 0.1            # the EKF's vehicle file: mass and yaw inertia x
//     vehicle_cornering_stiffness_spread: 0.2   # U(1 - s, 1 + s), each cornering stiffness too
//
// Every value is drawn from the scenario's seed (stream "mismatch"), so each Monte Carlo seed is
// another unit. The simulator uses the drawn (true) values; the estimators read the setup file as
// written (nominal values), and the EKF a copy of the vehicle file with the drawn parameters.
// Absent or null: no mismatch (the unit tests' scenarios).
#pragma once

#include "core/yaml_node.hpp"

namespace statebench::sim {

struct MismatchOptions {
  double imu_spread = 0.0;
  double gnss_covariance_scale_min = 1.0;
  double gnss_covariance_scale_max = 1.0;
  double gnss_slow_error_scale_min = 1.0;  // stream "mismatch_gnss_slow": the other draws stay
  double gnss_slow_error_scale_max = 1.0;
  double mount_translation_sigma_m = 0.0;
  double mount_rotation_sigma_deg = 0.0;
  double clock_offset_sigma_s = 0.0;
  double vehicle_mass_spread = 0.0;
  double vehicle_cornering_stiffness_spread = 0.0;
};

// Throws InputError "file:line:col: field 'mismatch.x': ..." on unknown keys or bad values.
MismatchOptions ParseMismatch(const YamlNode& node);

}  // namespace statebench::sim
