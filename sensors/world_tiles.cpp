#include "sensors/world_tiles.hpp"

#include <array>
#include <cmath>
#include <map>
#include <utility>

namespace statebench::sensors {

TerrainGrid SampleTerrain(const GroundHeightFn& ground, const Eigen::AlignedBox2d& footprint,
                          double spacing, double margin) {
  TerrainGrid g;
  g.spacing = spacing;
  g.x0 = std::floor((footprint.min().x() - margin) / spacing) * spacing;
  g.y0 = std::floor((footprint.min().y() - margin) / spacing) * spacing;
  g.nx = static_cast<int>(std::ceil((footprint.max().x() + margin - g.x0) / spacing));
  g.ny = static_cast<int>(std::ceil((footprint.max().y() + margin - g.y0) / spacing));
  g.heights.resize(static_cast<std::size_t>(g.nx + 1) * (g.ny + 1));
  for (int j = 0; j <= g.ny; ++j) {
    for (int i = 0; i <= g.nx; ++i) {
      g.heights[static_cast<std::size_t>(j) * (g.nx + 1) + i] =
          ground(g.x0 + i * spacing, g.y0 + j * spacing);
    }
  }
  return g;
}

std::vector<TriangleMesh> TerrainTiles(const TerrainGrid& g, const RoadClearance& clearance,
                                       int tile_cells) {
  std::vector<TriangleMesh> tiles;
  for (int j0 = 0; j0 < g.ny; j0 += tile_cells) {
    for (int i0 = 0; i0 < g.nx; i0 += tile_cells) {
      TriangleMesh& mesh = tiles.emplace_back();
      const int i1 = std::min(g.nx, i0 + tile_cells), j1 = std::min(g.ny, j0 + tile_cells);
      const int w = i1 - i0 + 1;
      for (int j = j0; j <= j1; ++j) {
        for (int i = i0; i <= i1; ++i) mesh.AddVertex(g.Node(i, j));
      }
      for (int j = 0; j < j1 - j0; ++j) {
        for (int i = 0; i < i1 - i0; ++i) {
          const int a = j * w + i, b = a + 1, c = a + w + 1, d = a + w;
          for (const std::array<int, 3>& t : {std::array<int, 3>{a, b, c}, {a, c, d}}) {
            const Vec3 centroid =
                (mesh.vertices[t[0]] + mesh.vertices[t[1]] + mesh.vertices[t[2]]) / 3.0;
            mesh.AddTriangle(t[0], t[1], t[2],
                             clearance.OnRoad(centroid.head<2>()) ? SurfaceMaterial::kRoad
                                                                  : SurfaceMaterial::kGround);
          }
        }
      }
    }
  }
  return tiles;
}

std::vector<TriangleMesh> ObjectTiles(const WorldLayout& layout, double tile_m,
                                      const LidarWorldOptions& options) {
  std::map<std::pair<long, long>, TriangleMesh> tiles;  // ordered: deterministic
  const auto tile_of = [&](const Vec3& p) -> TriangleMesh& {
    return tiles[{std::lround(std::floor(p.x() / tile_m)),
                  std::lround(std::floor(p.y() / tile_m))}];
  };
  for (const WorldBox& b : layout.boxes) tile_of(b.centre_world).AddBox(b);
  for (const WorldCylinder& c : layout.cylinders) {
    tile_of(c.base_world).AddCylinder(c, options.cylinder_sides);
  }
  for (const WorldSphere& sp : layout.spheres) {
    tile_of(sp.centre_world).AddSphere(sp, options.sphere_subdivisions);
  }
  std::vector<TriangleMesh> out;
  for (auto& [key, mesh] : tiles) out.push_back(std::move(mesh));
  return out;
}

}  // namespace statebench::sensors
