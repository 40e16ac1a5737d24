// Error parameters of a simulated GNSS receiver (one antenna).
//
// Horizontal accuracy is given as CEP50, the radius holding half of the fixes. For a circular
// Gaussian with sigma per horizontal axis, CEP50 = sigma sqrt(2 ln 2) = 1.1774 sigma
// (CEP 2 m -> sigma 1.70 m). The error of each axis is
//   e = sqrt(1 - f) sigma w + sqrt(f) sigma g + multipath,
// w white N(0, 1), g a unit first-order Gauss-Markov process with time constant tau, f the
// correlated fraction of the variance; so the configured sigma is the total (stationary) sigma
// whatever f is. The reported covariance is covariance_scale * diag(sh^2, sh^2, sv^2): a scale
// other than 1 makes the receiver lie (< 1 overconfident, > 1 pessimistic). Multipath is never
// reported.
#pragma once

#include <array>
#include <cmath>
#include <optional>
#include <string_view>
#include <vector>

#include "core/measurements.hpp"

namespace statebench::sensors {

inline const double kCep50PerSigma = std::sqrt(2.0 * std::log(2.0));  // 1.17741

enum class GnssMode : int { kSingle = 0, kRtkFloat = 1, kRtkFixed = 2 };

std::optional<GnssMode> ParseGnssMode(std::string_view name);  // single|rtk_float|rtk_fixed
GnssFixStatus ToFixStatus(GnssMode mode);

struct GnssAccuracy {
  double cep_m = 0.0;             // horizontal CEP50
  double vertical_sigma_m = 0.0;  // 1-sigma vertical

  double HorizontalSigma() const { return cep_m / kCep50PerSigma; }
};

// Defaults per mode: RTK fixed sigma 1 cm, float 0.25 m, single point CEP 2 m (sigma 1.70 m);
// vertical sigma 1.5 times the horizontal one.
GnssAccuracy DefaultAccuracy(GnssMode mode);

// A window [start_s, end_s) without fixes.
struct GnssOutage {
  double start_s = 0.0;
  double end_s = 0.0;
};

// Multipath jumps: events start as a Poisson process of the given rate (counted while no event
// is active). Each event lasts duration_s * U(0.5, 1.5) and offsets the fix by a constant
// vector: horizontal magnitude magnitude_m * U(0.5, 1.5) in a uniform direction, vertical
// 0.5 * magnitude_m * N(0, 1).
struct GnssMultipathOptions {
  double events_per_hour = 0.0;
  double magnitude_m = 5.0;
  double duration_s = 3.0;
};

// Satellites in view needed for each mode (used only with a SatelliteVisibility model).
struct GnssSatelliteThresholds {
  int rtk_fixed = 7;
  int rtk_float = 5;
  int single = 4;
};

// The receiver's Doppler velocity of the antenna (off by default). White noise per ENU axis
// (carrier-Doppler velocity errors decorrelate within an epoch); reported sigma
// sqrt(covariance_scale) x the true one, like the position. Defaults: consumer receivers give
// 0.05 m/s speed accuracy (50 %, u-blox NEO-M8 / ZED-F9P data sheets), i.e. about 0.04 m/s per
// horizontal axis in open sky; 0.07 m/s leaves room for multipath and dynamics, and the vertical
// is worse (geometry), as for the position.
struct GnssVelocityOptions {
  bool enabled = false;
  double horizontal_sigma_mps = 0.07;  // per horizontal axis
  double vertical_sigma_mps = 0.12;
};

struct GnssOptions {
  GnssMode mode = GnssMode::kRtkFixed;
  // Accuracy per mode, indexed by GnssMode. The configured mode uses its entry; the others are
  // used when satellite visibility degrades the fix.
  std::array<GnssAccuracy, 3> accuracy = {DefaultAccuracy(GnssMode::kSingle),
                                          DefaultAccuracy(GnssMode::kRtkFloat),
                                          DefaultAccuracy(GnssMode::kRtkFixed)};
  double correlated_fraction = 0.0;  // f in [0, 1]
  double gauss_markov_tau_s = 60.0;
  double covariance_scale = 1.0;
  std::vector<GnssOutage> outages;
  GnssMultipathOptions multipath;
  GnssSatelliteThresholds min_satellites;
  GnssVelocityOptions velocity;

  const GnssAccuracy& AccuracyOf(GnssMode m) const { return accuracy[static_cast<int>(m)]; }
  GnssAccuracy& AccuracyOf(GnssMode m) { return accuracy[static_cast<int>(m)]; }
};

}  // namespace statebench::sensors
