#include "core/yaml_merge.hpp"

namespace statebench {
namespace {

YAML::Node Merge(const YAML::Node& base, const YAML::Node& overrides) {
  if (!base.IsMap() || !overrides.IsMap()) return YAML::Clone(overrides);
  YAML::Node merged = YAML::Clone(base);
  for (const auto& entry : overrides) {
    const std::string key = entry.first.as<std::string>();
    const YAML::Node current = merged[key];
    merged[key] = current.IsDefined() ? Merge(current, entry.second) : YAML::Clone(entry.second);
  }
  return merged;
}

void SetBlockStyle(YAML::Node node) {
  if (!node.IsMap() && !node.IsSequence()) return;
  node.SetStyle(YAML::EmitterStyle::Block);
  if (node.IsMap()) {
    for (auto entry : node) SetBlockStyle(entry.second);
  } else {
    for (auto element : node) SetBlockStyle(element);
  }
}

}  // namespace

YAML::Node MergeYaml(const YAML::Node& base, const YAML::Node& overrides) {
  if (!overrides.IsDefined() || overrides.IsNull()) return YAML::Clone(base);
  return Merge(base, overrides);
}

std::string ToYamlText(const YAML::Node& node) {
  if (!node.IsDefined() || node.IsNull()) return "";
  YAML::Node block = YAML::Clone(node);
  SetBlockStyle(block);
  YAML::Emitter out;
  out << block;
  return std::string(out.c_str()) + "\n";
}

}  // namespace statebench
