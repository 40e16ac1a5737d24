#include "sensors/ray_fan.hpp"

#include <algorithm>
#include <cassert>
#include <cmath>

namespace statebench::sensors {
namespace {

// Rounding of the bounds (directions turned in double differ from the turned fan by ~1e-16).
constexpr double kAngleSlack = 1e-9;
constexpr double kDistanceSlackM = 1e-6;

}  // namespace

RayFan RayFan::Rotated(const Quat& R) const {
  RayFan out = *this;
  out.normal = R * normal;
  out.axis = R * axis;
  return out;
}

bool RayFan::MayMeetBall(const Vec3& origin, double max_range_m, const Vec3& centre,
                         double radius) const {
  // A point p = origin + r d of the fan (0 < r <= max_range_m) has |normal . (p - origin)| <=
  // max_range_m * spread and axis . (p - origin) >= 0 (min_along_axis >= 0); the ball holds
  // points within `radius` of its centre.
  const Vec3 v = centre - origin;
  const double reach = radius + kDistanceSlackM;
  if (std::abs(normal.dot(v)) > reach + max_range_m * (spread + kAngleSlack)) return false;
  if (min_along_axis >= 0.0 && axis.dot(v) < -reach) return false;
  const double far = reach + max_range_m;
  return v.squaredNorm() <= far * far;
}

RayFan FanOf(std::span<const Vec3> unit_directions) {
  assert(!unit_directions.empty());
  const Vec3& first = unit_directions.front();
  RayFan fan;
  Vec3 normal = first.cross(unit_directions.back());
  if (normal.norm() < 1e-6) normal = first.unitOrthogonal();
  fan.normal = normal.normalized();
  Vec3 sum = Vec3::Zero();
  for (const Vec3& d : unit_directions) sum += d;
  fan.axis = sum.norm() > 1e-6 ? Vec3(sum.normalized()) : first;
  fan.spread = 0.0;
  fan.min_along_axis = 1.0;
  for (const Vec3& d : unit_directions) {
    fan.spread = std::max(fan.spread, std::abs(fan.normal.dot(d)));
    fan.min_along_axis = std::min(fan.min_along_axis, fan.axis.dot(d));
  }
  return fan;
}

}  // namespace statebench::sensors
