// Where a scenario value came from, kept after parsing so that errors found later (a route edge
// missing from the built network, a SUMO tool that is not installed) still name the scenario
// file, line, column and field, in the same words as YamlNode::Fail.
#pragma once

#include <string>

#include "core/error.hpp"
#include "core/yaml_node.hpp"

namespace statebench::sim {

struct SourceRef {
  std::string where;  // "file:line:column"
  std::string field;  // dotted path, e.g. "ego.route[3]"

  static SourceRef Of(const YamlNode& node) { return {node.Where(), node.field()}; }

  // InputError "<where>: field '<field>': <what>".
  [[noreturn]] void Fail(const std::string& what) const {
    throw InputError(where + ": field '" + (field.empty() ? "<root>" : field) + "': " + what);
  }

  bool operator==(const SourceRef&) const = default;
};

}  // namespace statebench::sim
