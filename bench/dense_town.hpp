// The dense test town both lidar benchmarks scan (bench/sensors/lidar_raycast_bench.cpp,
// bench/estimator/lidar_registration_bench.cpp): a 5x5 grid of 120 m blocks, two 3.5 m lanes,
// a sloped and undulating terrain, and buildings 8-30 m tall on almost every lot.
#pragma once

#include <cmath>
#include <memory>

#include "sensors/lidar_simulator.hpp"
#include "sensors/synthetic_roads.hpp"

namespace statebench::bench {

inline double DenseTownTerrain(double x, double y) {
  return 0.01 * x + 2.0 * std::sin(0.004 * y);
}

inline sensors::RoadGeometry DenseTownRoads() {
  return sensors::MakeGridRoads(5, 5, 120.0, 2, 3.5, DenseTownTerrain);
}

// The town without traffic (seed 1).
inline std::unique_ptr<sensors::LidarWorld> BuildDenseTown(const sensors::RoadGeometry& roads) {
  sensors::WorldLayoutOptions layout;
  layout.seed = 1;
  layout.buildings.probability = 0.95;
  layout.buildings.facade_min_m = 12.0;
  layout.buildings.facade_max_m = 30.0;
  layout.buildings.gap_min_m = 1.0;
  layout.buildings.gap_max_m = 5.0;
  layout.buildings.height_min_m = 8.0;
  layout.buildings.height_max_m = 30.0;
  return sensors::LidarWorld::Build(roads, DenseTownTerrain, layout);
}

}  // namespace statebench::bench
