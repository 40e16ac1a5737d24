// Shared fixtures of the lidar tests: bare worlds (no generated objects) and error-free lidars.
#pragma once

#include <gtest/gtest.h>

#include <bit>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "core/measurements.hpp"
#include "sensors/lidar_model_params.hpp"
#include "sensors/lidar_world.hpp"
#include "sensors/synthetic_roads.hpp"
#include "sensors/world_layout.hpp"

namespace statebench::sensors::testing {

inline WorldLayoutOptions BareLayoutOptions() {
  WorldLayoutOptions o;
  o.kerbs.enabled = false;
  o.buildings.enabled = false;
  o.poles.spacing_m = 0.0;
  o.trees.spacing_m = 0.0;
  o.parked_cars.probability = 0.0;
  return o;
}

// Every field of every point equal, bit for bit (NaN payloads included).
inline void ExpectSameBits(const std::vector<LidarPoint>& a, const std::vector<LidarPoint>& b) {
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(std::bit_cast<std::uint32_t>(a[i].x), std::bit_cast<std::uint32_t>(b[i].x)) << i;
    EXPECT_EQ(std::bit_cast<std::uint32_t>(a[i].y), std::bit_cast<std::uint32_t>(b[i].y)) << i;
    EXPECT_EQ(std::bit_cast<std::uint32_t>(a[i].z), std::bit_cast<std::uint32_t>(b[i].z)) << i;
    EXPECT_EQ(std::bit_cast<std::uint32_t>(a[i].intensity),
              std::bit_cast<std::uint32_t>(b[i].intensity))
        << i;
    EXPECT_EQ(std::bit_cast<std::uint32_t>(a[i].t), std::bit_cast<std::uint32_t>(b[i].t)) << i;
    EXPECT_EQ(a[i].ring, b[i].ring) << i;
  }
}

// A flat ground at plane_z with a straight road and `boxes`, nothing else.
inline std::unique_ptr<LidarWorld> FlatWorld(double plane_z, const std::vector<WorldBox>& boxes = {}) {
  const GroundHeightFn ground = [plane_z](double, double) { return plane_z; };
  WorldLayoutOptions layout = BareLayoutOptions();
  layout.extra_boxes = boxes;
  LidarWorldOptions options;
  options.ground_margin_m = 150.0;
  return LidarWorld::Build(MakeStraightRoad(-50.0, 50.0, 1, 3.5, ground), ground, layout, options);
}

// A lidar with exact ranges: no noise, no dropout, no reflectivity limit.
inline LidarModelParams ExactLidar(const std::string& model) {
  LidarModelValues v;
  v.model = model;
  v.sensor_id = "lidar_test";
  v.range_noise_sigma_m = 0.0;
  v.dropout_probability = 0.0;
  v.range_at_10pct_m = 0.0;
  return MakeLidarModelParams(v, "test");
}

}  // namespace statebench::sensors::testing
