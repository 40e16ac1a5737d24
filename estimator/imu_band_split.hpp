// Splits an IMU signal into vehicle motion and vibration, keeping the motion: a vehicle moves
// below a few Hz (turns, acceleration, braking pitch), an engine's harmonics and the road's
// resonances at tens of Hz. The low band is the signal through two cascaded moving averages of
// `taps` samples (a triangle of 2 taps - 1 samples, centred; at 100 Hz and 10 taps its gain is
// -3 dB at ~3.2 Hz, zero at 10, 20, 30 Hz and 0.014 at a 26.7 Hz idle tone).
//
// lowpass_std: per-axis sample standard deviation of the low band over the window (what the
//   standstill tests compare: an idle engine leaves it near the white noise's level, which the
//   triangle keeps sqrt((2 taps^2 + 1) / (3 taps^3)) of, 0.26 at 10 taps).
#pragma once

#include <span>

#include "core/eigen_types.hpp"

namespace statebench::est {

struct ImuBand {
  bool valid = false;
  Vec3 lowpass_std = Vec3::Zero();
};

// x: consecutive samples of one signal at a constant rate. Not valid for taps < 2 (no low-pass)
// or fewer than 2 taps + 1 samples.
ImuBand SplitImuBand(std::span<const Vec3> x, int taps);

// The moving-average length in samples for a low-pass of lowpass_s at sample period dt_s
// (at least 1).
int LowPassTaps(double lowpass_s, double dt_s);

}  // namespace statebench::est
