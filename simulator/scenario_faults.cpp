#include "simulator/scenario_faults.hpp"

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

}  // namespace

bool SensorOutage::Covers(const std::string& sensor_id, TimeNs stamp_ns) const {
  const double t = ToSeconds(stamp_ns);
  if (t < start_s || t >= end_s) return false;
  for (const std::string& s : sensors) {
    if (s == sensor_id) return true;
  }
  return false;
}

ScenarioFaults ApplyFaults(const YamlNode& faults, sensors::SensorSetup* setup) {
  ScenarioFaults out;
  if (faults.IsNull()) return out;
  faults.ExpectMap();
  faults.ExpectOnlyKeys({"gnss_outages", "urban_canyon", "sensor_outages"});
  if (const auto outages = faults.Find("gnss_outages"); outages && !outages->IsNull()) {
    ApplyGnssOutages(*outages, setup);
  }
  if (const auto canyon = faults.Find("urban_canyon"); canyon && !canyon->IsNull()) {
    out.urban_canyon = ParseUrbanCanyon(*canyon);
  }
  if (const auto outages = faults.Find("sensor_outages"); outages && !outages->IsNull()) {
    out.sensor_outages = ParseSensorOutages(*outages, *setup);
  }
  return out;
}

}  // namespace statebench::sim
