#include "sensors/lidar_options.hpp"

namespace statebench::sensors {

std::optional<LidarModel> ParseLidarModel(std::string_view name) {
  if (name == "hesai_xt32") return LidarModel::kHesaiXt32;
  if (name == "velodyne_vlp16") return LidarModel::kVelodyneVlp16;
  return std::nullopt;
}

std::string_view LidarModelName(LidarModel model) {
  return model == LidarModel::kHesaiXt32 ? "hesai_xt32" : "velodyne_vlp16";
}

LidarOptions DefaultLidarOptions(LidarModel model) {
  LidarOptions o;
  o.model = model;
  if (model == LidarModel::kHesaiXt32) {
    o.min_range_m = 0.5;
    o.max_range_m = 120.0;
    o.range_noise_sigma_m = 0.01;
  } else {
    o.min_range_m = 0.5;
    o.max_range_m = 100.0;
    o.range_noise_sigma_m = 0.015;
  }
  return o;
}

}  // namespace statebench::sensors
