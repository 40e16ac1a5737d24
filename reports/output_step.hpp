// How far the output moves from one estimate to the next beyond the motion: the jump a vehicle
// controller sees when a smoother's correction lands between two 100 Hz outputs. Two
// definitions, for consecutive estimates k-1, k of the same output stream:
//
// - against the truth (metrics.json `output_step`): the estimated motion minus the reference's,
//     position  |(p_k - p_{k-1}) - (p*_k - p*_{k-1})|
//     yaw       |wrap((psi_k - psi_{k-1}) - (psi*_k - psi*_{k-1}))|
//   (psi: yaw of R = Rz Ry Rx, as the RMSE defines it);
// - truth-free (diagnostics.json `output_step`, usable on real logs): the estimate against its
//   own motion, its velocity and the gyro over the step (trapezoid; the residual of a smooth
//   output is O(jerk dt^3), micrometres at 100 Hz),
//     position  |p_k - p_{k-1} - (v_{k-1} + v_k) dt / 2|
//     yaw       |wrap(psi_k - psi(R_{k-1} Exp(((w_{k-1} + w_k) / 2 - b_g,k) dt)))|
//   with w the raw gyro samples at the two stamps and b_g,k the estimate's gyro bias. Gyro noise
//   sets its floor (sigma dt per step, e.g. 0.4 mrad for a vibrating 0.04 rad/s MEMS at 100 Hz).
//
// Statistics: median, 99th percentile (within 0.05 %, core/running_statistics.hpp) and maximum
// over every pair. A pair needs two consecutive output epochs with an estimate: Break() where
// an epoch has none (not initialised, lost), so a gap is not counted as a step.
#pragma once

#include <cstddef>
#include <optional>

#include "core/running_statistics.hpp"
#include "core/state.hpp"
#include "reports/trajectory_metrics.hpp"

namespace statebench::reports {

struct OutputStepErrors {
  double position_m = 0.0;
  double yaw_rad = 0.0;
};

// Against the reference at the two stamps.
OutputStepErrors StepAgainstReference(const NavState& previous, const NavState& current,
                                      const ReferenceState& previous_reference,
                                      const ReferenceState& current_reference);
// Against the estimate's own velocity and the gyro (raw samples, IMU frame) at the two stamps.
OutputStepErrors StepAgainstOwnMotion(const NavState& previous, const NavState& current,
                                      const Vec3& previous_omega_imu, const Vec3& omega_imu);

// Statistics of the pairs seen so far.
class OutputStepStatistics {
 public:
  void Add(const OutputStepErrors& e);
  OutputSteps Summary() const;

 private:
  RunningStatistics position_m_, yaw_rad_;
};

// The truth-free steps of one output stream, fed estimate by estimate.
class OwnMotionStepMeter {
 public:
  // An estimate of the stream and the raw gyro sample at its stamp.
  void Add(const NavState& estimate, const Vec3& omega_imu);
  // The output had no estimate at an epoch: the next one starts a new pair.
  void Break() { previous_.reset(); }
  OutputSteps Summary() const { return statistics_.Summary(); }

 private:
  struct Previous {
    NavState state;
    Vec3 omega_imu;
  };
  std::optional<Previous> previous_;
  OutputStepStatistics statistics_;
};

}  // namespace statebench::reports
