#include "sensors/sensor_mounts.hpp"

#include "core/csv.hpp"
#include "core/transform_config.hpp"
#include "core/yaml_node.hpp"

namespace statebench::sensors {
std::vector<SensorMount> ReadSensorMounts(const std::filesystem::path& setup_file) {
  const YamlNode root = YamlNode::LoadFile(setup_file);
  root.ExpectMap();
  const YamlNode list = root["sensors"];
  list.ExpectSequence();
  std::vector<SensorMount> out;
  for (std::size_t i = 0; i < list.size(); ++i) {
    const YamlNode entry = list.At(i);
    entry.ExpectMap();
    SensorMount m;
    m.type = entry.Get<std::string>("type");
    m.id = entry.Get<std::string>("id");
    m.T_body_sensor = ParseTransform(entry["T_body_sensor"]);
    if (const auto l = entry.Find("latency_s"); l && !l->IsNull()) m.latency_s = l->As<double>();
    if (const auto e = entry.Find("estimator"); e && !e->IsNull()) {
      e->ExpectMap();
      m.estimator = e->FlowText();
    }
    out.push_back(std::move(m));
  }
  return out;
}

std::string SensorMountsYaml(const std::string& name, const std::vector<SensorMount>& mounts,
                             const std::string& header_comment) {
  std::string y = header_comment;
  y += "name: " + YamlQuoted(name) + "\nsensors:" + (mounts.empty() ? " []\n" : "\n");
  for (const SensorMount& m : mounts) {
    if (!m.comment.empty()) y += "  # " + m.comment + "\n";
    y += "  - type: " + m.type + "\n    id: " + YamlQuoted(m.id) + "\n";
    y += "    T_body_sensor: " + TransformYaml(m.T_body_sensor) + "\n";
    if (m.latency_s) y += "    latency_s: " + NumberText(*m.latency_s) + "\n";
    if (!m.estimator.empty()) y += "    estimator: " + m.estimator + "\n";
  }
  return y;
}

}  // namespace statebench::sensors
