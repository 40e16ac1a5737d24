#include "sensors/lidar_model_params.hpp"

#include <cmath>
#include <string>

#include "core/error.hpp"

namespace statebench::sensors {

LidarModelParams MakeLidarModelParams(const LidarModelValues& v, std::string_view where) {
  const auto fail = [&](const std::string& field, const std::string& what) {
    throw InputError(std::string(where) + ": field '" + field + "': " + what);
  };
  LidarModelParams p;
  p.sensor_id = v.sensor_id;
  p.T_body_lidar = v.T_body_lidar;
  if (v.model == "hesai_xt32") {
    p.beams = HesaiXt32BeamModel();
    p.max_range_m = 120.0;
    p.range_noise_sigma_m = 0.01;
    p.range_at_10pct_m = 80.0;
  } else if (v.model == "velodyne_vlp16") {
    p.beams = VelodyneVlp16BeamModel();
    p.max_range_m = 100.0;
    p.range_noise_sigma_m = 0.03;
    p.range_at_10pct_m = 0.0;
  } else {
    fail("model", "unknown lidar model '" + v.model + "' (expected hesai_xt32 or velodyne_vlp16)");
  }
  if (v.sensor_id.empty()) fail("id", "must not be empty");
  p.min_range_m = v.min_range_m.value_or(p.min_range_m);
  p.max_range_m = v.max_range_m.value_or(p.max_range_m);
  p.range_noise_sigma_m = v.range_noise_sigma_m.value_or(p.range_noise_sigma_m);
  p.dropout_probability = v.dropout_probability.value_or(p.dropout_probability);
  p.range_at_10pct_m = v.range_at_10pct_m.value_or(p.range_at_10pct_m);
  if (!(p.min_range_m >= 0.0)) fail("min_range_m", "must be >= 0");
  if (!(p.max_range_m > p.min_range_m)) fail("max_range_m", "must be > min_range_m");
  if (!(p.range_noise_sigma_m >= 0.0)) fail("range_noise_sigma_m", "must be >= 0");
  if (!(p.dropout_probability >= 0.0 && p.dropout_probability <= 1.0)) {
    fail("dropout_probability", "must be in [0, 1]");
  }
  if (!std::isfinite(p.range_at_10pct_m)) fail("range_at_10pct_m", "must be finite");
  if (!(v.latency_s >= 0.0)) fail("latency_s", "must be >= 0");
  p.latency_ns = FromSeconds(v.latency_s);
  if (v.rotation_rate_hz) {
    const double rate = *v.rotation_rate_hz;
    if (rate != 10.0 && rate != 20.0) fail("rate_hz", "spinning lidars run at 10 or 20 Hz");
    p.beams.columns = static_cast<int>(std::lround(p.beams.columns * 10.0 / rate));
    p.beams.rotation_rate_hz = rate;
  }
  return p;
}

}  // namespace statebench::sensors
