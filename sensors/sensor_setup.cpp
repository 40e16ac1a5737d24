#include "sensors/sensor_setup.hpp"

#include <algorithm>
#include <array>
#include <set>
#include <sstream>

#include "core/transform_config.hpp"
#include "sensors/sensor_options_yaml.hpp"

namespace statebench::sensors {
namespace {

constexpr std::array<std::string_view, 6> kTypeNames = {
    "imu", "gnss", "wheel_encoders", "speed_encoder", "steering_encoder", "lidar"};

// Accepted rates per type; every rate must also divide the 1 kHz truth rate.
struct RateRange {
  double lo, hi;
};
constexpr std::array<RateRange, 6> kRateRanges = {{
    {50.0, 1000.0},  // imu
    {1.0, 20.0},     // gnss
    {10.0, 200.0},   // wheel encoders
    {10.0, 200.0},   // speed encoder
    {10.0, 200.0},   // steering encoder
    {5.0, 20.0},     // lidar
}};

std::string Num(double v) {
  std::ostringstream os;
  os << v;
  return os.str();
}

SensorType ParseType(const YamlNode& node) {
  const std::string name = node.As<std::string>();
  for (std::size_t i = 0; i < kTypeNames.size(); ++i) {
    if (kTypeNames[i] == name) return static_cast<SensorType>(i);
  }
  node.Fail("unknown sensor type '" + name +
            "' (expected one of: imu, gnss, wheel_encoders, speed_encoder, steering_encoder, "
            "lidar)");
}

SensorSpec ParseSpec(const YamlNode& entry, SensorType type) {
  SensorSpec spec;
  spec.id = entry.Get<std::string>("id");
  if (spec.id.empty()) entry["id"].Fail("must not be empty");
  const YamlNode rate = entry["rate_hz"];
  const RateRange range = kRateRanges[static_cast<int>(type)];
  spec.rate_hz = InRange(rate, range.lo, range.hi);
  if (!RateDividesTruthRate(spec.rate_hz)) {
    rate.Fail(Num(spec.rate_hz) +
              " Hz does not divide the 1000 Hz truth rate (1/rate must be a "
              "whole number of milliseconds)");
  }
  spec.T_body_sensor = ParseTransform(entry["T_body_sensor"]);
  spec.latency_s = InRange(entry["latency_s"], 0.0, 10.0);
  return spec;
}

SensorOptions ParseOptions(const YamlNode& entry, SensorType type) {
  switch (type) {
    case SensorType::kImu:
      return ParseImuOptions(entry);
    case SensorType::kGnss:
      return ParseGnssOptions(entry);
    case SensorType::kWheelEncoders:
      return ParseWheelEncoderOptions(entry);
    case SensorType::kSpeedEncoder:
      return ParseSpeedEncoderOptions(entry);
    case SensorType::kSteeringEncoder:
      return ParseSteeringEncoderOptions(entry);
    case SensorType::kLidar:
      return ParseLidarOptions(entry);
  }
  entry.Fail("unhandled sensor type");
}

DualAntennaHeadingOptions ParseDualAntenna(const YamlNode& node, const SensorSetup& setup) {
  node.ExpectOnlyKeys({"id", "main", "aux", "latency_s", "min_status"});
  DualAntennaHeadingOptions o;
  o.id = node.Get<std::string>("id");
  o.main_antenna = node.Get<std::string>("main");
  o.aux_antenna = node.Get<std::string>("aux");
  const SensorConfig* antennas[2] = {nullptr, nullptr};
  for (int i = 0; i < 2; ++i) {
    const YamlNode ref = node[i == 0 ? "main" : "aux"];
    antennas[i] = setup.Find(ref.As<std::string>());
    if (!antennas[i] || antennas[i]->type() != SensorType::kGnss) {
      ref.Fail("no gnss sensor with id '" + ref.As<std::string>() + "' in this setup");
    }
  }
  if (o.main_antenna == o.aux_antenna) node["aux"].Fail("must differ from main");
  if (antennas[0]->spec.PeriodNs() != antennas[1]->spec.PeriodNs()) {
    node["aux"].Fail("the two antennas must have the same rate_hz");
  }
  o.latency_s = node.Has("latency_s")
                    ? InRange(node["latency_s"], 0.0, 10.0)
                    : std::max(antennas[0]->spec.latency_s, antennas[1]->spec.latency_s);
  if (const auto status = node.Find("min_status")) {
    const auto mode = ParseGnssMode(status->As<std::string>());
    if (!mode) status->Fail("expected one of: rtk_fixed, rtk_float, single");
    o.min_status = ToFixStatus(*mode);
  }
  return o;
}

}  // namespace

std::string_view SensorTypeName(SensorType type) { return kTypeNames[static_cast<int>(type)]; }

const SensorConfig* SensorSetup::Find(std::string_view id) const {
  for (const auto& s : sensors) {
    if (s.spec.id == id) return &s;
  }
  return nullptr;
}

std::vector<const SensorConfig*> SensorSetup::OfType(SensorType type) const {
  std::vector<const SensorConfig*> out;
  for (const auto& s : sensors) {
    if (s.type() == type) out.push_back(&s);
  }
  return out;
}

SensorSetup LoadSensorSetup(const std::filesystem::path& path) {
  return ParseSensorSetup(YamlNode::LoadFile(path));
}

SensorSetup ParseSensorSetup(const YamlNode& root) {
  root.ExpectOnlyKeys({"name", "description", "sensors", "dual_antenna_headings"});
  SensorSetup setup;
  setup.source = root.source();
  setup.name = root.Get<std::string>("name");
  if (const auto d = root.Find("description")) d->As<std::string>();

  std::set<std::string> ids;
  const YamlNode list = root["sensors"];
  list.ExpectSequence();
  if (list.size() == 0) list.Fail("a setup needs at least one sensor");
  for (std::size_t i = 0; i < list.size(); ++i) {
    const YamlNode entry = list.At(i);
    entry.ExpectMap();
    const SensorType type = ParseType(entry["type"]);
    SensorConfig config{ParseSpec(entry, type), ParseOptions(entry, type), entry.Where()};
    if (!ids.insert(config.spec.id).second) {
      entry["id"].Fail("duplicate sensor id '" + config.spec.id + "'");
    }
    setup.sensors.push_back(std::move(config));
  }
  if (const auto pairs = root.Find("dual_antenna_headings")) {
    pairs->ExpectSequence();
    for (std::size_t i = 0; i < pairs->size(); ++i) {
      const YamlNode node = pairs->At(i);
      DualAntennaHeadingOptions o = ParseDualAntenna(node, setup);
      if (!ids.insert(o.id).second) node["id"].Fail("duplicate sensor id '" + o.id + "'");
      setup.dual_antenna_headings.push_back(std::move(o));
    }
  }
  return setup;
}

}  // namespace statebench::sensors
