// Spatial index of the drivable area (lane corridors and junction polygons) on the ground plane,
// answering "is this point on a road" and "does this footprint keep its distance from every road".
//
// A lane corridor is the set of points within width/2 of the lane's centre polyline (a chain of
// capsules, so slightly larger than the lane at its ends: conservative for clearance checks).
#pragma once

#include <cstdint>
#include <unordered_map>
#include <vector>

#include "core/eigen_types.hpp"
#include "sensors/world_inputs.hpp"

namespace statebench::sensors {

class RoadClearance {
 public:
  explicit RoadClearance(const RoadGeometry& roads, double cell_size_m = 16.0);

  // Inside a lane corridor or a junction polygon.
  bool OnRoad(const Vec2& p) const;

  // True when every point of the polygon is at least clearance_m away from every lane corridor
  // and every junction polygon.
  bool PolygonClear(const std::vector<Vec2>& polygon, double clearance_m) const;

  bool empty() const { return segments_.empty() && junctions_.empty(); }

 private:
  struct LaneSegment {
    Vec2 a;
    Vec2 b;
    double half_width_m;
  };
  struct Candidates {
    std::vector<int> segments;
    std::vector<int> junctions;
  };

  std::int64_t CellKey(int ix, int iy) const;
  void Insert(const Vec2& min, const Vec2& max, int id, bool junction);
  Candidates Query(const Vec2& min, const Vec2& max) const;

  double cell_size_m_;
  std::vector<LaneSegment> segments_;
  std::vector<std::vector<Vec2>> junctions_;
  std::unordered_map<std::int64_t, Candidates> cells_;
};

}  // namespace statebench::sensors
