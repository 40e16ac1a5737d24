#include "sensors/rosbag_topic_map.hpp"

#include <algorithm>
#include <cmath>
#include <set>

#include "core/csv.hpp"
#include "core/error.hpp"
#include "core/transform_config.hpp"

namespace statebench::sensors {
namespace {

constexpr std::array<std::pair<std::string_view, RosTopicKind>, 8> kKinds = {{
    {"imu", RosTopicKind::kImu},
    {"gnss", RosTopicKind::kGnss},
    {"body_velocity", RosTopicKind::kBodyVelocity},
    {"speed_encoder", RosTopicKind::kSpeedEncoder},
    {"steering_encoder", RosTopicKind::kSteeringEncoder},
    {"wheel_encoders", RosTopicKind::kWheelEncoders},
    {"lidar", RosTopicKind::kLidar},
    {"gnss_velocity", RosTopicKind::kGnssVelocity},
}};

RosTopicKind ParseKind(const YamlNode& node) {
  const std::string name = node.As<std::string>();
  std::string names;
  for (const auto& [n, kind] : kKinds) {
    if (n == name) return kind;
    names += (names.empty() ? "" : ", ") + std::string(n);
  }
  node.Fail("unknown type '" + name + "' (expected one of: " + names + ")");
}

// Keys a topic entry of `kind` may have beyond topic, id, type, frame_id, T_body_sensor,
// latency_s, estimator.
std::vector<std::string_view> KindKeys(RosTopicKind kind) {
  switch (kind) {
    case RosTopicKind::kGnss:
      return {"position_sigma_m"};
    case RosTopicKind::kBodyVelocity:
      return {"twist_sigma"};
    case RosTopicKind::kSteeringEncoder:
      return {"joint"};
    case RosTopicKind::kWheelEncoders:
      return {"joints"};
    case RosTopicKind::kLidar:
      return {"time_field", "time_scale_s"};
    case RosTopicKind::kGnssVelocity:
      return {"velocity_sigma_mps"};
    default:
      return {};
  }
}

constexpr std::array<std::string_view, 7> kCommonTopicKeys = {
    "topic", "id", "type", "frame_id", "T_body_sensor", "latency_s", "estimator"};

void CheckKeys(const YamlNode& entry, RosTopicKind kind) {
  const std::vector<std::string_view> own = KindKeys(kind);
  for (const std::string& key : entry.Keys()) {
    bool known = false;
    for (std::string_view k : kCommonTopicKeys) known = known || k == key;
    for (std::string_view k : own) known = known || k == key;
    if (known) continue;
    bool other_kind = false;
    for (const auto& [n, k] : kKinds) {
      for (std::string_view option : KindKeys(k)) other_kind = other_kind || option == key;
    }
    if (other_kind) {
      entry[key].Fail("not an option of a topic of type '" + std::string(RosTopicKindName(kind)) +
                      "'");
    }
    entry[key].Fail("unknown field");
  }
}

// A log sensor id names files: lidar/<id>/..., imu/<id>.csv.
std::string SensorId(const YamlNode& node) {
  const std::string id = node.As<std::string>();
  if (id.empty() || id == "." || id == ".." || id.find_first_of("/\\") != std::string::npos) {
    node.Fail("sensor id '" + id + "' cannot name a file (no '/', not empty)");
  }
  return id;
}

std::vector<double> PositiveNumbers(const YamlNode& node, std::size_t n) {
  const std::vector<double> v = node.As<std::vector<double>>();
  if (v.size() != n) {
    node.Fail("expected a list of " + std::to_string(n) + " numbers, got " +
              std::to_string(v.size()));
  }
  for (double x : v) {
    if (!(x > 0.0)) node.Fail("sigmas must be positive");
  }
  return v;
}

RosTopicEntry ParseTopic(const YamlNode& entry) {
  entry.ExpectMap();
  RosTopicEntry t;
  t.where = entry.Where();
  t.topic = entry.Get<std::string>("topic");
  if (t.topic.empty()) entry["topic"].Fail("must not be empty");
  t.id = SensorId(entry["id"]);
  t.kind = ParseKind(entry["type"]);
  CheckKeys(entry, t.kind);
  if (const auto f = entry.Find("frame_id"); f && !f->IsNull()) {
    t.frame_id = NormalizedFrameId(f->As<std::string>());
    if (t.frame_id->empty()) f->Fail("must not be empty");
  }
  if (const auto m = entry.Find("T_body_sensor"); m && !m->IsNull()) {
    t.T_body_sensor = ParseTransform(*m);
  }
  if (const auto l = entry.Find("latency_s"); l && !l->IsNull()) {
    t.latency_s = l->As<double>();
    if (*t.latency_s < 0.0 || *t.latency_s > 10.0) l->Fail("expected a latency in [0, 10] s");
  }
  if (const auto e = entry.Find("estimator"); e && !e->IsNull()) {
    e->ExpectMap();
    t.estimator = e->FlowText();
  }
  if (const auto s = entry.Find("position_sigma_m"); s && !s->IsNull()) {
    const std::vector<double> v = PositiveNumbers(*s, 3);
    t.position_sigma_m = Vec3(v[0], v[1], v[2]);
  }
  if (const auto s = entry.Find("velocity_sigma_mps"); s && !s->IsNull()) {
    const std::vector<double> v = PositiveNumbers(*s, 3);
    t.velocity_sigma_mps = Vec3(v[0], v[1], v[2]);
  }
  if (const auto s = entry.Find("twist_sigma"); s && !s->IsNull()) {
    const std::vector<double> v = PositiveNumbers(*s, 6);
    t.twist_sigma = Vec6(v.data());
  }
  t.joint = entry.Get<std::string>("joint", t.id);
  t.joints = {t.id + "_fl", t.id + "_fr", t.id + "_rl", t.id + "_rr"};
  if (const auto j = entry.Find("joints"); j && !j->IsNull()) {
    const std::vector<std::string> names = j->As<std::vector<std::string>>();
    if (names.size() != 4) {
      j->Fail("expected 4 joint names: front-left, front-right, rear-left, rear-right");
    }
    for (std::size_t i = 0; i < 4; ++i) t.joints[i] = names[i];
  }
  if (const auto f = entry.Find("time_field"); f && !f->IsNull()) {
    t.time_field = f->As<std::string>();
  }
  if (const auto s = entry.Find("time_scale_s"); s && !s->IsNull()) {
    t.time_scale_s = s->As<double>();
    if (!(*t.time_scale_s > 0.0)) s->Fail("must be positive (seconds per unit of the field)");
  }
  return t;
}

RosStaticTransform ParseStaticTransform(const YamlNode& entry) {
  entry.ExpectMap();
  entry.ExpectOnlyKeys({"parent", "child", "T_parent_child"});
  RosStaticTransform s;
  s.where = entry.Where();
  s.parent = NormalizedFrameId(entry.Get<std::string>("parent"));
  s.child = NormalizedFrameId(entry.Get<std::string>("child"));
  if (s.parent.empty()) entry["parent"].Fail("must not be empty");
  if (s.child.empty()) entry["child"].Fail("must not be empty");
  if (s.parent == s.child) entry["child"].Fail("must differ from parent");
  s.T_parent_child = ParseTransform(entry["T_parent_child"]);
  return s;
}

std::string Numbers(const double* v, int n) {
  std::string out = "[";
  for (int i = 0; i < n; ++i) {
    if (i > 0) out += ", ";
    AppendNumber(out, v[i]);
  }
  return out + "]";
}

}  // namespace

std::string_view RosTopicKindName(RosTopicKind kind) {
  for (const auto& [n, k] : kKinds) {
    if (k == kind) return n;
  }
  return "?";
}

std::string NormalizedFrameId(std::string_view frame_id) {
  while (!frame_id.empty() && frame_id.front() == '/') frame_id.remove_prefix(1);
  return std::string(frame_id);
}

RosTopicMap LoadRosTopicMap(const std::filesystem::path& path) {
  return ParseRosTopicMap(YamlNode::LoadFile(path));
}

RosTopicMap ParseRosTopicMap(const YamlNode& root) {
  root.ExpectMap();
  root.ExpectOnlyKeys({"base_frame", "scenario", "origin", "topics", "static_transforms"});
  RosTopicMap map;
  map.source = root.source();
  map.base_frame = NormalizedFrameId(root.Get<std::string>("base_frame", map.base_frame));
  if (map.base_frame.empty()) root["base_frame"].Fail("must not be empty");
  map.scenario = root.Get<std::string>("scenario", "");
  if (const auto o = root.Find("origin"); o && !o->IsNull()) {
    o->ExpectMap();
    o->ExpectOnlyKeys({"latitude_deg", "longitude_deg", "altitude_m"});
    map.origin = GeodeticPoint{o->Get<double>("latitude_deg"), o->Get<double>("longitude_deg"),
                               o->Get<double>("altitude_m")};
    if (std::abs(map.origin->latitude_deg) > 90.0) (*o)["latitude_deg"].Fail("not in [-90, 90]");
    if (std::abs(map.origin->longitude_deg) > 180.0) {
      (*o)["longitude_deg"].Fail("not in [-180, 180]");
    }
  }
  const YamlNode topics = root["topics"];
  topics.ExpectSequence();
  if (topics.size() == 0) topics.Fail("at least one topic is required");
  std::set<std::string> ids, velocity_ids;
  for (std::size_t i = 0; i < topics.size(); ++i) {
    RosTopicEntry t = ParseTopic(topics.At(i));
    std::set<std::string>& seen = t.kind == RosTopicKind::kGnssVelocity ? velocity_ids : ids;
    if (!seen.insert(t.id).second) topics.At(i)["id"].Fail("duplicate sensor id '" + t.id + "'");
    map.topics.push_back(std::move(t));
  }
  for (std::size_t i = 0; i < map.topics.size(); ++i) {
    const RosTopicEntry& t = map.topics[i];
    if (t.kind != RosTopicKind::kGnssVelocity) continue;
    const bool has_gnss = std::any_of(map.topics.begin(), map.topics.end(), [&](const auto& g) {
      return g.kind == RosTopicKind::kGnss && g.id == t.id;
    });
    if (!has_gnss) {
      topics.At(i)["id"].Fail("no gnss topic with id '" + t.id +
                              "' (a gnss_velocity topic names the receiver it belongs to)");
    }
  }
  if (const auto list = root.Find("static_transforms"); list && !list->IsNull()) {
    list->ExpectSequence();
    for (std::size_t i = 0; i < list->size(); ++i) {
      map.static_transforms.push_back(ParseStaticTransform(list->At(i)));
    }
  }
  return map;
}

std::string RosTopicMapYaml(const RosTopicMap& map, const std::string& header_comment) {
  std::string y = header_comment;
  y += "base_frame: " + YamlQuoted(map.base_frame) + "\n";
  if (!map.scenario.empty()) y += "scenario: " + YamlQuoted(map.scenario) + "\n";
  if (map.origin) {
    y += "origin: {latitude_deg: " + NumberText(map.origin->latitude_deg) +
         ", longitude_deg: " + NumberText(map.origin->longitude_deg) +
         ", altitude_m: " + NumberText(map.origin->altitude_m) + "}\n";
  }
  y += "topics:\n";
  for (const RosTopicEntry& t : map.topics) {
    y += "  - topic: " + YamlQuoted(t.topic) + "\n";
    y += "    id: " + YamlQuoted(t.id) + "\n";
    y += "    type: " + std::string(RosTopicKindName(t.kind)) + "\n";
    if (t.frame_id) y += "    frame_id: " + YamlQuoted(*t.frame_id) + "\n";
    if (t.T_body_sensor) y += "    T_body_sensor: " + TransformYaml(*t.T_body_sensor) + "\n";
    if (t.latency_s) y += "    latency_s: " + NumberText(*t.latency_s) + "\n";
    if (!t.estimator.empty()) y += "    estimator: " + t.estimator + "\n";
    if (t.position_sigma_m) {
      y += "    position_sigma_m: " + Numbers(t.position_sigma_m->data(), 3) + "\n";
    }
    if (t.twist_sigma) y += "    twist_sigma: " + Numbers(t.twist_sigma->data(), 6) + "\n";
    if (t.velocity_sigma_mps) {
      y += "    velocity_sigma_mps: " + Numbers(t.velocity_sigma_mps->data(), 3) + "\n";
    }
    if (t.kind == RosTopicKind::kSteeringEncoder && t.joint != t.id) {
      y += "    joint: " + YamlQuoted(t.joint) + "\n";
    }
    if (t.kind == RosTopicKind::kWheelEncoders) {
      y += "    joints: [" + YamlQuoted(t.joints[0]) + ", " + YamlQuoted(t.joints[1]) + ", " +
           YamlQuoted(t.joints[2]) + ", " + YamlQuoted(t.joints[3]) + "]\n";
    }
    if (t.time_field) y += "    time_field: " + YamlQuoted(*t.time_field) + "\n";
    if (t.time_scale_s) y += "    time_scale_s: " + NumberText(*t.time_scale_s) + "\n";
  }
  if (!map.static_transforms.empty()) {
    y += "static_transforms:\n";
    for (const RosStaticTransform& s : map.static_transforms) {
      y += "  - {parent: " + YamlQuoted(s.parent) + ", child: " + YamlQuoted(s.child) +
           ", T_parent_child: " + TransformYaml(s.T_parent_child) + "}\n";
    }
  }
  return y;
}

}  // namespace statebench::sensors
