// The lidar world's triangle meshes cut into tiles for the raycaster: the terrain sampled on a
// regular grid (two triangles per cell, road where the centroid is on a lane or junction) and the
// roadside objects grouped by the square tile holding their centre.
#pragma once

#include <Eigen/Geometry>
#include <vector>

#include "sensors/lidar_world.hpp"
#include "sensors/road_clearance.hpp"
#include "sensors/world_mesh.hpp"

namespace statebench::sensors {

// Terrain heights at the nodes (x0 + i s, y0 + j s), i in [0, nx], j in [0, ny].
struct TerrainGrid {
  double x0 = 0.0, y0 = 0.0, spacing = 1.0;
  int nx = 0, ny = 0;
  std::vector<double> heights;
  Vec3 Node(int i, int j) const {
    return Vec3(x0 + i * spacing, y0 + j * spacing,
                heights[static_cast<std::size_t>(j) * (nx + 1) + i]);
  }
};

// The footprint grown by `margin`, sampled every `spacing`.
TerrainGrid SampleTerrain(const GroundHeightFn& ground, const Eigen::AlignedBox2d& footprint,
                          double spacing, double margin);

// Square tiles of tile_cells x tile_cells grid cells, two triangles per cell; triangles whose
// centroid is on a lane or junction are road.
std::vector<TriangleMesh> TerrainTiles(const TerrainGrid& g, const RoadClearance& clearance,
                                       int tile_cells);

// Objects grouped by the square tile (side tile_m) holding their centre, in a fixed order.
std::vector<TriangleMesh> ObjectTiles(const WorldLayout& layout, double tile_m,
                                      const LidarWorldOptions& options);

}  // namespace statebench::sensors
