#include "estimator/estimator_config.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <set>

#include "core/error.hpp"
#include "core/transform_config.hpp"

namespace statebench::est {
namespace {

constexpr std::array<std::pair<std::string_view, SensorKind>, 7> kKinds = {{
    {"imu", SensorKind::kImu},
    {"gnss", SensorKind::kGnss},
    {"wheel_encoders", SensorKind::kWheelEncoders},
    {"speed_encoder", SensorKind::kSpeedEncoder},
    {"steering_encoder", SensorKind::kSteeringEncoder},
    {"lidar", SensorKind::kLidar},
    {"body_velocity", SensorKind::kBodyVelocity},
}};

SensorKind ParseKind(const YamlNode& node) {
  const std::string name = node.As<std::string>();
  for (const auto& [n, kind] : kKinds) {
    if (n == name) return kind;
  }
  std::string names;
  for (const auto& [n, kind] : kKinds) names += (names.empty() ? "" : ", ") + std::string(n);
  node.Fail("unknown sensor type '" + name + "' (expected one of: " + names + ")");
}

double Positive(const YamlNode& node) {
  const double v = node.As<double>();
  if (!(v > 0.0) || !std::isfinite(v)) node.Fail("must be a positive number");
  return v;
}

double NonNegative(const YamlNode& node) {
  const double v = node.As<double>();
  if (!(v >= 0.0) || !std::isfinite(v)) node.Fail("must be a non-negative number");
  return v;
}

// Sets *value from node[key] when present, validated by check.
template <typename Check>
void Read(const YamlNode& node, const char* key, double* value, Check check) {
  if (const auto child = node.Find(key); child && !child->IsNull()) *value = check(*child);
}

void ReadInt(const YamlNode& node, const char* key, int min, int* value) {
  if (const auto child = node.Find(key); child && !child->IsNull()) {
    *value = child->As<int>();
    if (*value < min) child->Fail("must be at least " + std::to_string(min));
  }
}

ImuNoise ParseImuNoise(const YamlNode& node, ImuNoise noise) {
  node.ExpectMap();
  node.ExpectOnlyKeys({"gyro_noise_density", "accel_noise_density", "gyro_random_walk",
                       "accel_random_walk", "integration_density"});
  Read(node, "gyro_noise_density", &noise.gyro_noise_density, Positive);
  Read(node, "accel_noise_density", &noise.accel_noise_density, Positive);
  Read(node, "gyro_random_walk", &noise.gyro_random_walk, Positive);
  Read(node, "accel_random_walk", &noise.accel_random_walk, Positive);
  Read(node, "integration_density", &noise.integration_density, NonNegative);
  return noise;
}

RobustKernel ParseKernel(const YamlNode& node, RobustKernel kernel) {
  node.ExpectMap();
  node.ExpectOnlyKeys({"type", "scale"});
  if (const auto type = node.Find("type")) {
    try {
      kernel.type = ParseRobustKernelType(type->As<std::string>());
    } catch (const InputError& e) {
      type->Fail(e.what());
    }
  }
  Read(node, "scale", &kernel.scale, Positive);
  return kernel;
}

MeasurementGateOptions ParseGate(const YamlNode& node, MeasurementGateOptions o,
                                 const char* sigma_key) {
  node.ExpectMap();
  node.ExpectOnlyKeys({sigma_key, "gate_chi2", "gate_reset_s", "robust_kernel"});
  Read(node, sigma_key, &o.max_sigma, Positive);
  Read(node, "gate_chi2", &o.gate_chi2, Positive);
  Read(node, "gate_reset_s", &o.gate_reset_s, Positive);
  if (const auto k = node.Find("robust_kernel")) o.kernel = ParseKernel(*k, o.kernel);
  return o;
}

InitializationOptions ParseInitialization(const YamlNode& node, InitializationOptions o) {
  node.ExpectMap();
  node.ExpectOnlyKeys({"mode", "static_duration_s", "static_max_gyro_std_radps",
                       "static_max_accel_std_mps2", "course_min_distance_m", "roll_pitch_sigma_rad",
                       "moving_roll_pitch_sigma_rad", "course_yaw_sigma_rad",
                       "static_velocity_sigma_mps", "moving_velocity_sigma_mps",
                       "gyro_bias_sigma_radps", "accel_bias_sigma_mps2"});
  if (const auto mode = node.Find("mode")) {
    const std::string m = mode->As<std::string>();
    if (m == "auto") {
      o.mode = InitializationMode::kAuto;
    } else if (m == "static") {
      o.mode = InitializationMode::kStatic;
    } else if (m == "moving") {
      o.mode = InitializationMode::kMoving;
    } else {
      mode->Fail("unknown mode '" + m + "' (expected auto, static or moving)");
    }
  }
  Read(node, "static_duration_s", &o.static_duration_s, Positive);
  Read(node, "static_max_gyro_std_radps", &o.static_max_gyro_std_radps, Positive);
  Read(node, "static_max_accel_std_mps2", &o.static_max_accel_std_mps2, Positive);
  Read(node, "course_min_distance_m", &o.course_min_distance_m, Positive);
  Read(node, "roll_pitch_sigma_rad", &o.roll_pitch_sigma_rad, Positive);
  Read(node, "moving_roll_pitch_sigma_rad", &o.moving_roll_pitch_sigma_rad, Positive);
  Read(node, "course_yaw_sigma_rad", &o.course_yaw_sigma_rad, Positive);
  Read(node, "static_velocity_sigma_mps", &o.static_velocity_sigma_mps, Positive);
  Read(node, "moving_velocity_sigma_mps", &o.moving_velocity_sigma_mps, Positive);
  Read(node, "gyro_bias_sigma_radps", &o.gyro_bias_sigma_radps, Positive);
  Read(node, "accel_bias_sigma_mps2", &o.accel_bias_sigma_mps2, Positive);
  return o;
}

GeodeticPoint ParseOrigin(const YamlNode& node) {
  node.ExpectMap();
  node.ExpectOnlyKeys({"latitude_deg", "longitude_deg", "altitude_m"});
  GeodeticPoint p;
  p.latitude_deg = node.Get<double>("latitude_deg");
  p.longitude_deg = node.Get<double>("longitude_deg");
  p.altitude_m = node.Get<double>("altitude_m", 0.0);
  if (std::abs(p.latitude_deg) > 90.0) node["latitude_deg"].Fail("must be in [-90, 90]");
  if (std::abs(p.longitude_deg) > 180.0) node["longitude_deg"].Fail("must be in [-180, 180]");
  return p;
}

// The `estimator:` block of a sensor entry.
void ParseSensorOverrides(const YamlNode& node, SensorKind kind, EstimatorSensorSetup* setup,
                          GnssAntenna* antenna) {
  node.ExpectMap();
  if (kind == SensorKind::kImu) {
    setup->imu_noise = ParseImuNoise(node, ImuNoise{});
  } else if (kind == SensorKind::kGnss) {
    node.ExpectOnlyKeys({"covariance_scale", "min_sigma_m"});
    Read(node, "covariance_scale", &antenna->covariance_scale, Positive);
    Read(node, "min_sigma_m", &antenna->min_sigma_m, NonNegative);
  } else {
    node.Fail("no estimator overrides for this sensor type");
  }
}

void ParseDualAntenna(const YamlNode& node, EstimatorSensorSetup* setup) {
  node.ExpectMap();
  DualAntennaPair pair;
  pair.heading_id = node.Get<std::string>("id");
  if (pair.heading_id.empty()) node["id"].Fail("must not be empty");
  if (setup->Find(pair.heading_id) != nullptr || setup->FindHeading(pair.heading_id)) {
    node["id"].Fail("duplicate sensor id '" + pair.heading_id + "'");
  }
  for (const char* role : {"main", "aux"}) {
    const YamlNode ref = node[role];
    const GnssAntenna* antenna = setup->FindAntenna(ref.As<std::string>());
    if (antenna == nullptr) {
      ref.Fail("no gnss sensor with id '" + ref.As<std::string>() + "' in this setup");
    }
    (role[0] == 'm' ? pair.main : pair.aux) = antenna->id;
    (role[0] == 'm' ? pair.p_imu_main : pair.p_imu_aux) = antenna->p_imu_antenna;
  }
  if (pair.main == pair.aux) node["aux"].Fail("must differ from main");
  pair.latency_s = std::max(setup->Find(pair.main)->latency_s, setup->Find(pair.aux)->latency_s);
  Read(node, "latency_s", &pair.latency_s, NonNegative);
  if ((pair.p_imu_aux - pair.p_imu_main).norm() < 0.1) {
    node["aux"].Fail("the antennas are less than 0.1 m apart");
  }
  setup->dual_antennas.push_back(pair);
}

FactorUse ReadUse(const YamlNode& node, FactorUse use) {
  const auto n = node.Find("enabled");
  if (!n) return use;
  try {
    return ParseFactorUse(n->As<std::string>());
  } catch (const InputError& e) {
    n->Fail(e.what());
  }
  return use;
}

bool ReadBool(const YamlNode& node, const char* key, bool value) {
  const auto n = node.Find(key);
  if (!n) return value;
  const std::string v = n->As<std::string>();
  if (v == "true" || v == "on") return true;
  if (v == "false" || v == "off") return false;
  n->Fail("expected true or false, got '" + v + "'");
  return value;
}

LidarFactorOptions ParseLidar(const YamlNode& node, LidarFactorOptions o) {
  node.ExpectMap();
  node.ExpectOnlyKeys({"enabled", "min_range_m", "max_range_m", "voxel_size_m",
                       "max_points_per_voxel", "covariance_scale", "min_sigma_translation_m",
                       "min_sigma_rotation_rad", "robust_kernel", "max_prior_deviation_m"});
  o.use = ReadUse(node, o.use);
  Read(node, "min_range_m", &o.odometry.min_range_m, NonNegative);
  Read(node, "max_range_m", &o.odometry.max_range_m, Positive);
  Read(node, "voxel_size_m", &o.odometry.voxel_size_m, Positive);
  ReadInt(node, "max_points_per_voxel", 1, &o.odometry.max_points_per_voxel);
  Read(node, "covariance_scale", &o.covariance_scale, Positive);
  Read(node, "min_sigma_translation_m", &o.min_sigma_translation_m, Positive);
  Read(node, "min_sigma_rotation_rad", &o.min_sigma_rotation_rad, Positive);
  if (const auto k = node.Find("robust_kernel")) o.kernel = ParseKernel(*k, o.kernel);
  Read(node, "max_prior_deviation_m", &o.max_prior_deviation_m, Positive);
  if (o.odometry.max_range_m <= o.odometry.min_range_m) {
    node["max_range_m"].Fail("must exceed min_range_m");
  }
  return o;
}

KinematicFactorOptions ParseKinematic(const YamlNode& node, KinematicFactorOptions o) {
  node.ExpectMap();
  node.ExpectOnlyKeys({"enabled", "period_s", "speed_sigma_mps", "speed_scale_sigma",
                       "steering_sigma_rad", "lateral_sigma_mps", "slip_per_lateral_accel",
                       "vertical_sigma_mps",
                       "rear_steering_ratio", "max_gap_s"});
  o.use = ReadUse(node, o.use);
  Read(node, "period_s", &o.period_s, Positive);
  Read(node, "speed_sigma_mps", &o.speed_sigma_mps, Positive);
  Read(node, "speed_scale_sigma", &o.speed_scale_sigma, NonNegative);
  Read(node, "steering_sigma_rad", &o.steering_sigma_rad, Positive);
  Read(node, "lateral_sigma_mps", &o.lateral_sigma_mps, Positive);
  Read(node, "slip_per_lateral_accel", &o.slip_per_lateral_accel, NonNegative);
  Read(node, "vertical_sigma_mps", &o.vertical_sigma_mps, Positive);
  Read(node, "rear_steering_ratio", &o.rear_steering_ratio, NonNegative);
  Read(node, "max_gap_s", &o.max_gap_s, Positive);
  return o;
}

NonHolonomicOptions ParseNonHolonomic(const YamlNode& node, NonHolonomicOptions o) {
  node.ExpectMap();
  node.ExpectOnlyKeys({"enabled", "rate_hz", "slip_per_lateral_accel", "lateral_sigma_mps",
                       "vertical_sigma_mps"});
  o.enabled = ReadBool(node, "enabled", o.enabled);
  Read(node, "slip_per_lateral_accel", &o.slip_per_lateral_accel, NonNegative);
  Read(node, "rate_hz", &o.rate_hz, Positive);
  Read(node, "lateral_sigma_mps", &o.lateral_sigma_mps, Positive);
  Read(node, "vertical_sigma_mps", &o.vertical_sigma_mps, Positive);
  return o;
}

ZeroVelocityOptions ParseZeroVelocity(const YamlNode& node, ZeroVelocityOptions o) {
  node.ExpectMap();
  node.ExpectOnlyKeys({"enabled", "rate_hz", "window_s", "max_gyro_std_radps",
                       "max_accel_std_mps2", "max_encoder_speed_mps", "max_estimated_speed_mps",
                       "sigma_mps"});
  o.enabled = ReadBool(node, "enabled", o.enabled);
  Read(node, "rate_hz", &o.rate_hz, Positive);
  Read(node, "window_s", &o.window_s, Positive);
  Read(node, "max_gyro_std_radps", &o.max_gyro_std_radps, Positive);
  Read(node, "max_accel_std_mps2", &o.max_accel_std_mps2, Positive);
  Read(node, "max_encoder_speed_mps", &o.max_encoder_speed_mps, Positive);
  Read(node, "max_estimated_speed_mps", &o.max_estimated_speed_mps, Positive);
  Read(node, "sigma_mps", &o.sigma_mps, Positive);
  return o;
}

}  // namespace

FactorUse ParseFactorUse(const std::string& value) {
  if (value == "auto") return FactorUse::kAuto;
  if (value == "true" || value == "on") return FactorUse::kOn;
  if (value == "false" || value == "off") return FactorUse::kOff;
  throw InputError("expected auto, true or false, got '" + value + "'");
}

const char* FactorUseName(FactorUse use) {
  switch (use) {
    case FactorUse::kAuto:
      return "auto";
    case FactorUse::kOn:
      return "true";
    case FactorUse::kOff:
      return "false";
  }
  return "?";
}

const EstimatorSensor* EstimatorSensorSetup::Find(const std::string& id) const {
  for (const auto& s : sensors) {
    if (s.id == id) return &s;
  }
  return nullptr;
}

const GnssAntenna* EstimatorSensorSetup::FindAntenna(const std::string& id) const {
  for (const auto& a : antennas) {
    if (a.id == id) return &a;
  }
  return nullptr;
}

const DualAntennaPair* EstimatorSensorSetup::FindHeading(const std::string& heading_id) const {
  if (heading_id.empty()) return nullptr;
  for (const auto& p : dual_antennas) {
    if (p.heading_id == heading_id) return &p;
  }
  return nullptr;
}

double EstimatorSensorSetup::MaxMeasurementLatency() const {
  double latency = 0.0;
  for (const auto& s : sensors) {
    if (s.kind == SensorKind::kGnss) latency = std::max(latency, s.latency_s);
  }
  for (const auto& p : dual_antennas) latency = std::max(latency, p.latency_s);
  return latency;
}

double FactorGraphOptions::ReorderLatency(const EstimatorSensorSetup& setup) const {
  return reorder_latency_s.value_or(setup.MaxMeasurementLatency() + kReorderMarginS);
}

EstimatorSensorSetup LoadEstimatorSensorSetup(const std::filesystem::path& path) {
  return ParseEstimatorSensorSetup(YamlNode::LoadFile(path));
}

EstimatorSensorSetup ParseEstimatorSensorSetup(const YamlNode& root) {
  root.ExpectMap();
  EstimatorSensorSetup setup;
  setup.source = root.source();
  setup.name = root.Get<std::string>("name", "");
  const YamlNode list = root["sensors"];
  list.ExpectSequence();
  if (list.size() == 0) list.Fail("at least one sensor is required");

  // Pass 1: ids, kinds and mounts in the body frame (simulation parameters are not read).
  bool has_imu = false;
  std::vector<YamlNode> entries;
  for (std::size_t i = 0; i < list.size(); ++i) entries.push_back(list.At(i));
  for (const YamlNode& entry : entries) {
    entry.ExpectMap();
    EstimatorSensor s;
    s.kind = ParseKind(entry["type"]);
    s.id = entry.Get<std::string>("id");
    if (s.id.empty()) entry["id"].Fail("must not be empty");
    if (setup.Find(s.id) != nullptr) entry["id"].Fail("duplicate sensor id '" + s.id + "'");
    s.T_body_sensor = ParseTransform(entry["T_body_sensor"]);
    Read(entry, "latency_s", &s.latency_s, NonNegative);
    if (s.kind == SensorKind::kImu) {
      if (has_imu) entry["type"].Fail("a second imu (the estimator uses one)");
      has_imu = true;
      setup.imu_id = s.id;
      setup.T_body_imu = s.T_body_sensor;
    }
    setup.sensors.push_back(s);
  }
  if (!has_imu) list.Fail("no imu in the sensor setup (the estimator needs one)");

  // Pass 2: everything in the IMU frame, and the estimator overrides.
  const SE3 T_imu_body = setup.T_body_imu.Inverse();
  for (std::size_t i = 0; i < entries.size(); ++i) {
    EstimatorSensor& s = setup.sensors[i];
    s.T_imu_sensor = T_imu_body * s.T_body_sensor;
    GnssAntenna antenna;
    antenna.id = s.id;
    antenna.p_imu_antenna = s.T_imu_sensor.translation();
    if (const auto o = entries[i].Find("estimator")) {
      ParseSensorOverrides(*o, s.kind, &setup, &antenna);
    }
    if (s.kind == SensorKind::kGnss) setup.antennas.push_back(antenna);
  }

  if (const auto pairs = root.Find("dual_antenna_headings"); pairs && !pairs->IsNull()) {
    pairs->ExpectSequence();
    for (std::size_t i = 0; i < pairs->size(); ++i) ParseDualAntenna(pairs->At(i), &setup);
  } else if (setup.antennas.size() == 2 &&
             (setup.antennas[1].p_imu_antenna - setup.antennas[0].p_imu_antenna).norm() >= 0.1) {
    DualAntennaPair pair;
    pair.main = setup.antennas[0].id;
    pair.aux = setup.antennas[1].id;
    pair.p_imu_main = setup.antennas[0].p_imu_antenna;
    pair.p_imu_aux = setup.antennas[1].p_imu_antenna;
    setup.dual_antennas.push_back(pair);
  }
  return setup;
}

bool FactorGraphOptions::IsValid(std::string* why) const {
  const auto fail = [&](const std::string& message) {
    if (why != nullptr) *why = "factor graph options: " + message;
    return false;
  };
  const auto positive = [](double v) { return v > 0.0 && std::isfinite(v); };
  if (!positive(window_s)) return fail("window_s must be positive");
  if (imu_samples_per_state < 1) return fail("imu_samples_per_state must be at least 1");
  if (!positive(solve_interval_s)) return fail("solve_interval_s must be positive");
  if (reorder_latency_s && (!(*reorder_latency_s >= 0.0) || !std::isfinite(*reorder_latency_s))) {
    return fail("reorder_latency_s must be non-negative");
  }
  if (max_iterations < 1) return fail("max_iterations must be at least 1");
  if (num_threads < 1) return fail("num_threads must be at least 1");
  std::string noise_why;
  if (!imu_noise.IsValid(&noise_why)) return fail(noise_why);
  for (const MeasurementGateOptions* g : {&gnss, &heading}) {
    if (!positive(g->max_sigma) || !positive(g->gate_chi2) || !positive(g->gate_reset_s)) {
      return fail("gate thresholds must be positive");
    }
    if (g->kernel.type != RobustKernelType::kNone && !positive(g->kernel.scale)) {
      return fail("robust kernel scale must be positive");
    }
  }
  const InitializationOptions& i = initialization;
  for (double v : {i.static_duration_s, i.static_max_gyro_std_radps, i.static_max_accel_std_mps2,
                   i.course_min_distance_m, i.roll_pitch_sigma_rad, i.moving_roll_pitch_sigma_rad,
                   i.course_yaw_sigma_rad, i.static_velocity_sigma_mps, i.moving_velocity_sigma_mps,
                   i.gyro_bias_sigma_radps, i.accel_bias_sigma_mps2}) {
    if (!positive(v)) return fail("initialization values must be positive");
  }
  return true;
}

FactorGraphOptions LoadFactorGraphOptions(const std::filesystem::path& path) {
  return ParseFactorGraphOptions(YamlNode::LoadFile(path));
}

FactorGraphOptions ParseFactorGraphOptions(const YamlNode& root) {
  FactorGraphOptions o;
  if (root.IsNull()) return o;  // an empty file: all defaults
  root.ExpectMap();
  root.ExpectOnlyKeys({"name", "description", "window_s", "imu_samples_per_state",
                       "solve_interval_s", "reorder_latency_s", "max_iterations", "num_threads",
                       "origin", "imu_noise", "initialization", "gnss", "heading", "lidar",
                       "kinematic", "non_holonomic", "zero_velocity"});
  Read(root, "window_s", &o.window_s, Positive);
  ReadInt(root, "imu_samples_per_state", 1, &o.imu_samples_per_state);
  Read(root, "solve_interval_s", &o.solve_interval_s, Positive);
  if (const auto n = root.Find("reorder_latency_s"); n && !n->IsNull()) {
    if (n->IsScalar() && n->raw().as<std::string>() == "auto") {
      o.reorder_latency_s.reset();
    } else {
      o.reorder_latency_s = NonNegative(*n);
    }
  }
  ReadInt(root, "max_iterations", 1, &o.max_iterations);
  ReadInt(root, "num_threads", 1, &o.num_threads);
  if (const auto n = root.Find("origin"); n && !n->IsNull()) o.origin = ParseOrigin(*n);
  if (const auto n = root.Find("imu_noise")) o.imu_noise = ParseImuNoise(*n, o.imu_noise);
  if (const auto n = root.Find("initialization")) {
    o.initialization = ParseInitialization(*n, o.initialization);
  }
  if (const auto n = root.Find("gnss")) o.gnss = ParseGate(*n, o.gnss, "max_sigma_m");
  if (const auto n = root.Find("heading")) o.heading = ParseGate(*n, o.heading, "max_sigma_rad");
  if (const auto n = root.Find("lidar")) o.lidar = ParseLidar(*n, o.lidar);
  if (const auto n = root.Find("kinematic")) o.kinematic = ParseKinematic(*n, o.kinematic);
  if (const auto n = root.Find("non_holonomic")) {
    o.non_holonomic = ParseNonHolonomic(*n, o.non_holonomic);
  }
  if (const auto n = root.Find("zero_velocity")) {
    o.zero_velocity = ParseZeroVelocity(*n, o.zero_velocity);
  }
  std::string why;
  if (!o.IsValid(&why)) root.Fail(why);
  return o;
}

}  // namespace statebench::est
