#include "sensors/gnss_receiver.hpp"

#include <algorithm>
#include <cmath>

namespace statebench::sensors {

GnssReceiver::GnssReceiver(const SensorSpec& spec, const GnssOptions& options,
                           const LocalEnuFrame& frame, std::uint64_t seed)
    : SensorModel(spec),
      options_(options),
      frame_(frame),
      errors_(options, seed, spec.id),
      velocity_rng_(MakeRng(seed, spec.id + "/velocity")) {}

void GnssReceiver::Observe(const TruthSample& truth, std::vector<Measurement>* out) {
  if (!spec().IsSampleTime(truth.t_ns)) return;
  if (auto fix = Sample(truth)) out->push_back(std::move(*fix));
}

bool GnssReceiver::InOutage(TimeNs t_ns) const {
  const double t_s = ToSeconds(t_ns);
  return std::any_of(options_.outages.begin(), options_.outages.end(),
                     [t_s](const GnssOutage& o) { return o.start_s <= t_s && t_s < o.end_s; });
}

std::optional<GnssMode> GnssReceiver::ModeAt(const Vec3& p_world_antenna, TimeNs t_ns) const {
  if (!visibility_) return options_.mode;
  const int n = visibility_->VisibleSatellites(p_world_antenna, t_ns);
  const GnssSatelliteThresholds& th = options_.min_satellites;
  GnssMode allowed = GnssMode::kSingle;
  if (n >= th.rtk_fixed) {
    allowed = GnssMode::kRtkFixed;
  } else if (n >= th.rtk_float) {
    allowed = GnssMode::kRtkFloat;
  } else if (n < th.single) {
    return std::nullopt;
  }
  return std::min(allowed, options_.mode);  // never better than the configured mode
}

GnssVelocity GnssReceiver::SampleVelocity(const TruthSample& truth) {
  const GnssVelocityOptions& o = options_.velocity;
  const Vec3 sigma(o.horizontal_sigma_mps, o.horizontal_sigma_mps, o.vertical_sigma_mps);
  Vec3 noise;
  for (int i = 0; i < 3; ++i) noise[i] = sigma[i] * velocity_normal_(velocity_rng_);
  GnssVelocity v;
  v.v_enu = truth.body.AtMount(spec().T_body_sensor).v_world + noise;
  v.sigma_enu = std::sqrt(options_.covariance_scale) * sigma;
  return v;
}

std::optional<GnssFix> GnssReceiver::Sample(const TruthSample& truth) {
  if (InOutage(truth.t_ns)) return std::nullopt;
  const Vec3 p_world_antenna = truth.body.T_world_frame * spec().T_body_sensor.translation();
  const std::optional<GnssMode> mode = ModeAt(p_world_antenna, truth.t_ns);
  if (!mode) return std::nullopt;

  const GnssAccuracy& accuracy = options_.AccuracyOf(*mode);
  const Vec3 p_measured = p_world_antenna + errors_.Sample(truth.t_ns, accuracy);
  const GeodeticPoint geo = frame_.ToGeodetic(p_measured);

  GnssFix fix;
  fix.header = MakeHeader(truth.t_ns);
  fix.latitude_deg = geo.latitude_deg;
  fix.longitude_deg = geo.longitude_deg;
  fix.altitude_m = geo.altitude_m;
  const double sh = accuracy.HorizontalSigma();
  const double sv = accuracy.vertical_sigma_m;
  fix.covariance_enu = options_.covariance_scale * Vec3(sh * sh, sh * sh, sv * sv).asDiagonal();
  fix.status = ToFixStatus(*mode);
  if (options_.velocity.enabled) fix.velocity = SampleVelocity(truth);
  return fix;
}

}  // namespace statebench::sensors
