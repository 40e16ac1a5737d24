#include "apps/scenario_estimators.hpp"

#include <fstream>
#include <set>
#include <stdexcept>

#include "core/error.hpp"
#include "core/yaml_node.hpp"
#include "estimator/estimator_factory.hpp"

namespace statebench::app {

namespace fs = std::filesystem;

std::vector<sim::EstimatorSpec> ChooseEstimators(const std::vector<sim::EstimatorSpec>& all,
                                                 const std::vector<std::string>& names,
                                                 const std::string& where) {
  std::set<std::string> chosen;
  for (const std::string& name : names) {
    std::vector<std::string> matches;
    for (const sim::EstimatorSpec& spec : all) {
      if (spec.label == name) matches.push_back(spec.label);
    }
    const bool by_label = !matches.empty();
    for (const sim::EstimatorSpec& spec : all) {
      if (!by_label && spec.type == name) matches.push_back(spec.label);
    }
    if (matches.empty()) {
      std::string labels;
      for (const sim::EstimatorSpec& spec : all) {
        labels += (labels.empty() ? "" : ", ") + spec.label;
      }
      throw std::invalid_argument("'" + name + "' is neither the name nor the type of an " +
                                  "estimator of " + where + " (names: " + labels + ")");
    }
    chosen.insert(matches.begin(), matches.end());
  }
  std::vector<sim::EstimatorSpec> selected;
  for (const sim::EstimatorSpec& spec : all) {
    if (chosen.count(spec.label)) selected.push_back(spec);
  }
  return selected;
}

est::EstimatorSensorSetup EstimatorSetupOf(const sim::ScenarioSensors& sensors) {
  const YamlNode setup_node = YamlNode::LoadString(
      sensors.setup_yaml, sensors.setup.source.empty() ? "sensor setup" : sensors.setup.source);
  return est::ParseEstimatorSensorSetup(setup_node);
}

std::unique_ptr<est::Estimator> MakeScenarioEstimator(const sim::EstimatorSpec& spec,
                                                      const sim::Scenario& scenario,
                                                      const est::EstimatorSensorSetup& setup,
                                                      const fs::path& dir,
                                                      const fs::path& vehicle_file,
                                                      est::LidarOdometryPool* lidar_pool) {
  // The estimator's own view of the setup: only its inputs.
  est::EstimatorSensorSetup own = setup;
  if (!spec.inputs.empty()) {
    try {
      own = est::RestrictToSensors(setup, spec.inputs);
    } catch (const InputError& e) {
      throw InputError(spec.source.where + ": field '" + spec.source.field +
                       ".inputs': " + e.what());
    }
  }
  fs::create_directories(dir);
  const fs::path config = dir / "estimator_config.yaml";
  std::ofstream(config) << sim::EstimatorConfigText(spec, scenario);
  est::EstimatorFiles files;
  files.options = config;
  files.vehicle = vehicle_file.empty() ? scenario.vehicle_file : vehicle_file;
  try {
    return est::MakeEstimator(spec.type, own, files, lidar_pool);
  } catch (const InputError& e) {
    const std::string from = spec.config.empty() ? "built-in defaults" : spec.config.string();
    throw InputError(std::string(e.what()) + "\n  in the options of estimator '" + spec.label +
                     "' (" + spec.source.where + ": field '" + spec.source.field + "'): " + from +
                     (spec.overrides ? " with the scenario's overrides" : "") + ", merged into " +
                     config.string());
  }
}

}  // namespace statebench::app
