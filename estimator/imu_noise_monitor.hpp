// The IMU noise the estimator sees, measured from the samples instead of taken from the
// datasheet: a consumer IMU on a car with its engine running reads 0.01-0.04 rad/s and
// 0.1-0.4 m/s^2 of vibration per sample, 10-20x what its datasheet density gives at 100 Hz.
//
// Only samples of a still vehicle are measured (the motion constraints' standstill test passed
// over them: imu_window_statistics.hpp, with an engine running on the low band): the vehicle's
// own motion is then zero and everything the IMU reads beyond gravity and its bias is its noise
// and vibration. While the vehicle moves, the same measurement reads the motion as noise (a car's
// yaw-rate changes over 0.1 s alone read ~4e-4 rad/s/sqrt(Hz), 20x an industrial gyro's
// density), so road vibration that grows with speed is not measured: what the stops measured is
// used throughout.
//
// Every block_s of contiguous still samples, each signal's means over consecutive spans of scale_s
// (0.1 s: the default keyframe interval, one preintegration) give its Hadamard variance
// H = (1/6) E[(m[k+1] - 2 m[k] + m[k-1])^2] per axis; for white noise H = density^2 / scale_s,
// so the block's density is sqrt(mean over the axes of H x scale_s) (the mean over the axes
// because the preintegration's noise is isotropic). The second difference removes the vehicle's
// own motion up to a constant jerk. A running mean over the blocks (time constant
// time_constant_s) is the measured density. It is the white noise that would spread one
// preintegration's mean rate and specific force as the IMU's does: a vibration tone averages out
// over the span where white noise does not (an 800 rpm idle's 26.7 Hz order reads 0.45 x its rms
// x sqrt(0.01 s)), so a white noise of the tone's per-sample variance would over-state it and
// weaken the IMU against every other factor (measured: the 60 s outage drifts more).
//
// The used density of each signal is the configured one, or the measured one when that is above
// inflate_above x the configured one (a datasheet within a factor of it is kept: the defaults
// absorb that much), at most max_inflation x the configured one. Never below the configured one.
// The random walks and integration_density stay as configured.
#pragma once

#include <optional>
#include <vector>

#include "core/measurements.hpp"
#include "estimator/imu_noise.hpp"

namespace statebench::est {

struct ImuNoiseEstimationOptions {
  bool enabled = true;
  double block_s = 1.0;
  double scale_s = 0.1;
  double time_constant_s = 10.0;
  double inflate_above = 2.0;
  double max_inflation = 30.0;
};

// What diagnostics.json shows (densities in Kalibr units).
struct ImuNoiseReport {
  bool enabled = false;
  int blocks = 0;  // blocks measured
  double gyro_configured = 0.0, accel_configured = 0.0;
  double gyro_measured = 0.0, accel_measured = 0.0;  // running mean at the last block
  double gyro_used = 0.0, accel_used = 0.0;          // used since the last block
  double gyro_used_max = 0.0, accel_used_max = 0.0;  // largest used over the run
};

class ImuNoiseMonitor {
 public:
  ImuNoiseMonitor(const ImuNoiseEstimationOptions& options, const ImuNoise& configured);

  // Adds a released sample of a still vehicle. Samples not newer than the last one taken are
  // skipped (still windows overlap); a gap of more than two sample periods starts a new block.
  // True when a block closed and used() changed.
  bool AddStill(const ImuSample& sample);

  const ImuNoise& used() const { return used_; }
  const ImuNoiseReport& report() const { return report_; }

 private:
  void CloseBlock();
  double Used(double measured, double configured) const;

  ImuNoiseEstimationOptions options_;
  ImuNoise configured_;
  ImuNoise used_;
  ImuNoiseReport report_;
  std::vector<ImuSample> block_;
  std::optional<TimeNs> last_ns_;  // the newest sample taken
  TimeNs period_ns_ = 0;           // between the two newest samples taken
  std::optional<double> gyro_variance_density_;   // running mean of density^2
  std::optional<double> accel_variance_density_;
};

}  // namespace statebench::est
