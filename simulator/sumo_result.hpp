// What one SUMO run of a scenario leaves for the rest of the simulator: the ego's reference
// (route centre line and speed profile) for the vehicle model, and the road and traffic geometry
// for the terrain fit and the lidar world.
//
// Frames and conventions: positions are ENU metres (SUMO network coordinates); yaw is ENU,
// radians counter-clockwise from east (SUMO's angle is degrees clockwise from north:
// yaw = pi/2 - angle); pitch follows FLU body axes with R = Rz(yaw) Ry(pitch), so a nose-up
// grade gives a negative pitch (pitch = -slope). Sample times are those SUMO's own outputs
// (FCD) give the same state: the ego appears at t = 0 at its departure position and speed, and
// the state after each further step is labelled with the step's start time + step_s.
#pragma once

#include <limits>
#include <string>
#include <vector>

#include "core/eigen_types.hpp"
#include "simulator/driven_path.hpp"

namespace statebench::sim {

struct EgoSample {
  double t_s = 0.0;
  std::string lane_id;
  std::size_t driven_lane = 0;  // index into SumoResult::driven_path.lanes()
  double lane_pos_m = 0.0;      // SUMO lane position of the front bumper
  double s_m = 0.0;             // arc length of the front bumper on the driven path
  double v_mps = 0.0;           // SUMO speed (lane-length units per second)
  double a_mps2 = 0.0;          // SUMO acceleration over the step that ended at t_s
  // Speed along the driven path, v_mps * shape length / lane length of the current lane. Equal
  // to v_mps on normal lanes (within 1e-4); junction lanes differ by up to a few percent, so
  // s_m is the integral of ds_dt_mps, not exactly of v_mps.
  double ds_dt_mps = 0.0;
  Vec3 p_world_front = Vec3::Zero();  // front bumper centre on the road surface
  double yaw_rad = 0.0;
  double slope_rad = 0.0;  // road grade along the heading, positive uphill
  char tls_state = ' ';    // next traffic light's signal for the ego: r y g G, ' ' none
  double tls_distance_m = std::numeric_limits<double>::infinity();
  // Gap to the leader within 100 m, minus the ego's minimum gap (as SUMO reports it: about 0
  // when stopped behind a vehicle).
  double leader_gap_m = std::numeric_limits<double>::infinity();
  bool operator==(const EgoSample&) const = default;
};

struct LaneGeometry {
  std::string id;
  std::string edge_id;
  bool internal = false;  // junction-internal lane (id starts with ':')
  double width_m = 0.0;
  double length_m = 0.0;    // SUMO's lane length
  std::vector<Vec3> shape;  // centre line
  bool operator==(const LaneGeometry&) const = default;
};

// A junction's outline (SUMO's internal junctions, which have none, are left out).
struct JunctionGeometry {
  std::string id;
  std::vector<Vec3> shape;  // outline polygon, not closed
  bool operator==(const JunctionGeometry&) const = default;
};

// A traffic vehicle as a box: centre of the box, orientation R = Rz(yaw) Ry(pitch), extents.
struct TrafficBox {
  std::string id;
  Vec3 p_world_center = Vec3::Zero();  // front bumper moved back L/2 and up H/2 in body axes
  double yaw_rad = 0.0;
  double pitch_rad = 0.0;
  double length_m = 0.0;
  double width_m = 0.0;
  double height_m = 0.0;
  double v_mps = 0.0;
  bool operator==(const TrafficBox&) const = default;
};

struct TrafficFrame {
  double t_s = 0.0;
  std::vector<TrafficBox> boxes;
  bool operator==(const TrafficFrame&) const = default;
};

struct SumoResult {
  double step_s = 0.1;
  std::vector<EgoSample> ego;  // every step from t = 0 to the duration or arrival
  bool ego_arrived = false;    // the ego reached the end of its route
  // Lanes the ego drove, in order; it extends past the last sample (the run continues a little
  // so the path tracker can look ahead), unless the route ended.
  DrivenPath driven_path;
  std::vector<LaneGeometry> lanes;  // every lane of the network
  std::vector<JunctionGeometry> junctions;
  std::vector<TrafficFrame> traffic;  // one frame per ego sample, same t_s

  // Centre lines of all lanes, for Terrain::FitPolylines.
  std::vector<std::vector<Vec3>> LaneShapes() const;
  // Points of all lane centre lines resampled every `spacing_m` (shape vertices kept).
  std::vector<Vec3> LanePoints(double spacing_m) const;

  bool operator==(const SumoResult&) const = default;
};

}  // namespace statebench::sim
