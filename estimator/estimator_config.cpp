#include "estimator/estimator_config.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <set>

#include "core/error.hpp"
#include "core/transform_config.hpp"
#include "estimator/factor_graph_option_table.hpp"

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

// The `estimator:` block of a sensor entry.
void ParseSensorOverrides(const YamlNode& node, SensorKind kind, EstimatorSensorSetup* setup,
                          GnssAntenna* antenna) {
  node.ExpectMap();
  if (kind == SensorKind::kImu) {
    ImuNoise noise;
    ImuNoiseOptionTable().Read(node, &noise);
    setup->imu_noise = noise;
  } else if (kind == SensorKind::kGnss) {
    GnssAntennaOptionTable().Read(node, antenna);
    const bool given[3] = {antenna->correlated_error_sigma_m > 0.0,
                           antenna->correlated_error_vertical_sigma_m > 0.0,
                           antenna->correlated_error_tau_s > 0.0};
    if (given[0] != given[1] || given[0] != given[2]) {
      node.Fail(
          "correlated_error_sigma_m, correlated_error_vertical_sigma_m and "
          "correlated_error_tau_s describe the receiver's slow error together: give all three "
          "above 0, or none");
    }
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
  ReadOptionalNumber(node, "latency_s", OptionRange::NonNegative(), &pair.latency_s);
  if ((pair.p_imu_aux - pair.p_imu_main).norm() < 0.1) {
    node["aux"].Fail("the antennas are less than 0.1 m apart");
  }
  setup->dual_antennas.push_back(pair);
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

LidarPriorSource ParseLidarPriorSource(const std::string& value) {
  if (value == "imu") return LidarPriorSource::kImu;
  if (value == "constant_velocity") return LidarPriorSource::kConstantVelocity;
  if (value == "gyro") return LidarPriorSource::kGyro;
  throw InputError("expected imu, constant_velocity or gyro, got '" + value + "'");
}

const char* LidarPriorSourceName(LidarPriorSource source) {
  switch (source) {
    case LidarPriorSource::kImu:
      return "imu";
    case LidarPriorSource::kConstantVelocity:
      return "constant_velocity";
    case LidarPriorSource::kGyro:
      return "gyro";
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

std::vector<std::string> EstimatorSensorSetup::PositionSensorIds() const {
  std::vector<std::string> ids;
  for (const GnssAntenna& a : antennas) ids.push_back(a.id);
  return ids;
}

double EstimatorSensorSetup::MaxMeasurementLatency() const {
  double latency = 0.0;
  for (const auto& s : sensors) {
    if (s.kind == SensorKind::kGnss || s.kind == SensorKind::kBodyVelocity) {
      latency = std::max(latency, s.latency_s);
    }
  }
  for (const auto& p : dual_antennas) latency = std::max(latency, p.latency_s);
  return latency;
}

double FactorGraphOptions::ReorderLatency(const EstimatorSensorSetup& setup) const {
  return reorder_latency_s.value_or(setup.MaxMeasurementLatency() + kReorderMarginS);
}

EstimatorSensorSetup RestrictToSensors(const EstimatorSensorSetup& setup,
                                       const std::vector<std::string>& ids) {
  const auto kept = [&ids](const std::string& id) {
    return std::find(ids.begin(), ids.end(), id) != ids.end();
  };
  for (const std::string& id : ids) {
    if (setup.Find(id) == nullptr && setup.FindHeading(id) == nullptr) {
      std::string known;
      for (const EstimatorSensor& s : setup.sensors) known += (known.empty() ? "" : ", ") + s.id;
      throw InputError("input '" + id + "' is not a sensor of the setup " + setup.source +
                       " (sensors: " + known + ")");
    }
  }
  if (!kept(setup.imu_id)) {
    throw InputError("the inputs must include the IMU '" + setup.imu_id + "' (setup " +
                     setup.source + ")");
  }
  EstimatorSensorSetup out = setup;
  out.sensors.clear();
  for (const EstimatorSensor& s : setup.sensors) {
    if (kept(s.id)) out.sensors.push_back(s);
  }
  out.antennas.clear();
  for (const GnssAntenna& a : setup.antennas) {
    if (kept(a.id)) out.antennas.push_back(a);
  }
  out.dual_antennas.clear();
  for (const DualAntennaPair& p : setup.dual_antennas) {
    const bool heading_kept =
        p.heading_id.empty() ? kept(p.main) && kept(p.aux) : kept(p.heading_id);
    if (heading_kept) out.dual_antennas.push_back(p);
  }
  return out;
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
    ReadOptionalNumber(entry, "latency_s", OptionRange::NonNegative(), &s.latency_s);
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
  if (!FactorGraphOptionTable().IsValid(*this, why)) return false;
  if (batch && lagged_output) {
    if (why != nullptr) *why = "factor graph options: batch and lagged_output exclude each other";
    return false;
  }
  return true;
}

FactorGraphOptions LoadFactorGraphOptions(const std::filesystem::path& path) {
  return ParseFactorGraphOptions(YamlNode::LoadFile(path));
}

FactorGraphOptions ParseFactorGraphOptions(const YamlNode& root) {
  FactorGraphOptions o;
  if (root.IsNull()) return o;  // an empty file: all defaults
  FactorGraphOptionTable().Read(root, &o);
  return o;
}

}  // namespace statebench::est
