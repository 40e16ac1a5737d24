#include "estimator/estimator_factory.hpp"

#include "core/error.hpp"
#include "estimator/ekf_single_track.hpp"
#include "estimator/factor_graph_estimator.hpp"

namespace statebench::est {

std::vector<std::string> KnownEstimators() { return {"factor_graph", "ekf"}; }

std::unique_ptr<Estimator> MakeEstimator(const std::string& name, const EstimatorSensorSetup& setup,
                                         const EstimatorFiles& files,
                                         LidarOdometryPool* lidar_pool) {
  if (name == "factor_graph") {
    FactorGraphOptions options =
        files.options.empty() ? FactorGraphOptions{} : LoadFactorGraphOptions(files.options);
    options.batch = options.batch || files.batch;
    return std::make_unique<FactorGraphEstimator>(setup, options, lidar_pool);
  }
  if (name == "ekf") {
    if (files.batch) throw InputError("estimator 'ekf' has no full-batch form (batch)");
    if (files.vehicle.empty()) {
      throw InputError("estimator 'ekf' needs the vehicle parameters file (setup " + setup.source +
                       ")");
    }
    EkfOptions options = files.options.empty() ? EkfOptions{} : LoadEkfOptions(files.options);
    options.vehicle = LoadSingleTrackParams(files.vehicle);
    return std::make_unique<EkfSingleTrackEstimator>(setup, options);
  }
  std::string known;
  for (const std::string& k : KnownEstimators()) known += (known.empty() ? "" : ", ") + k;
  throw InputError("unknown estimator '" + name + "' (known: " + known + ")");
}

}  // namespace statebench::est
