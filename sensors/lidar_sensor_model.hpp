// A spinning lidar of a sensor setup as a SensorModel of the SensorSuite: it buffers the truth
// body poses of the current sweep and, once the sweep is complete, ray casts it through
// LidarSimulator (sensors/lidar_simulator.hpp) into the LidarWorld.
//
// Sweeps: the head spins at the entry's rate_hz (10 or 20 Hz); sweep k starts at
// t_k = k * period (the first sweep at the first multiple of the period at or after the first
// truth sample) and is emitted when the truth reaches t_k + period, the end of the sweep. Its
// arrival is t_k + period + latency (LidarSimulator's rule), i.e. exactly truth.t_ns + latency
// when truth stamps fall on the sweep ends (1 kHz truth does), so the suite's release contract
// (MinArrivalDelayNs = latency) holds. A sweep still open when the truth ends is dropped.
//
// Poses at the column times (every 50 us for an XT32 at 10 Hz) are interpolated between the two
// bracketing truth samples with SE3::Interpolate. Between 1 ms samples the error of the
// geodesic against the true motion is below a dt^2 / 8 (0.25 um at a = 2 m/s^2) and
// omega^2 dt^2 / 8 rad: far below any range noise.
#pragma once

#include <cstdint>
#include <optional>
#include <string_view>
#include <utility>
#include <vector>

#include "sensors/lidar_model_params.hpp"
#include "sensors/lidar_options.hpp"
#include "sensors/lidar_simulator.hpp"
#include "sensors/lidar_world.hpp"
#include "sensors/sensor_model.hpp"

namespace statebench::sensors {

// The simulator's parameters of a setup entry: model, ranges, noise and dropout from `options`,
// mount and latency from `spec`, rotation rate = spec.rate_hz. Throws InputError naming `where`
// (e.g. the entry's "file:line:column") when the rate is not 10 or 20 Hz.
LidarModelParams LidarParamsFromSetup(const SensorSpec& spec, const LidarOptions& options,
                                      std::string_view where);

class LidarSensorModel : public SensorModel {
 public:
  // `world` must outlive the model, its traffic set before the first sweep. `seed` is the
  // scenario seed (the simulator derives its streams from it and the sensor id).
  LidarSensorModel(const SensorSpec& spec, const LidarOptions& options, const LidarWorld& world,
                   std::uint64_t seed, std::string_view where = "");

  void Observe(const TruthSample& truth, std::vector<Measurement>* out) override;

  const LidarSimulator& simulator() const { return simulator_; }
  TimeNs sweep_period_ns() const { return period_ns_; }

 private:
  // T_world_body at t_ns from the buffered samples (t_ns within the buffer).
  SE3 BodyPoseAt(TimeNs t_ns) const;

  LidarSimulator simulator_;
  TimeNs period_ns_ = 0;
  std::optional<TimeNs> sweep_start_ns_;
  std::vector<std::pair<TimeNs, SE3>> poses_;  // T_world_body from the sweep start, by time
};

}  // namespace statebench::sensors
