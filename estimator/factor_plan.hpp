// Which factors a sensor setup and the factor graph's options give: the sensors each front end
// uses and the vehicle geometry they need.
#pragma once

#include <vector>

#include "core/se3.hpp"
#include "estimator/estimator_config.hpp"
#include "estimator/sliding_window_smoother.hpp"

namespace statebench::est {

struct FactorPlan {
  std::vector<const EstimatorSensor*> lidars;  // used lidars, setup order
  const EstimatorSensor* speed = nullptr;      // speed encoder (zero velocity, kinematic)
  const EstimatorSensor* steering = nullptr;
  bool kinematic = false;
  double wheelbase_m = 0.0;
  // Rear-axle frame (the speed encoder's mount, else the body frame) in the IMU frame: the
  // point and axes of the non-holonomic constraint.
  SE3 T_imu_axle;
};

// InputError when an option requires a sensor the setup does not have. The plan points into
// `setup`, which must outlive it.
FactorPlan PlanFactors(const EstimatorSensorSetup& setup, const FactorGraphOptions& options);

SlidingWindowOptions SmootherOptions(const EstimatorSensorSetup& setup,
                                     const FactorGraphOptions& options);

}  // namespace statebench::est
