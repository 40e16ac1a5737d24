// Outer edges of the drivable area: the stretches of lane edges with no other lane or junction
// beside them. Kerbs, buildings and street furniture are placed along these runs.
#pragma once

#include <vector>

#include "core/eigen_types.hpp"
#include "sensors/road_clearance.hpp"
#include "sensors/world_inputs.hpp"

namespace statebench::sensors {

struct BoundarySample {
  Vec2 p_edge;    // on the lane edge, m
  Vec2 tangent;   // unit, along the lane's direction of travel
  Vec2 outward;   // unit, pointing away from the road
};

// Samples every step_m along one continuous outer edge.
struct BoundaryRun {
  double step_m = 1.0;
  std::vector<BoundarySample> samples;
  double Length() const { return step_m * static_cast<double>(samples.size()); }
  // Sample nearest to arc length s (clamped to the run).
  const BoundarySample& At(double s) const;
};

// A lane edge sample is outer when the point probe_m beyond it is on no road. Runs shorter than
// min_length_m are dropped. Order follows the lanes, left edge before right: deterministic.
std::vector<BoundaryRun> FindOuterBoundaries(const RoadGeometry& roads,
                                             const RoadClearance& clearance, double step_m,
                                             double probe_m, double min_length_m);

}  // namespace statebench::sensors
