// Analytic road networks (no SUMO) for tests, benchmarks and quick scenarios. Right-hand traffic:
// lane k of a direction (k = 0 next to the axis) has its centre (k + 0.5) lane widths to the
// right of the street axis. Centre polylines are sampled every vertex_spacing_m with z = ground.
#pragma once

#include "sensors/world_inputs.hpp"

namespace statebench::sensors {

// A two-way street along x (axis y = 0) from x_begin_m to x_end_m, no junctions.
RoadGeometry MakeStraightRoad(double x_begin_m, double x_end_m, int lanes_per_direction,
                              double lane_width_m, const GroundHeightFn& ground,
                              double vertex_spacing_m = 10.0);

// A Manhattan grid of nodes_x * nodes_y junctions, block_m apart (node (i, j) at (i, j) * block_m),
// two-way streets between neighbours and square junction polygons at the nodes.
RoadGeometry MakeGridRoads(int nodes_x, int nodes_y, double block_m, int lanes_per_direction,
                           double lane_width_m, const GroundHeightFn& ground,
                           double vertex_spacing_m = 10.0);

}  // namespace statebench::sensors
