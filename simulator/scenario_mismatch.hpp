// Applying a scenario's `mismatch:` (simulator/mismatch_options.hpp) to the simulated vehicle and
// writing the vehicle file the estimators are given.
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "simulator/mismatch_options.hpp"
#include "sensors/sensor_setup.hpp"
#include "simulator/scenario_faults.hpp"

namespace statebench::sim {


// What was drawn for one sensor (factors 1 and offsets 0 where the option is off).
struct SensorMismatch {
  std::string id;
  Vec3 mount_translation_m = Vec3::Zero();   // true minus nominal, body frame
  Vec3 mount_rotation_deg = Vec3::Zero();    // rotation vector, sensor frame
  double clock_offset_s = 0.0;               // non-IMU sensors: stamp minus true time
  double reported_covariance_scale = 1.0;    // GNSS receivers
  double slow_error_variance_factor = 1.0;   // GNSS receivers: gauss_markov fraction x this
  double gyro_noise_factor = 1.0, gyro_walk_factor = 1.0;    // the IMU
  double accel_noise_factor = 1.0, accel_walk_factor = 1.0;
};

struct VehicleMismatch {
  std::filesystem::path file;  // the vehicle file the estimators are given
  double mass_factor = 1.0;    // mass and yaw inertia
  double cornering_stiffness_front_factor = 1.0, cornering_stiffness_rear_factor = 1.0;
};


// Draws the mismatch of one run from `seed` and applies it to the simulator's setup (IMU noise,
// GNSS reported covariance, mounts) and to its stream faults (clock offsets, as clock jumps
// over the whole run). Returns what was drawn, for run.json.
std::vector<SensorMismatch> ApplyMismatch(const MismatchOptions& options, std::uint64_t seed,
                             sensors::SensorSetup* setup, ScenarioFaults* faults);

// Writes the vehicle file the estimators are given: `vehicle_file` with mass, yaw inertia and
// cornering stiffnesses drawn from `seed` (the same draws for the same seed); returns what was
// drawn. Without vehicle spreads the file is a plain copy.
VehicleMismatch WriteEstimatorVehicleFile(const MismatchOptions& options, std::uint64_t seed,
                                         const std::filesystem::path& vehicle_file,
                                         const std::filesystem::path& out);

}  // namespace statebench::sim
