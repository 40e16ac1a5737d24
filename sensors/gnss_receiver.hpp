// Simulated GNSS receiver of one antenna. The fix is the antenna phase centre (body position
// plus the lever arm T_body_sensor), plus the error of GnssErrorProcess, converted to WGS84
// latitude/longitude/ellipsoidal height through the scenario's local ENU frame (GeographicLib,
// exact). It reports a 3x3 ENU covariance and a fix status like a real receiver.
//
// With options.velocity.enabled the fix also carries the antenna's ENU velocity (truth
// v + R (omega x lever arm), exact rigid-body kinematics) plus white noise from its own random
// stream (seed, "<id>/velocity"), so turning it on leaves the position bits unchanged.
//
// No fix is produced inside a scheduled outage, nor when a SatelliteVisibility model leaves
// fewer satellites than the single-point threshold. The fix stamp is the truth time it was taken
// at; it arrives latency_s later.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <random>

#include "core/geodetic.hpp"
#include "core/random.hpp"
#include "sensors/gnss_error_process.hpp"
#include "sensors/gnss_options.hpp"
#include "sensors/satellite_visibility.hpp"
#include "sensors/sensor_model.hpp"

namespace statebench::sensors {

class GnssReceiver : public SensorModel {
 public:
  GnssReceiver(const SensorSpec& spec, const GnssOptions& options, const LocalEnuFrame& frame,
               std::uint64_t seed);

  void SetSatelliteVisibility(std::shared_ptr<const SatelliteVisibility> visibility) {
    visibility_ = std::move(visibility);
  }

  void Observe(const TruthSample& truth, std::vector<Measurement>* out) override;

  // The fix at truth.t_ns regardless of the schedule (stamps strictly increasing), or nothing
  // during an outage or without enough satellites.
  std::optional<GnssFix> Sample(const TruthSample& truth);

  // The mode the receiver is in for an antenna position and time, or nothing (no fix).
  std::optional<GnssMode> ModeAt(const Vec3& p_world_antenna, TimeNs t_ns) const;

  const GnssOptions& options() const { return options_; }
  bool in_multipath() const { return errors_.in_multipath(); }

 private:
  bool InOutage(TimeNs t_ns) const;
  GnssVelocity SampleVelocity(const TruthSample& truth);

  GnssOptions options_;
  LocalEnuFrame frame_;
  GnssErrorProcess errors_;
  std::mt19937_64 velocity_rng_;
  NormalSampler velocity_normal_;
  std::shared_ptr<const SatelliteVisibility> visibility_;
};

}  // namespace statebench::sensors
