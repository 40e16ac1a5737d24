#include "sensors/log_manifest.hpp"

#include <fstream>
#include <set>

#include "core/csv.hpp"
#include "core/error.hpp"
#include "core/transform_config.hpp"
#include "core/yaml_node.hpp"

namespace statebench::sensors {
namespace {

// A relative path that stays inside the log directory.
std::string RelativeFile(const YamlNode& node) {
  const std::string file = node.As<std::string>();
  const std::filesystem::path p(file);
  if (file.empty() || p.is_absolute()) node.Fail("expected a path relative to the log directory");
  for (const auto& part : p) {
    if (part == "..") node.Fail("must stay inside the log directory");
  }
  return file;
}

}  // namespace

void WriteLogManifest(const std::filesystem::path& file, const LogManifest& m) {
  std::string y = "# StateBench recorded log (docs/log-format.md)\n";
  y += "format: statebench-log\nversion: " + std::to_string(m.version) + "\n";
  y += "scenario: " + YamlQuoted(m.scenario) + "\n";
  if (m.seed) y += "seed: " + std::to_string(*m.seed) + "\n";
  if (m.origin) {
    y += "origin: {latitude_deg: " + NumberText(m.origin->latitude_deg) +
         ", longitude_deg: " + NumberText(m.origin->longitude_deg) +
         ", altitude_m: " + NumberText(m.origin->altitude_m) + "}\n";
  }
  if (m.setup) y += "setup: " + YamlQuoted(*m.setup) + "\n";
  if (m.truth_csv) y += "truth: " + YamlQuoted(*m.truth_csv) + "\n";
  if (m.truth_imu_mount) y += "truth_imu_mount: " + TransformYaml(*m.truth_imu_mount) + "\n";
  y += "streams:\n";
  for (const LogStreamEntry& s : m.streams) {
    y += "  - {id: " + YamlQuoted(s.id) + ", type: " + std::string(LogStreamTypeName(s.type)) +
         ", file: " + YamlQuoted(s.file) + ", count: " + std::to_string(s.count) + "}\n";
  }
  std::ofstream out(file, std::ios::binary);
  out << y;
  out.close();
  if (!out) throw InputError(file.string() + ": cannot write the log manifest");
}

LogManifest ReadLogManifest(const std::filesystem::path& file) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(file, ec)) {
    throw InputError(file.string() + ": no log manifest (is this a StateBench log directory?)");
  }
  const YamlNode root = YamlNode::LoadFile(file);
  root.ExpectMap();
  root.ExpectOnlyKeys(
      {"format", "version", "scenario", "seed", "origin", "setup", "truth", "truth_imu_mount",
       "streams"});
  if (root.Get<std::string>("format") != "statebench-log") {
    root["format"].Fail("expected 'statebench-log'");
  }
  LogManifest m;
  m.version = root.Get<int>("version");
  if (m.version != kLogFormatVersion) {
    root["version"].Fail("unsupported version " + std::to_string(m.version) +
                         " (this reader: " + std::to_string(kLogFormatVersion) + ")");
  }
  m.scenario = root.Get<std::string>("scenario", "");
  if (root.Has("seed")) m.seed = root.Get<std::uint64_t>("seed");
  if (const auto origin = root.Find("origin"); origin && !origin->IsNull()) {
    origin->ExpectOnlyKeys({"latitude_deg", "longitude_deg", "altitude_m"});
    m.origin =
        GeodeticPoint{origin->Get<double>("latitude_deg"), origin->Get<double>("longitude_deg"),
                      origin->Get<double>("altitude_m", 0.0)};
  }
  if (const auto setup = root.Find("setup"); setup && !setup->IsNull()) {
    m.setup = RelativeFile(*setup);
  }
  if (const auto truth = root.Find("truth"); truth && !truth->IsNull()) {
    m.truth_csv = RelativeFile(*truth);
  }
  if (const auto mount = root.Find("truth_imu_mount"); mount && !mount->IsNull()) {
    m.truth_imu_mount = ParseTransform(*mount);
  }
  const YamlNode streams = root["streams"];
  streams.ExpectSequence();
  std::set<std::string> ids;
  for (std::size_t i = 0; i < streams.size(); ++i) {
    const YamlNode s = streams.At(i);
    s.ExpectOnlyKeys({"id", "type", "file", "count"});
    LogStreamEntry e;
    e.id = s.Get<std::string>("id");
    if (e.id.empty()) s["id"].Fail("must not be empty");
    if (!ids.insert(e.id).second) s["id"].Fail("duplicate stream id '" + e.id + "'");
    const auto type = ParseLogStreamType(s.Get<std::string>("type"));
    if (!type) {
      s["type"].Fail("unknown type '" + s.Get<std::string>("type") +
                     "' (expected imu, gnss, dual_antenna_heading, wheel_speeds, "
                     "vehicle_speed, steering_angle, lidar or body_velocity)");
    }
    e.type = *type;
    e.file = RelativeFile(s["file"]);
    e.count = static_cast<std::size_t>(s.Get<std::uint64_t>("count", 0));
    m.streams.push_back(std::move(e));
  }
  return m;
}

}  // namespace statebench::sensors
