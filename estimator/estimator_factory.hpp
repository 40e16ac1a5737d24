// Builds an estimator by name, so tools and scenarios can run either the factor graph or the EKF
// baseline behind the Estimator interface.
#pragma once

#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "estimator/estimator.hpp"
#include "estimator/estimator_config.hpp"
#include "estimator/shared_lidar_odometry.hpp"

namespace statebench::est {

// Files an estimator may read besides the sensor setup.
struct EstimatorFiles {
  // factor_graph: options YAML (scenarios/estimators/factor_graph.yaml); empty: defaults.
  // ekf: options YAML (scenarios/estimators/ekf.yaml); empty: defaults.
  std::filesystem::path options;
  // ekf: the vehicle parameters file (scenarios/vehicles/*.yaml), required. factor_graph: unused.
  std::filesystem::path vehicle;
  // factor_graph: the full-batch smoother whatever the options file says (batch: true);
  // ekf: an InputError (it has no batch form).
  bool batch = false;
};

// "factor_graph", "ekf".
std::vector<std::string> KnownEstimators();

// Throws InputError naming the estimator and listing the known ones if `name` is unknown, and
// the loaders' InputErrors (file:line: field) on bad files; "ekf" without a vehicle file is an
// InputError too. lidar_pool: shared lidar odometries of the run (factor_graph with
// lidar.motion_prior: constant_velocity; shared_lidar_odometry.hpp); nullptr: none shared.
std::unique_ptr<Estimator> MakeEstimator(const std::string& name, const EstimatorSensorSetup& setup,
                                         const EstimatorFiles& files,
                                         LidarOdometryPool* lidar_pool = nullptr);

}  // namespace statebench::est
