#include "sensors/synthetic_roads.hpp"

#include <algorithm>
#include <cmath>

namespace statebench::sensors {
namespace {

// Lanes of a two-way street from a to b (ground plane), both directions.
void AddStreet(const Vec2& a, const Vec2& b, int lanes, double width, const GroundHeightFn& ground,
               double spacing, RoadGeometry* roads) {
  const double length = (b - a).norm();
  const Vec2 along = (b - a) / length;
  const Vec2 right(along.y(), -along.x());
  const int n = std::max(1, static_cast<int>(std::ceil(length / spacing)));
  for (int k = 0; k < lanes; ++k) {
    for (const int dir : {1, -1}) {
      LaneShape lane;
      lane.width_m = width;
      const Vec2 offset = dir * (k + 0.5) * width * right;
      for (int i = 0; i <= n; ++i) {
        const double u = dir > 0 ? static_cast<double>(i) / n : 1.0 - static_cast<double>(i) / n;
        const Vec2 p = a + u * (b - a) + offset;
        lane.centre.emplace_back(p.x(), p.y(), ground(p.x(), p.y()));
      }
      roads->lanes.push_back(std::move(lane));
    }
  }
}

}  // namespace

RoadGeometry MakeStraightRoad(double x_begin_m, double x_end_m, int lanes_per_direction,
                              double lane_width_m, const GroundHeightFn& ground,
                              double vertex_spacing_m) {
  RoadGeometry roads;
  AddStreet(Vec2(x_begin_m, 0.0), Vec2(x_end_m, 0.0), lanes_per_direction, lane_width_m, ground,
            vertex_spacing_m, &roads);
  return roads;
}

RoadGeometry MakeGridRoads(int nodes_x, int nodes_y, double block_m, int lanes_per_direction,
                           double lane_width_m, const GroundHeightFn& ground,
                           double vertex_spacing_m) {
  RoadGeometry roads;
  const double half = lanes_per_direction * lane_width_m + 1.0;  // junction half size
  for (int j = 0; j < nodes_y; ++j) {
    for (int i = 0; i < nodes_x; ++i) {
      const Vec2 c(i * block_m, j * block_m);
      if (i + 1 < nodes_x) {
        AddStreet(c + Vec2(half, 0.0), c + Vec2(block_m - half, 0.0), lanes_per_direction,
                  lane_width_m, ground, vertex_spacing_m, &roads);
      }
      if (j + 1 < nodes_y) {
        AddStreet(c + Vec2(0.0, half), c + Vec2(0.0, block_m - half), lanes_per_direction,
                  lane_width_m, ground, vertex_spacing_m, &roads);
      }
      std::vector<Vec3> square;
      for (const Vec2& corner :
           {Vec2(-half, -half), Vec2(half, -half), Vec2(half, half), Vec2(-half, half)}) {
        const Vec2 p = c + corner;
        square.emplace_back(p.x(), p.y(), ground(p.x(), p.y()));
      }
      roads.junctions.push_back(std::move(square));
    }
  }
  return roads;
}

}  // namespace statebench::sensors
