#include "estimator/factor_plan.hpp"

#include <algorithm>
#include <string>

#include "core/error.hpp"

namespace statebench::est {

SlidingWindowOptions SmootherOptions(const EstimatorSensorSetup& setup,
                                     const FactorGraphOptions& o) {
  SlidingWindowOptions s;
  s.window_s = o.window_s;
  s.imu_samples_per_state = o.imu_samples_per_state;
  s.imu_noise = setup.imu_noise.value_or(o.imu_noise);
  s.gnss_kernel = o.gnss.kernel;
  s.heading_kernel = o.heading.kernel;
  s.max_iterations = o.max_iterations;
  s.num_threads = o.num_threads;
  s.solver = o.solver;
  s.keep_all_states = o.batch;
  s.keep_lagged_states = o.lagged_output;
  return s;
}

FactorPlan PlanFactors(const EstimatorSensorSetup& setup, const FactorGraphOptions& o) {
  FactorPlan plan;
  for (const EstimatorSensor& s : setup.sensors) {
    if (s.kind == SensorKind::kLidar) plan.lidars.push_back(&s);
    if (s.kind == SensorKind::kSpeedEncoder && plan.speed == nullptr) plan.speed = &s;
    if (s.kind == SensorKind::kSteeringEncoder && plan.steering == nullptr) plan.steering = &s;
  }
  const std::string where = "factor graph options for sensor setup '" +
                            (setup.name.empty() ? setup.source : setup.name) + "': ";
  if (o.lidar.use == FactorUse::kOn && plan.lidars.empty()) {
    throw InputError(where + "lidar.enabled is true but the setup has no lidar");
  }
  if (o.lidar.use == FactorUse::kOff) plan.lidars.clear();
  // The Ceres solver's batch store holds no globals of the window (sliding_window_smoother.hpp):
  // say so before the log is read, not at the first scan.
  if (o.solver == WindowSolver::kCeres && o.batch) {
    const bool gnss_errors =
        std::any_of(setup.antennas.begin(), setup.antennas.end(),
                    [&o](const GnssAntenna& a) { return o.gnss.EstimatesCorrelatedErrorOf(a); });
    const bool globals = (o.lidar.estimate_mount && !plan.lidars.empty()) ||
                         (o.non_holonomic.enabled && o.non_holonomic.estimate_mount) ||
                         o.gnss.estimate_time_offset || gnss_errors || o.imu_triad.any() ||
                         o.gnss_calibration.estimate_heading_baseline;
    if (globals) {
      throw InputError(where +
                       "solver: ceres with batch: true cannot estimate mounts, time offsets, "
                       "GNSS errors or IMU triad errors (lidar.estimate_mount, "
                       "non_holonomic.estimate_mount, gnss.estimate_time_offset, "
                       "gnss.estimate_correlated_error, imu_triad, "
                       "gnss_calibration.estimate_heading_baseline): set them false or use "
                       "solver: chain");
    }
  }
  const bool has_encoders = plan.speed != nullptr && plan.steering != nullptr;
  if (o.kinematic.use == FactorUse::kOn && !has_encoders) {
    throw InputError(where + "kinematic.enabled is true but the setup lacks a " +
                     (plan.speed == nullptr ? "speed_encoder" : "steering_encoder"));
  }
  plan.kinematic = has_encoders && o.kinematic.use != FactorUse::kOff;
  if (plan.kinematic) {
    plan.wheelbase_m = plan.steering->T_body_sensor.translation().x() -
                       plan.speed->T_body_sensor.translation().x();
    if (plan.wheelbase_m < 0.1) {
      throw InputError(where +
                       "the kinematic factor needs the steering encoder (front axle) at "
                       "least 0.1 m ahead of the speed encoder (rear axle) along body x; got " +
                       std::to_string(plan.wheelbase_m) + " m");
    }
  }
  plan.T_imu_axle = plan.speed != nullptr ? plan.speed->T_imu_sensor : setup.T_body_imu.Inverse();
  return plan;
}

}  // namespace statebench::est
