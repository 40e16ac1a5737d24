// A vehicle box at one instant, posed for exact ray tests: its rotation (yaw about z, then
// nose-up pitch), centre and half extents, and the radius of its bounding ball. Posing once per
// lidar column instead of once per ray saves the rotation's sines and cosines; the intersection
// is the same arithmetic either way (same bits).
#pragma once

#include <optional>

#include "core/eigen_types.hpp"
#include "sensors/ray_hit.hpp"
#include "sensors/world_inputs.hpp"

namespace statebench::sensors {

struct PosedTrafficBox {
  Mat3 R_world_box;
  Vec3 centre_world;
  Vec3 half_m;      // half length, width, height
  double radius_m;  // of the ball around the centre that holds the box
};

PosedTrafficBox PoseTrafficBox(const TrafficBox& box);

// Exact ray / oriented box intersection (slab method in the box frame). Returns the entry range
// and the outward normal of the entry face; nullopt when missed, behind the origin, beyond
// max_range_m, or when the origin is inside the box.
std::optional<RayHit> IntersectTrafficBox(const PosedTrafficBox& box, const Vec3& origin_world,
                                          const Vec3& unit_direction_world, double max_range_m);
std::optional<RayHit> IntersectTrafficBox(const TrafficBox& box, const Vec3& origin_world,
                                          const Vec3& unit_direction_world, double max_range_m);

// False when the ray origin + r d, 0 < r <= max_range_m, cannot meet the box (it misses its
// bounding ball): a cheap test before IntersectTrafficBox.
bool MayMeetBox(const PosedTrafficBox& box, const Vec3& origin_world,
                const Vec3& unit_direction_world, double max_range_m);

}  // namespace statebench::sensors
