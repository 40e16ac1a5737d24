// A sweep file (docs/sweeps.md): base scenarios, seeds, axes of parameters and the estimators
// to run, expanded by sweep_expansion.hpp into independent runs.
//
//   name: setup2_gnss_noise
//   scenarios: [../paper/setup2_quadricycle.yaml]   # relative to the sweep file
//   seeds: {count: 20, first: 1}                     # or a list [1, 2, 3]
//   mode: grid                                       # full product (default), or zip
//   estimators: [factor_graph, ekf]                  # names or types; default: all of each
//   duration_s: 60                                   # optional, for every run
//   axes:
//     cep_m:                                         # the axis name, a column of the results
//       path: sensors.gnss_front.cep_m               # scenario_resolution.hpp
//       values: [1.0, 2.0, 4.0]                      # or range: {start, stop, step}
//     gyro_scale:                                    # or a draw per run from the run's seed:
//       path: ...                                    #   uniform: {low, high}
//       normal: {mean: 1.0, sigma: 0.1}              #   normal: {mean, sigma}
//                                                    #   choice: [a, b, c]
#pragma once

#include <yaml-cpp/yaml.h>

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace statebench::app {

struct SweepAxis {
  enum class Kind { kValues, kUniform, kNormal, kChoice };
  std::string name;
  std::string path;
  std::string where;  // "file:line:col" of the axis, for messages
  Kind kind = Kind::kValues;
  std::vector<YAML::Node> values;  // kValues, kChoice
  double a = 0.0;                  // uniform low, normal mean
  double b = 0.0;                  // uniform high, normal sigma

  bool random() const { return kind != Kind::kValues; }
};

struct SweepSpec {
  std::filesystem::path file;
  std::string name;
  std::vector<std::filesystem::path> scenarios;  // resolved against the sweep file's folder
  std::vector<std::string> scenario_where;       // their source locations
  std::vector<std::uint64_t> seeds;
  bool zip = false;
  std::vector<std::string> estimators;  // empty: every estimator of each scenario
  std::string estimators_where;
  std::optional<double> duration_s;
  std::vector<SweepAxis> axes;
};

// Throws InputError "file:line:col: field '...': ..." on anything wrong with the file itself:
// unknown keys, seeds that are not non-negative integers, an empty axis, a range that gives no
// value, zip axes of different lengths, a missing scenario file.
SweepSpec LoadSweepFile(const std::filesystem::path& file);

}  // namespace statebench::app
