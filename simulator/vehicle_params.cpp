#include "simulator/vehicle_params.hpp"

#include <cmath>
#include <numbers>
#include <sstream>

#include "core/state.hpp"
#include "core/transform_config.hpp"

namespace statebench::sim {
namespace {

constexpr double kDegToRad = std::numbers::pi / 180.0;

std::string Format(double v) {
  std::ostringstream os;
  os << v;
  return os.str();
}

// Reads node[key] as a number in (lo, hi] (lo excluded) or [lo, hi] (lo included).
double ReadNumber(const YamlNode& node, const std::string& key, double lo, double hi,
                  bool lo_included, const char* unit) {
  const YamlNode child = node[key];
  const double v = child.As<double>();
  const bool above = lo_included ? v >= lo : v > lo;
  if (!above || v > hi) {
    child.Fail("must be in " + std::string(lo_included ? "[" : "(") + Format(lo) + ", " +
               Format(hi) + "] " + unit + ", got " + Format(v));
  }
  return v;
}

double Positive(const YamlNode& node, const std::string& key, double hi, const char* unit) {
  return ReadNumber(node, key, 0.0, hi, false, unit);
}

VehicleKind ReadKind(const YamlNode& node) {
  const YamlNode child = node["kind"];
  const std::string s = child.As<std::string>();
  if (s == "quadricycle") return VehicleKind::kQuadricycle;
  if (s == "shuttle") return VehicleKind::kShuttle;
  child.Fail("unknown vehicle kind '" + s + "' (expected quadricycle or shuttle)");
}

DriveLayout ReadDrive(const YamlNode& node) {
  const YamlNode child = node["drive"];
  const std::string s = child.As<std::string>();
  if (s == "front") return DriveLayout::kFront;
  if (s == "all") return DriveLayout::kAll;
  child.Fail("unknown drive layout '" + s + "' (expected front or all)");
}

VehicleBody ReadBody(const YamlNode& node) {
  node.ExpectOnlyKeys({"length_m", "width_m", "height_m", "front_overhang_m"});
  VehicleBody b;
  b.length_m = Positive(node, "length_m", 20.0, "m");
  b.width_m = Positive(node, "width_m", 3.0, "m");
  b.height_m = Positive(node, "height_m", 5.0, "m");
  b.front_overhang_m = ReadNumber(node, "front_overhang_m", 0.0, 5.0, true, "m");
  return b;
}

// Cross-field checks: things no real vehicle can have.
void CheckConsistency(const YamlNode& node, const VehicleParams& p) {
  const double wheelbase = p.wheelbase_m();
  if (p.body.length_m < wheelbase + p.body.front_overhang_m) {
    node["body"]["length_m"].Fail("body length " + Format(p.body.length_m) +
                                  " m is shorter than wheelbase + front overhang (" +
                                  Format(wheelbase + p.body.front_overhang_m) + " m)");
  }
  if (p.track_width_m >= p.body.width_m) {
    node["track_width_m"].Fail("track width " + Format(p.track_width_m) +
                               " m must be smaller than the body width " + Format(p.body.width_m) +
                               " m");
  }
  if (p.cg_height_m >= p.body.height_m) {
    node["cg_height_m"].Fail("centre of gravity above the roof (body height " +
                             Format(p.body.height_m) + " m)");
  }
  if (p.wheel_radius_m * 2.0 >= p.body.height_m) {
    node["wheel_radius_m"].Fail("wheel diameter exceeds the body height");
  }
  // All the mass at the farthest corner of the body box bounds the yaw inertia.
  const double max_inertia =
      p.mass_kg * (p.body.length_m * p.body.length_m + p.body.width_m * p.body.width_m);
  if (p.yaw_inertia_kgm2 > max_inertia) {
    node["yaw_inertia_kgm2"].Fail("larger than mass * (length^2 + width^2) = " +
                                  Format(max_inertia) + " kg m^2, impossible for this body");
  }
  const double max_accel = p.friction_coefficient * kGravity;
  if (p.max_acceleration_mps2 > max_accel) {
    node["max_acceleration_mps2"].Fail("exceeds what the tyres allow (mu g = " + Format(max_accel) +
                                       " m/s^2)");
  }
  if (p.max_deceleration_mps2 > max_accel) {
    node["max_deceleration_mps2"].Fail("exceeds what the tyres allow (mu g = " + Format(max_accel) +
                                       " m/s^2)");
  }
  const double rear_angle = p.rear_steering_ratio * p.max_steering_angle_rad;
  if (std::abs(rear_angle) >= 1.2) {
    node["rear_steering_ratio"].Fail("rear wheel angle would exceed 69 deg");
  }
}

}  // namespace

Vec3 VehicleParams::body_box_center() const {
  return Vec3(front_bumper_to_origin_m() - 0.5 * body.length_m, 0.0, 0.5 * body.height_m);
}

VehicleParams LoadVehicleParams(const YamlNode& node) {
  node.ExpectOnlyKeys({"name",
                       "kind",
                       "mass_kg",
                       "yaw_inertia_kgm2",
                       "cg_height_m",
                       "cg_to_front_axle_m",
                       "cg_to_rear_axle_m",
                       "track_width_m",
                       "wheel_radius_m",
                       "cornering_stiffness_front_npr",
                       "cornering_stiffness_rear_npr",
                       "friction_coefficient",
                       "max_steering_angle_deg",
                       "max_steering_rate_degps",
                       "steering_time_constant_s",
                       "rear_steering_ratio",
                       "drive",
                       "drive_time_constant_s",
                       "max_acceleration_mps2",
                       "max_deceleration_mps2",
                       "max_speed_mps",
                       "rolling_resistance_coefficient",
                       "drag_area_m2",
                       "body",
                       "T_body_imu"});
  VehicleParams p;
  p.name = node.Get<std::string>("name");
  if (p.name.empty()) node["name"].Fail("must not be empty");
  p.kind = ReadKind(node);
  p.mass_kg = ReadNumber(node, "mass_kg", 50.0, 50000.0, true, "kg");
  p.yaw_inertia_kgm2 = Positive(node, "yaw_inertia_kgm2", 1e6, "kg m^2");
  p.cg_height_m = Positive(node, "cg_height_m", 3.0, "m");
  p.cg_to_front_axle_m = Positive(node, "cg_to_front_axle_m", 10.0, "m");
  p.cg_to_rear_axle_m = Positive(node, "cg_to_rear_axle_m", 10.0, "m");
  p.track_width_m = Positive(node, "track_width_m", 3.0, "m");
  p.wheel_radius_m = ReadNumber(node, "wheel_radius_m", 0.05, 1.5, true, "m");
  p.cornering_stiffness_front_npr = Positive(node, "cornering_stiffness_front_npr", 1e7, "N/rad");
  p.cornering_stiffness_rear_npr = Positive(node, "cornering_stiffness_rear_npr", 1e7, "N/rad");
  p.friction_coefficient = ReadNumber(node, "friction_coefficient", 0.05, 1.5, true, "");
  p.max_steering_angle_rad = Positive(node, "max_steering_angle_deg", 60.0, "deg") * kDegToRad;
  p.max_steering_rate_radps = Positive(node, "max_steering_rate_degps", 720.0, "deg/s") * kDegToRad;
  // The 1 kHz RK4 integration needs lags well above the 1 ms step.
  p.steering_time_constant_s = ReadNumber(node, "steering_time_constant_s", 0.01, 5.0, true, "s");
  p.rear_steering_ratio = ReadNumber(node, "rear_steering_ratio", 0.0, 1.0, true, "");
  p.drive = ReadDrive(node);
  p.drive_time_constant_s = ReadNumber(node, "drive_time_constant_s", 0.01, 5.0, true, "s");
  p.max_acceleration_mps2 = Positive(node, "max_acceleration_mps2", 15.0, "m/s^2");
  p.max_deceleration_mps2 = Positive(node, "max_deceleration_mps2", 15.0, "m/s^2");
  p.max_speed_mps = Positive(node, "max_speed_mps", 70.0, "m/s");
  p.rolling_resistance_coefficient =
      ReadNumber(node, "rolling_resistance_coefficient", 0.0, 0.1, true, "");
  p.drag_area_m2 = ReadNumber(node, "drag_area_m2", 0.0, 20.0, true, "m^2");
  p.body = ReadBody(node["body"]);
  p.T_body_imu = ParseTransform(node["T_body_imu"]);
  CheckConsistency(node, p);
  return p;
}

VehicleParams LoadVehicleParamsFile(const std::filesystem::path& path) {
  return LoadVehicleParams(YamlNode::LoadFile(path));
}

const char* ToString(VehicleKind kind) {
  return kind == VehicleKind::kQuadricycle ? "quadricycle" : "shuttle";
}

const char* ToString(DriveLayout drive) { return drive == DriveLayout::kFront ? "front" : "all"; }

}  // namespace statebench::sim
