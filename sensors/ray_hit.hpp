// Result of a ray cast into the lidar world.
#pragma once

#include "core/eigen_types.hpp"
#include "sensors/surface_material.hpp"

namespace statebench::sensors {

struct RayHit {
  double range_m = 0.0;               // distance from the ray origin along the unit direction
  Vec3 normal_world = Vec3::UnitZ();  // unit surface normal, facing the ray origin
  SurfaceMaterial material = SurfaceMaterial::kGround;
};

}  // namespace statebench::sensors
