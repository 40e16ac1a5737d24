// What the lidar world is built from, as plain data: the road network's geometry, the terrain
// height and the traffic. The simulator adapts its SUMO results to these types; nothing here
// depends on the simulator.
//
// Frame: world = local ENU (x east, y north, z up), metres.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "core/eigen_types.hpp"
#include "core/time.hpp"

namespace statebench::sensors {

// One lane: its centre polyline (z = road surface height) and its full width.
struct LaneShape {
  std::vector<Vec3> centre;
  double width_m = 3.2;
};

// The drivable area: lane corridors plus junction polygons (outline, any winding, not closed:
// the last vertex connects back to the first).
struct RoadGeometry {
  std::vector<LaneShape> lanes;
  std::vector<std::vector<Vec3>> junctions;
};

// Terrain (and road surface) height h(x, y) in the world frame, m. Must be smooth enough to be
// represented by a triangle grid of the chosen spacing, deterministic and callable from one thread.
using GroundHeightFn = std::function<double(double x, double y)>;

// A traffic vehicle as a box at one SUMO step.
struct TrafficBox {
  std::string id;
  Vec3 centre_world = Vec3::Zero();  // geometric centre of the box (not SUMO's front bumper)
  double yaw_rad = 0.0;              // heading of the box's length axis, CCW from east
  double pitch_rad = 0.0;            // nose-up positive (road slope)
  double length_m = 4.5;
  double width_m = 1.8;
  double height_m = 1.5;
};

// All traffic boxes at one SUMO step.
struct TrafficFrame {
  TimeNs t_ns = 0;
  std::vector<TrafficBox> boxes;
};

}  // namespace statebench::sensors
