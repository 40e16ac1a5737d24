#include "simulator/scenario_faults.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

namespace statebench::sim {
namespace {

using sensors::GnssOptions;
using sensors::SensorConfig;
using sensors::SensorType;

// The receivers an outage entry names (all GNSS receivers when `sensors` is absent).
std::vector<GnssOptions*> TargetReceivers(const YamlNode& entry, sensors::SensorSetup* setup) {
  std::vector<GnssOptions*> targets;
  const auto ids = entry.Find("sensors");
  if (!ids || ids->IsNull()) {
    for (SensorConfig& c : setup->sensors) {
      if (c.type() == SensorType::kGnss) targets.push_back(&std::get<GnssOptions>(c.options));
    }
    if (targets.empty()) entry.Fail("the sensor setup has no GNSS receiver");
    return targets;
  }
  ids->ExpectSequence();
  for (std::size_t i = 0; i < ids->size(); ++i) {
    const YamlNode id_node = ids->At(i);
    const std::string id = id_node.As<std::string>();
    SensorConfig* found = nullptr;
    for (SensorConfig& c : setup->sensors) {
      if (c.spec.id == id) found = &c;
    }
    if (!found) id_node.Fail("no sensor '" + id + "' in setup '" + setup->name + "'");
    if (found->type() != SensorType::kGnss) id_node.Fail("'" + id + "' is not a GNSS receiver");
    targets.push_back(&std::get<GnssOptions>(found->options));
  }
  return targets;
}

void ApplyGnssOutages(const YamlNode& list, sensors::SensorSetup* setup) {
  list.ExpectSequence();
  for (std::size_t i = 0; i < list.size(); ++i) {
    const YamlNode entry = list.At(i);
    entry.ExpectOnlyKeys({"sensors", "start_s", "end_s"});
    sensors::GnssOutage outage;
    outage.start_s = entry.Get<double>("start_s");
    if (outage.start_s < 0.0) entry["start_s"].Fail("must be >= 0");
    outage.end_s = entry.Get<double>("end_s", std::numeric_limits<double>::infinity());
    if (!(outage.end_s > outage.start_s)) entry["end_s"].Fail("must be after start_s");
    for (GnssOptions* options : TargetReceivers(entry, setup)) {
      options->outages.push_back(outage);
    }
  }
}

std::optional<sensors::SkyViewOptions> ParseUrbanCanyon(const YamlNode& node) {
  if (node.IsScalar()) {
    return node.As<bool>() ? std::optional(sensors::SkyViewOptions{}) : std::nullopt;
  }
  node.ExpectMap();
  node.ExpectOnlyKeys({"elevation_mask_deg", "blocking_range_m"});
  sensors::SkyViewOptions sky;
  sky.elevation_mask_deg = node.Get<double>("elevation_mask_deg", sky.elevation_mask_deg);
  if (!(sky.elevation_mask_deg >= 0.0 && sky.elevation_mask_deg < 90.0)) {
    node["elevation_mask_deg"].Fail("must be in [0, 90)");
  }
  sky.blocking_range_m = node.Get<double>("blocking_range_m", sky.blocking_range_m);
  if (!(sky.blocking_range_m > 0.0)) node["blocking_range_m"].Fail("must be > 0");
  return sky;
}

std::vector<SensorOutage> ParseSensorOutages(const YamlNode& list,
                                             const sensors::SensorSetup& setup) {
  list.ExpectSequence();
  std::vector<SensorOutage> out;
  for (std::size_t i = 0; i < list.size(); ++i) {
    const YamlNode entry = list.At(i);
    entry.ExpectOnlyKeys({"sensors", "start_s", "end_s"});
    SensorOutage outage;
    const YamlNode ids = entry["sensors"];
    ids.ExpectSequence();
    if (ids.size() == 0) ids.Fail("name at least one sensor");
    for (std::size_t k = 0; k < ids.size(); ++k) {
      const YamlNode id_node = ids.At(k);
      const std::string id = id_node.As<std::string>();
      bool found = false;
      for (const SensorConfig& c : setup.sensors) found = found || c.spec.id == id;
      if (!found) id_node.Fail("no sensor '" + id + "' in setup '" + setup.name + "'");
      outage.sensors.push_back(id);
    }
    outage.start_s = entry.Get<double>("start_s");
    if (outage.start_s < 0.0) entry["start_s"].Fail("must be >= 0");
    outage.end_s = entry.Get<double>("end_s", std::numeric_limits<double>::infinity());
    if (!(outage.end_s > outage.start_s)) entry["end_s"].Fail("must be after start_s");
    out.push_back(outage);
  }
  return out;
}

// The Measurement variant index of what a sensor of the setup delivers.
std::size_t MeasurementIndexOf(SensorType type) {
  switch (type) {
    case SensorType::kImu:
      return Measurement(std::in_place_type<ImuSample>).index();
    case SensorType::kGnss:
      return Measurement(std::in_place_type<GnssFix>).index();
    case SensorType::kWheelEncoders:
      return Measurement(std::in_place_type<WheelSpeeds>).index();
    case SensorType::kSpeedEncoder:
      return Measurement(std::in_place_type<VehicleSpeed>).index();
    case SensorType::kSteeringEncoder:
      return Measurement(std::in_place_type<SteeringAngle>).index();
    case SensorType::kLidar:
      return Measurement(std::in_place_type<LidarScan>).index();
  }
  return 0;
}

// `value` of a non_finite fault: nan, inf, -inf or any number (1e300, 4.9e-324, ...).
double ParseFaultValue(const YamlNode& node) {
  const std::string s = node.As<std::string>();
  if (s == "nan" || s == ".nan" || s == ".NaN") return std::numeric_limits<double>::quiet_NaN();
  if (s == "inf" || s == ".inf" || s == "+inf") return std::numeric_limits<double>::infinity();
  if (s == "-inf" || s == "-.inf") return -std::numeric_limits<double>::infinity();
  return node.As<double>();
}

MeasurementFault ParseInjectedFault(const YamlNode& entry, const sensors::SensorSetup& setup) {
  entry.ExpectMap();
  entry.ExpectOnlyKeys({"type", "sensors", "start_s", "end_s", "value", "shift_s", "offset_m",
                        "sigma_m", "far_m", "accel_limit_mps2", "gyro_limit_radps"});
  MeasurementFault f;
  const std::string type = entry.Get<std::string>("type");
  if (!ParseMeasurementFaultKind(type, &f.kind) || f.kind == MeasurementFaultKind::kGap) {
    entry["type"].Fail("unknown fault type '" + type +
                       "' (non_finite, duplicate, stamps_backwards, clock_jump, gnss_jump, "
                       "gnss_overconfident, lidar_garbage, imu_saturation; a gap is a "
                       "sensor_outages entry)");
  }
  const std::vector<std::size_t> types = MeasurementFaultTypes(f.kind);
  const auto acts_on = [&types](const SensorConfig& c) {
    return types.empty() ||
           std::find(types.begin(), types.end(), MeasurementIndexOf(c.type())) != types.end();
  };
  if (const auto ids = entry.Find("sensors"); ids && !ids->IsNull()) {
    ids->ExpectSequence();
    if (ids->size() == 0) ids->Fail("name at least one sensor, or leave `sensors` out");
    for (std::size_t k = 0; k < ids->size(); ++k) {
      const YamlNode id_node = ids->At(k);
      const std::string id = id_node.As<std::string>();
      const SensorConfig* c = setup.Find(id);
      if (!c) id_node.Fail("no sensor '" + id + "' in setup '" + setup.name + "'");
      if (!acts_on(*c)) {
        id_node.Fail("a " + type + " fault does not apply to '" + id + "' (sensor type " +
                     std::string(sensors::SensorTypeName(c->type())) + ")");
      }
      f.sensors.push_back(id);
    }
  } else if (std::none_of(setup.sensors.begin(), setup.sensors.end(), acts_on)) {
    entry["type"].Fail("setup '" + setup.name + "' has no sensor a " + type + " fault applies to");
  }
  f.start_s = entry.Get<double>("start_s");
  if (f.start_s < 0.0) entry["start_s"].Fail("must be >= 0");
  f.end_s = entry.Get<double>("end_s", std::numeric_limits<double>::infinity());
  if (!(f.end_s > f.start_s)) entry["end_s"].Fail("must be after start_s");

  using K = MeasurementFaultKind;
  const auto allow = [&](const char* key, std::initializer_list<K> kinds) {
    if (!entry.Find(key)) return false;
    if (std::find(kinds.begin(), kinds.end(), f.kind) == kinds.end()) {
      entry[key].Fail(std::string("not an option of a ") + type + " fault");
    }
    return true;
  };
  f.value = std::numeric_limits<double>::quiet_NaN();
  if (allow("value", {K::kNonFinite})) f.value = ParseFaultValue(entry["value"]);
  if (allow("shift_s", {K::kStampsBackwards, K::kClockJump})) {
    f.shift_s = entry.Get<double>("shift_s");
    if (f.kind == K::kStampsBackwards && !(f.shift_s > 0.0)) entry["shift_s"].Fail("must be > 0");
    if (f.shift_s == 0.0) entry["shift_s"].Fail("must not be 0");
  }
  if (f.kind == K::kGnssOverconfident) f.offset_m = Vec3(20.0, 0.0, 0.0);
  if (allow("offset_m", {K::kGnssJump, K::kGnssOverconfident})) {
    f.offset_m = entry.Get<Vec3>("offset_m");
  }
  if (allow("sigma_m", {K::kGnssOverconfident})) {
    f.sigma_m = entry.Get<double>("sigma_m");
    if (!(f.sigma_m > 0.0)) entry["sigma_m"].Fail("must be > 0");
  }
  if (allow("far_m", {K::kLidarGarbage})) {
    f.far_m = entry.Get<double>("far_m");
    if (f.far_m < 0.0) entry["far_m"].Fail("must be >= 0 (0: every point at the origin)");
  }
  if (allow("accel_limit_mps2", {K::kImuSaturation})) {
    f.accel_limit_mps2 = entry.Get<double>("accel_limit_mps2");
    if (!(f.accel_limit_mps2 > 0.0)) entry["accel_limit_mps2"].Fail("must be > 0");
  }
  if (allow("gyro_limit_radps", {K::kImuSaturation})) {
    f.gyro_limit_radps = entry.Get<double>("gyro_limit_radps");
    if (!(f.gyro_limit_radps > 0.0)) entry["gyro_limit_radps"].Fail("must be > 0");
  }
  return f;
}

}  // namespace

bool SensorOutage::Covers(const std::string& sensor_id, TimeNs stamp_ns) const {
  const double t = ToSeconds(stamp_ns);
  if (t < start_s || t >= end_s) return false;
  for (const std::string& s : sensors) {
    if (s == sensor_id) return true;
  }
  return false;
}

std::vector<MeasurementFault> ScenarioFaults::StreamFaults() const {
  std::vector<MeasurementFault> out;
  for (const SensorOutage& o : sensor_outages) {
    MeasurementFault gap;
    gap.kind = MeasurementFaultKind::kGap;
    gap.sensors = o.sensors;
    gap.start_s = o.start_s;
    gap.end_s = o.end_s;
    out.push_back(gap);
  }
  out.insert(out.end(), injected.begin(), injected.end());
  return out;
}

ScenarioFaults ApplyFaults(const YamlNode& faults, sensors::SensorSetup* setup) {
  ScenarioFaults out;
  if (faults.IsNull()) return out;
  faults.ExpectMap();
  faults.ExpectOnlyKeys({"gnss_outages", "urban_canyon", "sensor_outages", "injected"});
  if (const auto outages = faults.Find("gnss_outages"); outages && !outages->IsNull()) {
    ApplyGnssOutages(*outages, setup);
  }
  if (const auto canyon = faults.Find("urban_canyon"); canyon && !canyon->IsNull()) {
    out.urban_canyon = ParseUrbanCanyon(*canyon);
  }
  if (const auto outages = faults.Find("sensor_outages"); outages && !outages->IsNull()) {
    out.sensor_outages = ParseSensorOutages(*outages, *setup);
  }
  if (const auto injected = faults.Find("injected"); injected && !injected->IsNull()) {
    injected->ExpectSequence();
    for (std::size_t i = 0; i < injected->size(); ++i) {
      out.injected.push_back(ParseInjectedFault(injected->At(i), *setup));
    }
  }
  return out;
}

}  // namespace statebench::sim
