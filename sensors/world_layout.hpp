// The static objects of the lidar world, generated along the road network from a seed: kerbs on
// the outer lane edges, buildings set back from the road, poles, trees and parked cars. Pure
// geometry (no Bullet); LidarWorld turns it into triangle meshes.
//
// Determinism: one random stream, MakeRng(seed, "world"), consumed in a fixed order (buildings,
// parked cars, poles, trees; each along the outer boundary runs in lane order). No object ever
// overlaps a lane corridor or a junction: each footprint is checked against all of them.
#pragma once

#include <cstdint>
#include <vector>

#include "core/eigen_types.hpp"
#include "sensors/surface_material.hpp"
#include "sensors/world_inputs.hpp"

namespace statebench::sensors {

// Box standing upright, rotated about z only.
struct WorldBox {
  Vec3 centre_world = Vec3::Zero();
  double yaw_rad = 0.0;        // direction of the size.x() axis, CCW from east
  Vec3 size_m = Vec3::Ones();  // length (along yaw), width, height
  SurfaceMaterial material = SurfaceMaterial::kBuilding;
};

// Vertical cylinder from base_world up by height_m.
struct WorldCylinder {
  Vec3 base_world = Vec3::Zero();
  double radius_m = 0.1;
  double height_m = 1.0;
  SurfaceMaterial material = SurfaceMaterial::kPole;
};

struct WorldSphere {
  Vec3 centre_world = Vec3::Zero();
  double radius_m = 1.0;
  SurfaceMaterial material = SurfaceMaterial::kTreeCrown;
};

struct WorldLayout {
  std::vector<WorldBox> boxes;  // kerbs, buildings, parked cars, extra boxes
  std::vector<WorldCylinder> cylinders;
  std::vector<WorldSphere> spheres;
};

struct KerbOptions {
  bool enabled = true;
  double height_m = 0.13;
  double width_m = 0.25;
  double piece_length_m = 2.0;  // pieces follow the terrain and the lane's bends
  double gap_to_lane_m = 0.02;  // between lane edge and kerb face
};

struct BuildingOptions {
  bool enabled = true;
  double probability = 0.85;                        // that a facade slot holds a building
  double setback_min_m = 3.0, setback_max_m = 8.0;  // lane edge to facade
  double facade_min_m = 10.0, facade_max_m = 30.0;
  double depth_min_m = 8.0, depth_max_m = 18.0;
  double height_min_m = 6.0, height_max_m = 24.0;
  double gap_min_m = 2.0, gap_max_m = 12.0;  // between facades along the road
  double road_clearance_m = 1.0;
};

struct PoleOptions {
  double spacing_m = 35.0;  // mean distance along a boundary; <= 0 disables
  double offset_m = 0.8;    // lane edge to pole axis
  double radius_m = 0.1;
  double height_min_m = 6.0, height_max_m = 9.0;
};

struct TreeOptions {
  double spacing_m = 18.0;  // mean distance along a boundary; <= 0 disables
  double probability = 0.6;
  double offset_min_m = 2.5, offset_max_m = 4.0;  // lane edge to trunk axis
  double trunk_radius_m = 0.18;
  double trunk_height_min_m = 2.0, trunk_height_max_m = 3.5;
  double crown_radius_min_m = 1.0, crown_radius_max_m = 2.0;  // crowns stay off the road
};

struct ParkedCarOptions {
  double probability = 0.25;  // per slot; <= 0 disables
  double offset_m = 0.5;      // lane edge to the car's near side (behind the kerb)
  double length_m = 4.5, width_m = 1.8, height_m = 1.5;
  double gap_min_m = 1.0, gap_max_m = 6.0;
};

struct WorldLayoutOptions {
  std::uint64_t seed = 0;
  KerbOptions kerbs;
  BuildingOptions buildings;
  PoleOptions poles;
  TreeOptions trees;
  ParkedCarOptions parked_cars;
  double boundary_step_m = 1.0;
  std::vector<WorldBox> extra_boxes;  // added as given (centre z as given), not checked
};

// Throws InputError when an option is out of range (names the field).
WorldLayout BuildWorldLayout(const RoadGeometry& roads, const GroundHeightFn& ground,
                             const WorldLayoutOptions& options);

}  // namespace statebench::sensors
