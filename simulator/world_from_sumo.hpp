// The lidar world of a scenario, built from its SUMO run: every lane (junction-internal ones
// included) and junction outline of the network as the drivable area, the fitted terrain as the
// ground, and the traffic of the run as moving boxes (sensors/lidar_world.hpp).
//
// Conventions: both sides use ENU metres and yaw counter-clockwise from east. Pitch differs:
// SUMO's boxes (sumo_result.hpp) rotate by R = Rz(yaw) Ry(pitch), so nose-up is a negative
// pitch; the lidar's boxes (sensors/world_inputs.hpp) take nose-up as positive, with
// R = Rz(yaw) Ry(-pitch). The same orientation is therefore pitch_lidar = -pitch_sumo.
#pragma once

#include <cstdint>
#include <memory>

#include "sensors/lidar_world.hpp"
#include "sensors/traffic_timeline.hpp"
#include "sensors/world_inputs.hpp"
#include "sensors/world_layout.hpp"
#include "simulator/sumo_result.hpp"
#include "simulator/terrain.hpp"

namespace statebench::sim {

struct WorldFromSumoOptions {
  sensors::WorldLayoutOptions layout;  // layout.seed: which buildings, trees, ... stand where
  sensors::LidarWorldOptions world;
};

sensors::RoadGeometry ToRoadGeometry(const SumoResult& sumo);
sensors::TrafficBox ToLidarTrafficBox(const TrafficBox& box);
// One frame per SUMO step, stamped FromSeconds(t_s); throws InputError if SUMO's frames are not
// strictly increasing in time or repeat a vehicle id.
sensors::TrafficTimeline ToTrafficTimeline(const SumoResult& sumo);
// h(x, y) of the terrain; the function holds its own copy of the terrain.
sensors::GroundHeightFn GroundHeightOf(const Terrain& terrain);

// The static world with the run's traffic set. Throws InputError on bad options.
std::shared_ptr<sensors::LidarWorld> BuildLidarWorld(const SumoResult& sumo, const Terrain& terrain,
                                                     const WorldFromSumoOptions& options);

}  // namespace statebench::sim
