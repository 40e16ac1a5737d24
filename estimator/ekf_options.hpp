// Options of the single-track EKF baseline (ekf_single_track.hpp): the vehicle parameters of the
// dynamic bicycle model, read from a vehicle file of scenarios/vehicles/*.yaml, and the filter's
// noise and gate settings (all with defaults).
//
// The vehicle file is parsed here (not through simulator/, which the estimator must not link):
// only the keys below are read, every other key of the file is ignored.
#pragma once

#include <filesystem>
#include <string>

#include "core/option_table.hpp"
#include "core/yaml_node.hpp"
#include "estimator/measurement_checks.hpp"

namespace statebench::est {

// Linear single-track (bicycle) model parameters; SI units.
struct SingleTrackParams {
  double mass_kg = 560.0;                        // mass_kg
  double yaw_inertia_kgm2 = 350.0;               // yaw_inertia_kgm2
  double cg_to_front_axle_m = 0.93;              // cg_to_front_axle_m (lf)
  double cg_to_rear_axle_m = 0.76;               // cg_to_rear_axle_m (lr)
  double cornering_stiffness_front_npr = 22000;  // cornering_stiffness_front_npr (N/rad, axle)
  double cornering_stiffness_rear_npr = 35000;   // cornering_stiffness_rear_npr
  double rear_steering_ratio = 0.0;              // rear road-wheel angle = -ratio * front angle

  double Wheelbase() const { return cg_to_front_axle_m + cg_to_rear_axle_m; }
  bool IsValid(std::string* why = nullptr) const;
};

struct EkfOptions {
  SingleTrackParams vehicle;
  // Below blend_low_speed_mps the lateral dynamics are the kinematic bicycle model (well posed at
  // standstill); above blend_high_speed_mps the dynamic single-track model; linear in between.
  double blend_low_speed_mps = 1.0;
  double blend_high_speed_mps = 3.0;
  double kinematic_time_constant_s = 0.1;  // vy and r relax to the kinematic values at this rate
  // Continuous process noise (white-noise densities).
  double accel_noise_density = 0.05;   // m/s^2/sqrt(Hz), longitudinal acceleration input
  double lateral_model_density = 0.3;  // m/s^2/sqrt(Hz), single-track vy model error
  double yaw_accel_density = 1.0;      // rad/s^2/sqrt(Hz), single-track r model error
  // Position random walk standing for what the planar model misses (non-linear tyres, grades,
  // encoder scale error). Measured on a simulated setup-1 drive (240 s) with 1.7 m white GNSS
  // noise added: 0.01 gave a pose NEES of 31 (3 dof, overconfident), 0.1 gives 2.3.
  double position_density = 0.1;    // m/sqrt(s)
  double gyro_bias_walk = 1e-4;     // rad/s^2/sqrt(Hz)
  double accel_bias_walk = 1e-3;    // m/s^3/sqrt(Hz)
  double altitude_density = 0.1;    // m/sqrt(s), random walk of the filtered altitude
  double gyro_sigma_radps = 0.005;  // yaw-rate measurement noise per IMU sample
  double speed_sigma_mps = 0.05;    // speed encoder noise
  // Initialisation (from GNSS course and encoder speed).
  double course_min_distance_m = 5.0;
  double course_max_yaw_sigma_rad = 0.15;  // wait for this GNSS course precision (chord)
  double init_yaw_sigma_rad = 0.1;         // slip, chord vs tangent; added to the GNSS part
  double init_speed_sigma_mps = 0.5;
  double init_gyro_bias_sigma_radps = 0.01;
  double init_accel_bias_sigma_mps2 = 0.1;
  // Sigmas reported for the components the filter does not estimate.
  double roll_pitch_sigma_rad = 0.05;
  double vertical_velocity_sigma_mps = 0.2;
  // Gates: reported GNSS uncertainty threshold (m, sqrt of the largest eigenvalue) and
  // chi-square gates (p = 0.999) on the innovations; a gate opens again after gate_reset_s of
  // rejections.
  double gnss_max_sigma_m = 5.0;           // horizontal
  double gnss_max_vertical_sigma_m = 5.0;  // above (or none): the fix's height is not used
  double gnss_gate_chi2 = 13.82;       // 2 dof (horizontal)
  double speed_gate_chi2 = 10.83;      // 1 dof: speed encoder, each body_velocity component
  double heading_max_sigma_rad = 0.2;  // dual-antenna heading threshold
  double heading_gate_chi2 = 10.83;    // 1 dof
  double gate_reset_s = 10.0;
  double max_delay_s = 1.0;  // older measurements (stamp behind the filter) are kTooOld
  double history_s = 2.0;    // StateAt() serves stamps this far behind the newest IMU sample
  ImuLimits imu_limits;      // saturated or implausible samples, gaps (measurement_checks.hpp)

  bool IsValid(std::string* why = nullptr) const;
};

// The filter options (every field of EkfOptions but `vehicle`, same names, all optional; unknown
// keys and invalid values are InputErrors naming file:line and field). The vehicle comes from the
// vehicle file (LoadSingleTrackParams).
EkfOptions LoadEkfOptions(const std::filesystem::path& path);
// The tables behind the parser, the validation and the docs' option table.
const OptionTable<EkfOptions>& EkfOptionTable();
const OptionTable<SingleTrackParams>& SingleTrackParamsTable();
EkfOptions ParseEkfOptions(const YamlNode& root);

// Reads the vehicle parameters of a vehicle file (scenarios/vehicles/*.yaml); missing required
// keys or invalid values are InputErrors naming file:line and field.
SingleTrackParams LoadSingleTrackParams(const std::filesystem::path& path);
SingleTrackParams ParseSingleTrackParams(const YamlNode& root);

}  // namespace statebench::est
