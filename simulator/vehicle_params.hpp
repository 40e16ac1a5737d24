// Physical parameters of a simulated vehicle, read from scenarios/vehicles/*.yaml.
//
// Body frame: FLU (x forward, y left, z up), origin on the road surface below the centre of
// gravity (CG). The front axle is at x = +cg_to_front_axle_m, the rear axle at
// x = -cg_to_rear_axle_m. Angles are stored in radians (the YAML gives degrees where a human
// would think in degrees, and says so in the field name).
#pragma once

#include <filesystem>
#include <string>

#include "core/se3.hpp"
#include "core/yaml_node.hpp"

namespace statebench::sim {

enum class VehicleKind { kQuadricycle, kShuttle };
enum class DriveLayout { kFront, kAll };

struct VehicleBody {
  double length_m = 0.0;          // bumper to bumper
  double width_m = 0.0;           // without mirrors
  double height_m = 0.0;          // road to roof
  double front_overhang_m = 0.0;  // front axle to front bumper
};

struct VehicleParams {
  std::string name;
  VehicleKind kind = VehicleKind::kQuadricycle;

  double mass_kg = 0.0;             // including driver / nominal passengers
  double yaw_inertia_kgm2 = 0.0;    // about the vertical axis through the CG
  double cg_height_m = 0.0;         // CG above the road
  double cg_to_front_axle_m = 0.0;  // lf
  double cg_to_rear_axle_m = 0.0;   // lr
  double track_width_m = 0.0;       // lateral distance between left and right wheel contacts
  double wheel_radius_m = 0.0;      // rolling radius

  // Lateral tyre model: F_y = mu F_z tanh(C alpha / (mu F_z)), per axle (both tyres).
  double cornering_stiffness_front_npr = 0.0;  // N/rad
  double cornering_stiffness_rear_npr = 0.0;   // N/rad
  double friction_coefficient = 0.0;           // mu, tyre-road peak

  // Steering: front road-wheel angle (bicycle equivalent) follows its command through a
  // first-order lag with a smooth rate limit. Rear angle = -rear_steering_ratio * front angle
  // (counter-phase 4-wheel steering; 0 for a front-steered car).
  double max_steering_angle_rad = 0.0;
  double max_steering_rate_radps = 0.0;
  double steering_time_constant_s = 0.0;
  double rear_steering_ratio = 0.0;

  // Longitudinal: drive (+) / brake (-) force at the wheels follows its command with a lag.
  DriveLayout drive = DriveLayout::kFront;
  double drive_time_constant_s = 0.0;
  double max_acceleration_mps2 = 0.0;
  double max_deceleration_mps2 = 0.0;  // positive number
  double max_speed_mps = 0.0;
  double rolling_resistance_coefficient = 0.0;  // dimensionless, F = c m g
  double drag_area_m2 = 0.0;                    // Cd * frontal area

  VehicleBody body;
  SE3 T_body_imu;  // default IMU mount (a sensor setup may override it)

  double wheelbase_m() const { return cg_to_front_axle_m + cg_to_rear_axle_m; }
  // Distance from the front bumper back to the body origin (SUMO positions the front bumper).
  double front_bumper_to_origin_m() const { return cg_to_front_axle_m + body.front_overhang_m; }
  // Centre of the body box in the body frame (box from the road up to height_m).
  Vec3 body_box_center() const;
};

// Parses and validates the root map of a vehicle file; errors name file:line and the field.
VehicleParams LoadVehicleParams(const YamlNode& node);
VehicleParams LoadVehicleParamsFile(const std::filesystem::path& path);

const char* ToString(VehicleKind kind);
const char* ToString(DriveLayout drive);

}  // namespace statebench::sim
