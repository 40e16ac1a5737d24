// A fan of unit directions from one origin, as the channels of a spinning lidar's column: the
// directions lie within `spread` of the plane through the origin normal to `normal`
// (|normal . d| <= spread, 0 for a vertical column of beams) and, when min_along_axis >= 0, in
// the half-space in front of `axis` (axis . d >= min_along_axis). Used to cull what no ray of a
// column can reach (a sphere whose centre lies farther than its radius + max_range * spread from
// the plane, or behind the half-space by more than its radius) before casting its rays.
#pragma once

#include <span>

#include "core/eigen_types.hpp"

namespace statebench::sensors {

struct RayFan {
  Vec3 normal = Vec3::UnitZ();   // unit
  double spread = 1.0;           // max |normal . d| over the fan (1: no plane bound)
  Vec3 axis = Vec3::UnitX();     // unit
  double min_along_axis = -1.0;  // min axis . d over the fan (< 0: no half-space bound)

  // The same fan turned by R (directions R d).
  RayFan Rotated(const Quat& R) const;

  // False when no ray of the fan from `origin`, 0 < r <= max_range_m, meets the ball.
  bool MayMeetBall(const Vec3& origin, double max_range_m, const Vec3& centre, double radius) const;
};

// The fan of `unit_directions` (not empty): the plane through the first and last directions
// (any plane through the first when they are parallel), the axis along their mean.
RayFan FanOf(std::span<const Vec3> unit_directions);

}  // namespace statebench::sensors
