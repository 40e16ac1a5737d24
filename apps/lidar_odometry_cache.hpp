// The shared lidar odometry's registrations through the stage cache (`lidar_odometry` stage,
// docs/sweeps.md "The stage cache"): a run whose estimator inputs (the simulated streams, faults
// and mismatch: sim::EstimatorInputsKey) and shared-odometry key (odometry options, lidar mounts,
// gyro prior, intake) were seen before reads the registrations instead of computing them; the
// results are the same bits. Only complete runs are stored (LidarOdometryPool::Finish).
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "core/stage_cache.hpp"
#include "estimator/shared_lidar_odometry.hpp"

namespace statebench::app {

class CachedRegistrationStore final : public est::RegistrationStore {
 public:
  // inputs_key: sim::EstimatorInputsKey of the run.
  CachedRegistrationStore(StageCache& cache, std::string inputs_key)
      : cache_(cache), inputs_key_(std::move(inputs_key)) {}

  std::optional<std::vector<est::RecordedRegistration>> Load(const std::string& key) override;
  void Save(const std::string& key,
            const std::vector<est::RecordedRegistration>& registrations) override;

 private:
  std::string EntryKey(const std::string& key) const;

  StageCache& cache_;
  std::string inputs_key_;
};

}  // namespace statebench::app
