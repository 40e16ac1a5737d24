#include "sensors/gnss_error_process.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace statebench::sensors {
namespace {

// Exponential waiting time of a Poisson process, in ns.
TimeNs ExponentialWait(double rate_per_s, std::mt19937_64& rng) {
  const double u = 1.0 - Uniform01(rng);  // in (0, 1]
  return FromSeconds(-std::log(u) / rate_per_s);
}

}  // namespace

GnssErrorProcess::GnssErrorProcess(const GnssOptions& options, std::uint64_t seed,
                                   const std::string& stream_name)
    : options_(options),
      white_rng_(MakeRng(seed, stream_name + "/white")),
      gm_rng_(MakeRng(seed, "gnss_common_mode/gauss_markov")),
      multipath_rng_(MakeRng(seed, stream_name + "/multipath")) {
  if (options_.correlated_fraction > 0.0) {
    unit_gm_ = GaussMarkov3(1.0, options_.gauss_markov_tau_s, gm_rng_, gm_normal_);
  }
}

void GnssErrorProcess::AdvanceCommonMode(TimeNs t_ns) {
  const double step_s = ToSeconds(kCommonModeStep);
  while (gm_grid_ns_ + kCommonModeStep <= t_ns) {
    unit_gm_.Step(step_s, gm_rng_, gm_normal_);
    gm_grid_ns_ += kCommonModeStep;
  }
}

void GnssErrorProcess::AdvanceMultipath(TimeNs t_ns) {
  const GnssMultipathOptions& mp = options_.multipath;
  const double rate_per_s = mp.events_per_hour / 3600.0;
  if (rate_per_s <= 0.0) return;
  if (!last_t_ns_) {
    // The timeline starts at the first fix: the first event begins an exponential wait later.
    event_start_ns_ = t_ns + ExponentialWait(rate_per_s, multipath_rng_);
  }
  // Walk the timeline up to t. Events that start and end between two fixes (e.g. during an
  // outage) are drawn and dropped, so the timeline does not depend on the fix rate.
  while (true) {
    if (!event_drawn_) {
      if (event_start_ns_ > t_ns) break;
      const double duration_s = mp.duration_s * (0.5 + Uniform01(multipath_rng_));
      const double magnitude_m = mp.magnitude_m * (0.5 + Uniform01(multipath_rng_));
      const double azimuth = 2.0 * std::numbers::pi * Uniform01(multipath_rng_);
      event_offset_ = Vec3(magnitude_m * std::cos(azimuth), magnitude_m * std::sin(azimuth),
                           0.5 * mp.magnitude_m * multipath_normal_(multipath_rng_));
      event_end_ns_ = event_start_ns_ + std::max<TimeNs>(1, FromSeconds(duration_s));
      event_drawn_ = true;
    }
    if (event_end_ns_ > t_ns) break;
    event_start_ns_ = event_end_ns_ + ExponentialWait(rate_per_s, multipath_rng_);
    event_drawn_ = false;
  }
  in_multipath_ = event_drawn_;  // a drawn event has start <= t < end here
}

Vec3 GnssErrorProcess::Sample(TimeNs t_ns, const GnssAccuracy& accuracy) {
  AdvanceMultipath(t_ns);
  const double f = options_.correlated_fraction;
  Vec3 unit = Vec3::Zero();
  if (f < 1.0) {
    const double w = std::sqrt(1.0 - f);
    for (int i = 0; i < 3; ++i) unit[i] = w * white_normal_(white_rng_);
  }
  if (f > 0.0) {
    AdvanceCommonMode(t_ns);
    unit += std::sqrt(f) * unit_gm_.value();
  }
  last_t_ns_ = t_ns;
  const double sh = accuracy.HorizontalSigma();
  Vec3 error(sh * unit.x(), sh * unit.y(), accuracy.vertical_sigma_m * unit.z());
  if (in_multipath_) error += event_offset_;
  return error;
}

}  // namespace statebench::sensors
