#include "apps/sweep_file.hpp"

#include <cmath>
#include <set>

#include "core/error.hpp"
#include "core/yaml_node.hpp"

namespace statebench::app {
namespace {

namespace fs = std::filesystem;

constexpr std::size_t kMaxRangeValues = 100000;

std::vector<std::uint64_t> ParseSeeds(const YamlNode& node) {
  std::vector<std::uint64_t> seeds;
  if (node.IsSequence()) {
    if (node.size() == 0) node.Fail("empty list of seeds");
    for (std::size_t i = 0; i < node.size(); ++i) seeds.push_back(node.At(i).As<std::uint64_t>());
  } else if (node.IsMap()) {
    node.ExpectOnlyKeys({"count", "first"});
    const auto count = node["count"].As<std::uint64_t>();
    if (count == 0 || count > kMaxRangeValues) {
      node["count"].Fail("expected a count between 1 and " + std::to_string(kMaxRangeValues));
    }
    const auto first = node.Get<std::uint64_t>("first", 1);
    for (std::uint64_t i = 0; i < count; ++i) seeds.push_back(first + i);
  } else {
    node.Fail("expected a list of seeds or {count: N, first: S}");
  }
  std::set<std::uint64_t> unique(seeds.begin(), seeds.end());
  if (unique.size() != seeds.size()) node.Fail("a seed is listed twice");
  return seeds;
}

YAML::Node NumberNode(double v) {
  char text[64];
  std::snprintf(text, sizeof(text), "%.15g", v);
  return YAML::Node(std::string(text));
}

std::vector<YAML::Node> ScalarList(const YamlNode& node, const std::string& what) {
  node.ExpectSequence();
  if (node.size() == 0) node.Fail("empty " + what + ": give at least one value");
  std::vector<YAML::Node> values;
  for (std::size_t i = 0; i < node.size(); ++i) {
    const YamlNode v = node.At(i);
    if (v.IsNull()) v.Fail("a value of the axis is empty");
    values.push_back(YAML::Clone(v.raw()));
  }
  return values;
}

std::vector<YAML::Node> RangeValues(const YamlNode& node) {
  node.ExpectOnlyKeys({"start", "stop", "step"});
  const double start = node.Get<double>("start");
  const double stop = node.Get<double>("stop");
  const double step = node.Get<double>("step");
  if (!(step > 0.0)) node["step"].Fail("expected a positive step");
  if (!(stop >= start)) node["stop"].Fail("expected stop >= start");
  const double count = std::floor((stop - start) / step + 1e-9) + 1.0;
  if (count > static_cast<double>(kMaxRangeValues)) node.Fail("the range gives too many values");
  std::vector<YAML::Node> values;
  for (int i = 0; i < static_cast<int>(count); ++i) values.push_back(NumberNode(start + i * step));
  return values;
}

SweepAxis ParseAxis(const std::string& name, const YamlNode& node) {
  SweepAxis axis;
  axis.name = name;
  axis.where = node.Where();
  node.ExpectMap();
  node.ExpectOnlyKeys({"path", "values", "range", "uniform", "normal", "choice"});
  axis.path = node.Get<std::string>("path");
  if (axis.path.empty()) node["path"].Fail("empty path");
  int kinds = 0;
  for (const char* k : {"values", "range", "uniform", "normal", "choice"}) kinds += node.Has(k);
  if (kinds != 1) {
    node.Fail("give exactly one of values, range, uniform, normal or choice for axis '" + name +
              "'");
  }
  if (const auto values = node.Find("values")) {
    axis.values = ScalarList(*values, "axis");
  } else if (const auto range = node.Find("range")) {
    axis.values = RangeValues(*range);
  } else if (const auto choice = node.Find("choice")) {
    axis.kind = SweepAxis::Kind::kChoice;
    axis.values = ScalarList(*choice, "choice");
  } else if (const auto uniform = node.Find("uniform")) {
    uniform->ExpectOnlyKeys({"low", "high"});
    axis.kind = SweepAxis::Kind::kUniform;
    axis.a = uniform->Get<double>("low");
    axis.b = uniform->Get<double>("high");
    if (!(axis.b >= axis.a)) (*uniform)["high"].Fail("expected high >= low");
  } else if (const auto normal = node.Find("normal")) {
    normal->ExpectOnlyKeys({"mean", "sigma"});
    axis.kind = SweepAxis::Kind::kNormal;
    axis.a = normal->Get<double>("mean");
    axis.b = normal->Get<double>("sigma");
    if (!(axis.b >= 0.0)) (*normal)["sigma"].Fail("expected sigma >= 0");
  }
  return axis;
}

}  // namespace

SweepSpec LoadSweepFile(const fs::path& file) {
  const YamlNode root = YamlNode::LoadFile(file);
  root.ExpectMap();
  root.ExpectOnlyKeys(
      {"name", "description", "scenarios", "seeds", "mode", "estimators", "duration_s", "axes"});
  SweepSpec spec;
  spec.file = file;
  spec.name = root.Get<std::string>("name", file.stem().string());
  const YamlNode scenarios = root["scenarios"];
  const std::vector<YamlNode> scenario_nodes = [&] {
    std::vector<YamlNode> nodes;
    if (scenarios.IsScalar()) {
      nodes.push_back(scenarios);
    } else {
      scenarios.ExpectSequence();
      if (scenarios.size() == 0) scenarios.Fail("empty list: name at least one scenario");
      for (std::size_t i = 0; i < scenarios.size(); ++i) nodes.push_back(scenarios.At(i));
    }
    return nodes;
  }();
  for (const YamlNode& node : scenario_nodes) {
    const fs::path path = node.ResolvePath(node.As<std::string>());
    std::error_code ec;
    if (!fs::is_regular_file(path, ec)) node.Fail("no such scenario file: " + path.string());
    spec.scenarios.push_back(fs::absolute(path).lexically_normal());
    spec.scenario_where.push_back(node.Where());
  }
  spec.seeds = ParseSeeds(root["seeds"]);
  const std::string mode = root.Get<std::string>("mode", "grid");
  if (mode != "grid" && mode != "zip") {
    root["mode"].Fail("expected 'grid' (every combination) or 'zip' (the i-th values together)");
  }
  spec.zip = mode == "zip";
  if (const auto estimators = root.Find("estimators"); estimators && !estimators->IsNull()) {
    spec.estimators = estimators->As<std::vector<std::string>>();
    if (spec.estimators.empty()) estimators->Fail("empty list: name at least one estimator");
    spec.estimators_where = estimators->Where();
  }
  if (const auto duration = root.Find("duration_s"); duration && !duration->IsNull()) {
    spec.duration_s = duration->As<double>();
    if (!(*spec.duration_s > 0.0)) duration->Fail("expected a positive duration");
  }
  if (const auto axes = root.Find("axes"); axes && !axes->IsNull()) {
    axes->ExpectMap();
    for (const std::string& name : axes->Keys()) spec.axes.push_back(ParseAxis(name, (*axes)[name]));
  }
  if (spec.zip) {
    std::optional<std::size_t> length;
    for (const SweepAxis& axis : spec.axes) {
      if (axis.random()) continue;
      if (length && axis.values.size() != *length) {
        throw InputError(axis.where + ": field 'axes." + axis.name + "': mode zip needs " +
                         "axes of equal length (" + std::to_string(axis.values.size()) + " here, " +
                         std::to_string(*length) + " before)");
      }
      length = axis.values.size();
    }
  }
  return spec;
}

}  // namespace statebench::app
