#include "sensors/lidar_sensor_model.hpp"

#include <algorithm>
#include <cassert>
#include <string>

namespace statebench::sensors {
namespace {

// Smallest multiple of period_ns at or after t_ns.
TimeNs NextMultiple(TimeNs t_ns, TimeNs period_ns) {
  TimeNs k = t_ns / period_ns;
  if (k * period_ns < t_ns) ++k;
  return k * period_ns;
}

}  // namespace

LidarModelParams LidarParamsFromSetup(const SensorSpec& spec, const LidarOptions& options,
                                      std::string_view where) {
  LidarModelValues values;
  values.model = std::string(LidarModelName(options.model));
  values.sensor_id = spec.id;
  values.T_body_lidar = spec.T_body_sensor;
  values.min_range_m = options.min_range_m;
  values.max_range_m = options.max_range_m;
  values.range_noise_sigma_m = options.range_noise_sigma_m;
  values.dropout_probability = options.dropout_probability;
  values.rotation_rate_hz = spec.rate_hz;
  values.latency_s = spec.latency_s;
  return MakeLidarModelParams(values, where.empty() ? "lidar '" + spec.id + "'" : where);
}

LidarSensorModel::LidarSensorModel(const SensorSpec& spec, const LidarOptions& options,
                                   const LidarWorld& world, std::uint64_t seed,
                                   std::string_view where)
    : SensorModel(spec),
      simulator_(world, LidarParamsFromSetup(spec, options, where), seed),
      period_ns_(simulator_.params().beams.PeriodNs()) {}

void LidarSensorModel::Observe(const TruthSample& truth, std::vector<Measurement>* out) {
  assert(poses_.empty() || truth.t_ns > poses_.back().first);
  if (!sweep_start_ns_) sweep_start_ns_ = NextMultiple(truth.t_ns, period_ns_);
  if (truth.t_ns >= *sweep_start_ns_) poses_.emplace_back(truth.t_ns, truth.body.T_world_frame);

  const TimeNs sweep_end_ns = *sweep_start_ns_ + period_ns_;
  if (truth.t_ns < sweep_end_ns) return;

  // The sweep is complete: its last column fired before sweep_end_ns <= truth.t_ns. It needs a
  // pose at its start (a truth sample stamped exactly there), otherwise it is skipped.
  if (!poses_.empty() && poses_.front().first == *sweep_start_ns_) {
    const auto scan_index = static_cast<std::uint64_t>(*sweep_start_ns_ / period_ns_);
    out->push_back(simulator_.SimulateScanFromBody([this](TimeNs t_ns) { return BodyPoseAt(t_ns); },
                                                   *sweep_start_ns_, scan_index));
  }
  sweep_start_ns_ = NextMultiple(truth.t_ns, period_ns_);
  std::erase_if(poses_, [&](const auto& p) { return p.first < *sweep_start_ns_; });
}

SE3 LidarSensorModel::BodyPoseAt(TimeNs t_ns) const {
  const auto after = std::lower_bound(poses_.begin(), poses_.end(), t_ns,
                                      [](const auto& p, TimeNs t) { return p.first < t; });
  assert(after != poses_.end());
  if (after->first == t_ns || after == poses_.begin()) return after->second;
  const auto before = std::prev(after);
  const double alpha =
      static_cast<double>(t_ns - before->first) / static_cast<double>(after->first - before->first);
  return SE3::Interpolate(before->second, after->second, alpha);
}

}  // namespace statebench::sensors
