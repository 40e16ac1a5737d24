// Mean and per-axis sample standard deviation of the gyro and accel over a window of IMU
// samples, and the zero-velocity options' "quiet IMU" test on them: what the standstill
// detection (motion_constraint_front_end) and the zero-rate factor (body_velocity_front_end)
// both ask of their recent samples. The test passes on the raw samples, or, when they are not
// quiet, on their low band (imu_band_split.hpp) against half the thresholds: an engine running
// shakes the raw samples far above any threshold that still tells a car standing from one
// driving.
#pragma once

#include <vector>

#include "core/eigen_types.hpp"
#include "core/measurements.hpp"
#include "estimator/imu_band_split.hpp"
#include "estimator/motion_factor_options.hpp"

namespace statebench::est {

// The low band must be quiet to this share of the raw thresholds: it removes a tone far above
// its cut-off (an idle engine's, to 1-2 %) but keeps 0.26 of a white noise's std, so a white
// noise passes only below ~2x the raw thresholds, not an IMU four times noisier than them.
inline constexpr double kLowBandThresholdShare = 0.5;

// Both signals' bands over a window of IMU samples (a container of ImuSample at a constant
// rate), with a low-pass of lowpass_s; not valid when the window is too short for it.
struct ImuBands {
  ImuBand gyro, accel;
  int taps = 1;  // the moving averages' length: the low band sees the window's taps - 1 newest
                 // (and oldest) samples only faintly
  bool valid() const { return gyro.valid && accel.valid; }
};

template <typename Samples>
ImuBands SplitImuBands(const Samples& samples, double lowpass_s) {
  ImuBands b;
  const std::size_t n = samples.size();
  if (n < 3) return b;
  const double dt =
      ToSeconds(samples.back().header.stamp_ns - samples.front().header.stamp_ns) / (n - 1.0);
  std::vector<Vec3> gyro, accel;
  gyro.reserve(n);
  accel.reserve(n);
  for (const ImuSample& s : samples) {
    gyro.push_back(s.gyro);
    accel.push_back(s.accel);
  }
  const int taps = LowPassTaps(lowpass_s, dt);
  b.taps = taps;
  b.gyro = SplitImuBand(gyro, taps);
  b.accel = SplitImuBand(accel, taps);
  return b;
}

struct ImuWindowStatistics {
  Vec3 mean_gyro = Vec3::Zero();
  Vec3 mean_accel = Vec3::Zero();
  Vec3 std_gyro = Vec3::Zero();   // sample standard deviation (n - 1)
  Vec3 std_accel = Vec3::Zero();
  ImuBands bands;  // computed only when the raw samples are not quiet

  // Neither signal's standard deviation on any axis above the options' limit: raw, or in the
  // low band when the raw samples are not quiet.
  bool Quiet(const ZeroVelocityOptions& z) const {
    const auto quiet = [&](const Vec3& gyro_std, const Vec3& accel_std) {
      return !(gyro_std.maxCoeff() > z.max_gyro_std_radps) &&
             !(accel_std.maxCoeff() > z.max_accel_std_mps2);
    };
    return quiet(std_gyro, std_accel) ||
           (bands.valid() && quiet(bands.gyro.lowpass_std / kLowBandThresholdShare,
                                   bands.accel.lowpass_std / kLowBandThresholdShare));
  }
};

// samples: a container of ImuSample with at least two; the bands with z.lowpass_s when the raw
// samples are not quiet (z.lowpass_s 0: the raw test only).
template <typename Samples>
ImuWindowStatistics ComputeImuWindowStatistics(const Samples& samples,
                                               const ZeroVelocityOptions& z) {
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
  if (z.lowpass_s > 0.0 && !w.Quiet(z)) w.bands = SplitImuBands(samples, z.lowpass_s);
  return w;
}

}  // namespace statebench::est
