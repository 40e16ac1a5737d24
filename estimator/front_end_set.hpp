// The factor graph's front ends, in the order they are asked: one per measurement kind. A new
// measurement kind is a new front end added in MakeFrontEnds (front_end_set.cpp); the
// orchestrator hands measurements to whichever front end claims them.
#pragma once

#include <memory>
#include <vector>

#include "estimator/factor_plan.hpp"
#include "estimator/front_end.hpp"
#include "estimator/gnss_front_end.hpp"
#include "estimator/shared_lidar_odometry.hpp"

namespace statebench::est {

struct FrontEndSet {
  std::vector<std::unique_ptr<MeasurementFrontEnd>> all;
  const GnssFrontEnd* gnss = nullptr;  // in `all`: it holds the local ENU frame
};

// `setup`, `plan`, `options` and `ctx` must outlive the front ends.
// lidar_pool: shared lidar odometries (lidar_front_end.hpp); nullptr: none shared.
FrontEndSet MakeFrontEnds(const EstimatorSensorSetup& setup, const FactorPlan& plan,
                          const FactorGraphOptions& options, FrontEndContext& ctx,
                          LidarOdometryPool* lidar_pool = nullptr);

}  // namespace statebench::est
