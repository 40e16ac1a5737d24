#include "simulator/world_from_sumo.hpp"

#include <utility>
#include <vector>

namespace statebench::sim {

sensors::RoadGeometry ToRoadGeometry(const SumoResult& sumo) {
  sensors::RoadGeometry roads;
  roads.lanes.reserve(sumo.lanes.size());
  for (const LaneGeometry& lane : sumo.lanes) {
    if (lane.shape.size() < 2) continue;
    roads.lanes.push_back(sensors::LaneShape{lane.shape, lane.width_m});
  }
  for (const JunctionGeometry& junction : sumo.junctions) {
    if (junction.shape.size() >= 3) roads.junctions.push_back(junction.shape);
  }
  return roads;
}

sensors::TrafficBox ToLidarTrafficBox(const TrafficBox& box) {
  sensors::TrafficBox out;
  out.id = box.id;
  out.centre_world = box.p_world_center;
  out.yaw_rad = box.yaw_rad;
  out.pitch_rad = -box.pitch_rad;  // see the header: nose-up negative -> nose-up positive
  out.length_m = box.length_m;
  out.width_m = box.width_m;
  out.height_m = box.height_m;
  return out;
}

sensors::TrafficTimeline ToTrafficTimeline(const SumoResult& sumo) {
  std::vector<sensors::TrafficFrame> frames;
  frames.reserve(sumo.traffic.size());
  for (const TrafficFrame& frame : sumo.traffic) {
    sensors::TrafficFrame f;
    f.t_ns = FromSeconds(frame.t_s);
    f.boxes.reserve(frame.boxes.size());
    for (const TrafficBox& box : frame.boxes) f.boxes.push_back(ToLidarTrafficBox(box));
    frames.push_back(std::move(f));
  }
  return sensors::TrafficTimeline(std::move(frames));
}

sensors::GroundHeightFn GroundHeightOf(const Terrain& terrain) {
  return [terrain](double x, double y) { return terrain.Height(x, y); };
}

std::shared_ptr<sensors::LidarWorld> BuildLidarWorld(const SumoResult& sumo, const Terrain& terrain,
                                                     const WorldFromSumoOptions& options) {
  std::shared_ptr<sensors::LidarWorld> world = sensors::LidarWorld::Build(
      ToRoadGeometry(sumo), GroundHeightOf(terrain), options.layout, options.world);
  world->SetTraffic(ToTrafficTimeline(sumo));
  return world;
}

}  // namespace statebench::sim
