// A scenario made self-contained, so that a sweep can change any of its parameters by path and
// run it from another folder, and so that its identity can be hashed.
//
// ResolveScenario(file) loads and checks the scenario, then returns its YAML document with
//   - `sensors:` replaced by the setup map itself (the file's content, or the inline map);
//   - `vehicle:` and the plain-XML network files as absolute paths;
//   - `estimators:` as a list of {name, type, overrides} where `overrides` holds every option the
//     estimator runs with (its options file with the scenario's overrides merged over it).
// Written anywhere and loaded again, it runs exactly as the original does.
//
// Paths into it (SetScenarioValue) are dotted keys with [index] for list elements; two segments
// name list elements by their id instead of their position:
//   sensors.gnss_front.cep_m            the setup entry whose id is gnss_front
//   estimators.factor_graph.window_s    the options of the estimator labelled factor_graph
//   faults.gnss_outages[0].start_s      plain keys and indices
#pragma once

#include <yaml-cpp/yaml.h>

#include <filesystem>
#include <string>

namespace statebench::sim {

// Throws InputError (file:line: field ...) when the scenario, its setup or an estimator's
// options file is bad.
YAML::Node ResolveScenario(const std::filesystem::path& scenario_file);

// Sets the value at `path` (a clone of `value`). Every segment but the last must exist; the last
// may be a new key of a map (whether it is a valid field is for the scenario's loader to say).
// Inside an estimator's options (estimators.<label>....) a missing section is created as a map:
// an options file lists only what it sets, and the estimator's loader says whether the section
// and key exist.
// Throws std::invalid_argument naming the first segment that does not exist and what exists
// there.
void SetScenarioValue(YAML::Node& resolved, const std::string& path, const YAML::Node& value);

// The value at `path`, or an undefined node when it does not exist (same path rules).
YAML::Node ScenarioValue(const YAML::Node& resolved, const std::string& path);

// The resolved document as text with every file path replaced by "sha256:<hash of the file>":
// equal for two scenarios exactly when they run the same, wherever the files live.
std::string ScenarioFingerprint(const YAML::Node& resolved);

}  // namespace statebench::sim
