// A scenario's estimators as `statebench run` builds them, shared with the sweep's check of
// every run before anything starts: which entries a list of names picks, the estimators' view
// of the sensor setup, and each estimator built from its merged options file.
#pragma once

#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "estimator/estimator.hpp"
#include "estimator/estimator_config.hpp"
#include "estimator/shared_lidar_odometry.hpp"
#include "simulator/scenario.hpp"
#include "simulator/scenario_sensors.hpp"

namespace statebench::app {

// The entries of `all` that `names` pick, in the list's order: a name picks the entry with that
// label, or when no label matches, every entry of that type. Throws std::invalid_argument "'x'
// is neither the name nor the type of an estimator of <where> (names: a, b)".
std::vector<sim::EstimatorSpec> ChooseEstimators(const std::vector<sim::EstimatorSpec>& all,
                                                 const std::vector<std::string>& names,
                                                 const std::string& where);

// The setup as the estimators read it; throws InputError naming the setup file.
est::EstimatorSensorSetup EstimatorSetupOf(const sim::ScenarioSensors& sensors);

// Writes the estimator's merged options to DIR/estimator_config.yaml and builds the estimator
// from that file, so the run can be repeated from it. An InputError (a bad override, an option
// that does not fit the sensor setup) names the written file's line and the scenario's entry.
// vehicle_file: the vehicle parameters the estimator is told (empty: the scenario's own file).
// lidar_pool: the run's shared lidar odometries (est::MakeEstimator).
std::unique_ptr<est::Estimator> MakeScenarioEstimator(const sim::EstimatorSpec& spec,
                                                      const sim::Scenario& scenario,
                                                      const est::EstimatorSensorSetup& setup,
                                                      const std::filesystem::path& dir,
                                                      const std::filesystem::path& vehicle_file = {},
                                                      est::LidarOdometryPool* lidar_pool = nullptr);

}  // namespace statebench::app
