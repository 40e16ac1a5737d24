#include "estimator/ekf_options.hpp"

#include <cmath>

namespace statebench::est {

namespace {

bool Positive(double v) { return std::isfinite(v) && v > 0.0; }

}  // namespace

const OptionTable<SingleTrackParams>& SingleTrackParamsTable() {
  static const OptionTable<SingleTrackParams> table = [] {
    using S = SingleTrackParams;
    const OptionRange p = OptionRange::Positive();
    OptionTable<S> t("vehicle");
    t.Number("mass_kg", &S::mass_kg, p, "mass")
        .Number("yaw_inertia_kgm2", &S::yaw_inertia_kgm2, p, "yaw moment of inertia")
        .Number("cg_to_front_axle_m", &S::cg_to_front_axle_m, p, "lf")
        .Number("cg_to_rear_axle_m", &S::cg_to_rear_axle_m, p, "lr")
        .Number("cornering_stiffness_front_npr", &S::cornering_stiffness_front_npr, p,
                "N/rad, front axle")
        .Number("cornering_stiffness_rear_npr", &S::cornering_stiffness_rear_npr, p,
                "N/rad, rear axle")
        .Number("rear_steering_ratio", &S::rear_steering_ratio, OptionRange::Closed(-1.0, 1.0),
                "rear road-wheel angle = -ratio x front angle");
    return t;
  }();
  return table;
}

const OptionTable<EkfOptions>& EkfOptionTable() {
  static const OptionTable<EkfOptions> table = [] {
    using E = EkfOptions;
    const OptionRange p = OptionRange::Positive();
    OptionTable<E> t("ekf options");
    t.Number("blend_low_speed_mps", &E::blend_low_speed_mps, p, "below: kinematic bicycle model")
        .Number("blend_high_speed_mps", &E::blend_high_speed_mps, p,
                "above: dynamic single-track model (linear blend between)")
        .Number("kinematic_time_constant_s", &E::kinematic_time_constant_s, p,
                "vy and r relax to the kinematic values at this rate")
        .Number("accel_noise_density", &E::accel_noise_density, p,
                "m/s^2/sqrt(Hz), longitudinal acceleration input")
        .Number("lateral_model_density", &E::lateral_model_density, p,
                "m/s^2/sqrt(Hz), single-track vy model error")
        .Number("yaw_accel_density", &E::yaw_accel_density, p,
                "rad/s^2/sqrt(Hz), single-track r model error")
        .Number("position_density", &E::position_density, p,
                "m/sqrt(s), position random walk for what the planar model misses")
        .Number("gyro_bias_walk", &E::gyro_bias_walk, p, "rad/s^2/sqrt(Hz)")
        .Number("accel_bias_walk", &E::accel_bias_walk, p, "m/s^3/sqrt(Hz)")
        .Number("altitude_density", &E::altitude_density, p, "m/sqrt(s), altitude random walk")
        .Number("gyro_sigma_radps", &E::gyro_sigma_radps, p, "yaw-rate noise per IMU sample")
        .Number("speed_sigma_mps", &E::speed_sigma_mps, p, "speed encoder noise")
        .Number("course_min_distance_m", &E::course_min_distance_m, p,
                "GNSS displacement of the course initialisation")
        .Number("course_max_yaw_sigma_rad", &E::course_max_yaw_sigma_rad, p,
                "wait for this GNSS course precision")
        .Number("init_yaw_sigma_rad", &E::init_yaw_sigma_rad, p, "added to the course sigma")
        .Number("init_speed_sigma_mps", &E::init_speed_sigma_mps, p, "initial speed sigma")
        .Number("init_gyro_bias_sigma_radps", &E::init_gyro_bias_sigma_radps, p, "prior")
        .Number("init_accel_bias_sigma_mps2", &E::init_accel_bias_sigma_mps2, p, "prior")
        .Number("roll_pitch_sigma_rad", &E::roll_pitch_sigma_rad, p, "reported, not estimated")
        .Number("vertical_velocity_sigma_mps", &E::vertical_velocity_sigma_mps, p,
                "reported, not estimated")
        .Number("gnss_max_sigma_m", &E::gnss_max_sigma_m, p,
                "reported GNSS sigma threshold (horizontal)")
        .Number("gnss_max_vertical_sigma_m", &E::gnss_max_vertical_sigma_m, p,
                "a fix with a larger (or no) vertical sigma updates the horizontal state only")
        .Number("gnss_gate_chi2", &E::gnss_gate_chi2, p, "2 dof (horizontal)")
        .Number("speed_gate_chi2", &E::speed_gate_chi2, p,
                "1 dof: the speed encoder and each body_velocity component")
        .Number("heading_max_sigma_rad", &E::heading_max_sigma_rad, p,
                "dual-antenna heading threshold")
        .Number("heading_gate_chi2", &E::heading_gate_chi2, p, "1 dof")
        .Number("gate_reset_s", &E::gate_reset_s, p, "a gate opens after this many s of rejections")
        .Number("max_delay_s", &E::max_delay_s, p, "older measurements are too old")
        .Number("history_s", &E::history_s, p, "StateAt() serves stamps this far back")
        .Section("imu_limits", &E::imu_limits, ImuLimitsOptionTable(),
                 "saturated or implausible IMU samples, and IMU gaps")
        .AddRule([](const E& o) -> std::optional<std::pair<std::string, std::string>> {
          if (o.blend_high_speed_mps > o.blend_low_speed_mps) return std::nullopt;
          return std::make_pair(std::string("blend_high_speed_mps"),
                                std::string("must exceed blend_low_speed_mps"));
        });
    return t;
  }();
  return table;
}

bool SingleTrackParams::IsValid(std::string* why) const {
  return SingleTrackParamsTable().IsValid(*this, why);
}

bool EkfOptions::IsValid(std::string* why) const {
  return SingleTrackParamsTable().IsValid(vehicle, why) && EkfOptionTable().IsValid(*this, why);
}

EkfOptions ParseEkfOptions(const YamlNode& root) {
  EkfOptions options;
  if (root.IsNull()) return options;
  EkfOptionTable().Read(root, &options);
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
