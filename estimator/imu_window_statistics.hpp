// Mean and per-axis sample standard deviation of the gyro and accel over a window of IMU
// samples, and the zero-velocity options' "quiet IMU" test on them: what the standstill
// detection (motion_constraint_front_end) and the zero-rate factor (body_velocity_front_end)
// both ask of their recent samples.
#pragma once

#include "core/eigen_types.hpp"
#include "core/measurements.hpp"
#include "estimator/motion_factor_options.hpp"

namespace statebench::est {

struct ImuWindowStatistics {
  Vec3 mean_gyro = Vec3::Zero();
  Vec3 mean_accel = Vec3::Zero();
  Vec3 std_gyro = Vec3::Zero();   // sample standard deviation (n - 1)
  Vec3 std_accel = Vec3::Zero();

  // Neither signal's standard deviation on any axis above the options' limit.
  bool Quiet(const ZeroVelocityOptions& z) const {
    return !(std_gyro.maxCoeff() > z.max_gyro_std_radps) &&
           !(std_accel.maxCoeff() > z.max_accel_std_mps2);
  }
};

// samples: a container of ImuSample with at least two.
template <typename Samples>
ImuWindowStatistics ComputeImuWindowStatistics(const Samples& samples) {
  ImuWindowStatistics w;
  for (const ImuSample& s : samples) {
    w.mean_gyro += s.gyro;
    w.mean_accel += s.accel;
  }
  const double n = static_cast<double>(samples.size());
  w.mean_gyro /= n;
  w.mean_accel /= n;
  Vec3 var_g = Vec3::Zero(), var_a = Vec3::Zero();
  for (const ImuSample& s : samples) {
    var_g += (s.gyro - w.mean_gyro).cwiseAbs2();
    var_a += (s.accel - w.mean_accel).cwiseAbs2();
  }
  w.std_gyro = (var_g / (n - 1)).cwiseSqrt();
  w.std_accel = (var_a / (n - 1)).cwiseSqrt();
  return w;
}

}  // namespace statebench::est
