// Outer edges of the drivable area: the stretches of lane edges with no other lane or junction
// beside them. Kerbs, buildings and street furniture are placed along these runs.
#pragma once

#include <vector>

#include "core/eigen_types.hpp"
#include "sensors/road_clearance.hpp"
#include "sensors/world_inputs.hpp"

namespace statebench::sensors {

struct BoundarySample {
  Vec2 p_edge;   // on the lane edge, m
  Vec2 tangent;  // unit, along the lane's direction of travel
  Vec2 outward;  // unit, pointing away from the road
  double s_m;    // arc length of this sample along its run
  double ds_m;   // length of edge this sample stands for (centred on it)
};

// Samples about every step_m along one continuous outer edge.
struct BoundaryRun {
  std::vector<BoundarySample> samples;
  double Length() const;
  // Sample whose stretch contains arc length s (clamped to the run).
  const BoundarySample& At(double s) const;
  // Point on the edge at arc length s: the sample's point moved along its tangent.
  Vec2 PointAt(double s) const;
};

// A lane edge sample is outer when the point probe_m beyond it is on no road. Runs shorter than
// min_length_m are dropped. Order follows the lanes, left edge before right: deterministic.
std::vector<BoundaryRun> FindOuterBoundaries(const RoadGeometry& roads,
                                             const RoadClearance& clearance, double step_m,
                                             double probe_m, double min_length_m);

}  // namespace statebench::sensors
