// Parameters of a spinning lidar entry of a sensor setup. Parsed here so a setup file is
// complete; the beam models and the raycaster that use them live with the lidar simulation.
#pragma once

#include <optional>
#include <string_view>

namespace statebench::sensors {

enum class LidarModel { kHesaiXt32, kVelodyneVlp16 };

std::optional<LidarModel> ParseLidarModel(std::string_view name);  // hesai_xt32|velodyne_vlp16
std::string_view LidarModelName(LidarModel model);

struct LidarOptions {
  LidarModel model = LidarModel::kHesaiXt32;
  double min_range_m = 0.5;
  double max_range_m = 120.0;
  double range_noise_sigma_m = 0.01;  // 1-sigma range noise
  double dropout_probability = 0.0;   // chance that a return is lost, per beam
};

// Datasheet-like defaults (REFERENCE.md): XT32 120 m, +-1 cm; VLP-16 100 m, +-3 cm (sigma 1.5 cm).
LidarOptions DefaultLidarOptions(LidarModel model);

}  // namespace statebench::sensors
