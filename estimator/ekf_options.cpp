#include "estimator/ekf_options.hpp"

#include <cmath>

namespace statebench::est {

namespace {

bool Fails(bool ok, const char* field, std::string* why) {
  if (!ok && why != nullptr) *why = field;
  return !ok;
}

bool Positive(double v) { return std::isfinite(v) && v > 0.0; }

}  // namespace

bool SingleTrackParams::IsValid(std::string* why) const {
  if (Fails(Positive(mass_kg), "mass_kg", why)) return false;
  if (Fails(Positive(yaw_inertia_kgm2), "yaw_inertia_kgm2", why)) return false;
  if (Fails(Positive(cg_to_front_axle_m), "cg_to_front_axle_m", why)) return false;
  if (Fails(Positive(cg_to_rear_axle_m), "cg_to_rear_axle_m", why)) return false;
  if (Fails(Positive(cornering_stiffness_front_npr), "cornering_stiffness_front_npr", why)) {
    return false;
  }
  if (Fails(Positive(cornering_stiffness_rear_npr), "cornering_stiffness_rear_npr", why)) {
    return false;
  }
  if (Fails(std::isfinite(rear_steering_ratio) && std::abs(rear_steering_ratio) <= 1.0,
            "rear_steering_ratio", why)) {
    return false;
  }
  return true;
}

bool EkfOptions::IsValid(std::string* why) const {
  std::string vehicle_why;
  if (!vehicle.IsValid(&vehicle_why)) {
    if (why != nullptr) *why = "vehicle." + vehicle_why;
    return false;
  }
  const std::pair<double, const char*> positive[] = {
      {blend_low_speed_mps, "blend_low_speed_mps"},
      {kinematic_time_constant_s, "kinematic_time_constant_s"},
      {accel_noise_density, "accel_noise_density"},
      {lateral_model_density, "lateral_model_density"},
      {yaw_accel_density, "yaw_accel_density"},
      {position_density, "position_density"},
      {gyro_bias_walk, "gyro_bias_walk"},
      {accel_bias_walk, "accel_bias_walk"},
      {altitude_density, "altitude_density"},
      {gyro_sigma_radps, "gyro_sigma_radps"},
      {speed_sigma_mps, "speed_sigma_mps"},
      {course_min_distance_m, "course_min_distance_m"},
      {course_max_yaw_sigma_rad, "course_max_yaw_sigma_rad"},
      {init_yaw_sigma_rad, "init_yaw_sigma_rad"},
      {init_speed_sigma_mps, "init_speed_sigma_mps"},
      {init_gyro_bias_sigma_radps, "init_gyro_bias_sigma_radps"},
      {init_accel_bias_sigma_mps2, "init_accel_bias_sigma_mps2"},
      {roll_pitch_sigma_rad, "roll_pitch_sigma_rad"},
      {vertical_velocity_sigma_mps, "vertical_velocity_sigma_mps"},
      {gnss_max_sigma_m, "gnss_max_sigma_m"},
      {gnss_gate_chi2, "gnss_gate_chi2"},
      {speed_gate_chi2, "speed_gate_chi2"},
      {heading_max_sigma_rad, "heading_max_sigma_rad"},
      {heading_gate_chi2, "heading_gate_chi2"},
      {gate_reset_s, "gate_reset_s"},
      {max_delay_s, "max_delay_s"},
      {history_s, "history_s"},
  };
  for (const auto& [value, field] : positive) {
    if (Fails(Positive(value), field, why)) return false;
  }
  if (Fails(blend_high_speed_mps > blend_low_speed_mps && std::isfinite(blend_high_speed_mps),
            "blend_high_speed_mps", why)) {
    return false;
  }
  return true;
}

namespace {

// Field name -> member, for the YAML parser.
struct EkfField {
  const char* name;
  double EkfOptions::*member;
};

constexpr EkfField kEkfFields[] = {
    {"blend_low_speed_mps", &EkfOptions::blend_low_speed_mps},
    {"blend_high_speed_mps", &EkfOptions::blend_high_speed_mps},
    {"kinematic_time_constant_s", &EkfOptions::kinematic_time_constant_s},
    {"accel_noise_density", &EkfOptions::accel_noise_density},
    {"lateral_model_density", &EkfOptions::lateral_model_density},
    {"yaw_accel_density", &EkfOptions::yaw_accel_density},
    {"position_density", &EkfOptions::position_density},
    {"gyro_bias_walk", &EkfOptions::gyro_bias_walk},
    {"accel_bias_walk", &EkfOptions::accel_bias_walk},
    {"altitude_density", &EkfOptions::altitude_density},
    {"gyro_sigma_radps", &EkfOptions::gyro_sigma_radps},
    {"speed_sigma_mps", &EkfOptions::speed_sigma_mps},
    {"course_min_distance_m", &EkfOptions::course_min_distance_m},
    {"course_max_yaw_sigma_rad", &EkfOptions::course_max_yaw_sigma_rad},
    {"init_yaw_sigma_rad", &EkfOptions::init_yaw_sigma_rad},
    {"init_speed_sigma_mps", &EkfOptions::init_speed_sigma_mps},
    {"init_gyro_bias_sigma_radps", &EkfOptions::init_gyro_bias_sigma_radps},
    {"init_accel_bias_sigma_mps2", &EkfOptions::init_accel_bias_sigma_mps2},
    {"roll_pitch_sigma_rad", &EkfOptions::roll_pitch_sigma_rad},
    {"vertical_velocity_sigma_mps", &EkfOptions::vertical_velocity_sigma_mps},
    {"gnss_max_sigma_m", &EkfOptions::gnss_max_sigma_m},
    {"gnss_gate_chi2", &EkfOptions::gnss_gate_chi2},
    {"speed_gate_chi2", &EkfOptions::speed_gate_chi2},
    {"heading_max_sigma_rad", &EkfOptions::heading_max_sigma_rad},
    {"heading_gate_chi2", &EkfOptions::heading_gate_chi2},
    {"gate_reset_s", &EkfOptions::gate_reset_s},
    {"max_delay_s", &EkfOptions::max_delay_s},
    {"history_s", &EkfOptions::history_s},
};

}  // namespace

EkfOptions ParseEkfOptions(const YamlNode& root) {
  EkfOptions options;
  if (root.IsNull()) return options;
  root.ExpectMap();
  for (const std::string& key : root.Keys()) {
    const EkfField* field = nullptr;
    for (const EkfField& f : kEkfFields) {
      if (key == f.name) field = &f;
    }
    if (field == nullptr) root[key].Fail("unknown key");
    options.*(field->member) = root[key].As<double>();
  }
  std::string why;
  if (!options.IsValid(&why)) {
    const auto node = root.Find(why);
    if (node) node->Fail("invalid value");
    root.Fail("invalid combination of values ('" + why + "')");
  }
  return options;
}

EkfOptions LoadEkfOptions(const std::filesystem::path& path) {
  return ParseEkfOptions(YamlNode::LoadFile(path));
}

SingleTrackParams ParseSingleTrackParams(const YamlNode& root) {
  root.ExpectMap();
  SingleTrackParams p;
  const auto positive = [&](const char* key) {
    const YamlNode node = root[key];
    const double v = node.As<double>();
    if (!Positive(v)) node.Fail("must be a positive number");
    return v;
  };
  p.mass_kg = positive("mass_kg");
  p.yaw_inertia_kgm2 = positive("yaw_inertia_kgm2");
  p.cg_to_front_axle_m = positive("cg_to_front_axle_m");
  p.cg_to_rear_axle_m = positive("cg_to_rear_axle_m");
  p.cornering_stiffness_front_npr = positive("cornering_stiffness_front_npr");
  p.cornering_stiffness_rear_npr = positive("cornering_stiffness_rear_npr");
  if (const auto ratio = root.Find("rear_steering_ratio"); ratio && !ratio->IsNull()) {
    p.rear_steering_ratio = ratio->As<double>();
    if (!std::isfinite(p.rear_steering_ratio) || std::abs(p.rear_steering_ratio) > 1.0) {
      ratio->Fail("must be in [-1, 1]");
    }
  }
  return p;
}

SingleTrackParams LoadSingleTrackParams(const std::filesystem::path& path) {
  return ParseSingleTrackParams(YamlNode::LoadFile(path));
}

}  // namespace statebench::est
