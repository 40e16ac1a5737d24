// Deep merge of YAML documents: an options file with a scenario's overrides on top.
//
//   base:      {window_s: 1.0, gnss: {max_sigma_m: 5.0, gate_chi2: 16.27}}
//   overrides: {window_s: 0.5, gnss: {max_sigma_m: 3.0}}
//   merged:    {window_s: 0.5, gnss: {max_sigma_m: 3.0, gate_chi2: 16.27}}
//
// Maps merge key by key, recursively; any other override value (scalar, sequence, null) replaces
// the base value whole. A null or undefined overrides document leaves the base as it is. Keys only
// in the overrides are added: whether they are valid is for the loader of the merged document to
// say.
#pragma once

#include <yaml-cpp/yaml.h>

#include <string>

namespace statebench {

// A new tree; neither input is modified (yaml-cpp nodes share storage on copy, so the result is
// built from clones).
YAML::Node MergeYaml(const YAML::Node& base, const YAML::Node& overrides);

// Block-style YAML text of `node` (one key per line, whatever style it was read in), ending in a
// newline ("" for an undefined or null node).
std::string ToYamlText(const YAML::Node& node);

}  // namespace statebench
