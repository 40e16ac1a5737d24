#include "sensors/posed_traffic_box.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace statebench::sensors {
namespace {

// Slack of the ball test: rounding of the squared distances (ranges of a few hundred metres).
constexpr double kBallSlackM = 1e-3;

Mat3 BoxRotation(const TrafficBox& box) {
  // Yaw about z, then nose-up pitch (a negative rotation about the box's y axis, which points
  // left).
  return (Eigen::AngleAxisd(box.yaw_rad, Vec3::UnitZ()) *
          Eigen::AngleAxisd(-box.pitch_rad, Vec3::UnitY()))
      .toRotationMatrix();
}

}  // namespace

PosedTrafficBox PoseTrafficBox(const TrafficBox& box) {
  const Vec3 half(0.5 * box.length_m, 0.5 * box.width_m, 0.5 * box.height_m);
  return {BoxRotation(box), box.centre_world, half, half.norm()};
}

std::optional<RayHit> IntersectTrafficBox(const PosedTrafficBox& box, const Vec3& origin_world,
                                          const Vec3& unit_direction_world, double max_range_m) {
  const Mat3& r = box.R_world_box;
  const Vec3 o = r.transpose() * (origin_world - box.centre_world);
  const Vec3 d = r.transpose() * unit_direction_world;
  const Vec3& half = box.half_m;
  double t_enter = -std::numeric_limits<double>::infinity();
  double t_exit = std::numeric_limits<double>::infinity();
  int enter_axis = -1;
  for (int i = 0; i < 3; ++i) {
    if (d[i] == 0.0) {
      if (std::abs(o[i]) > half[i]) return std::nullopt;
      continue;
    }
    double t_a = (-half[i] - o[i]) / d[i];
    double t_b = (half[i] - o[i]) / d[i];
    if (t_a > t_b) std::swap(t_a, t_b);
    if (t_a > t_enter) {
      t_enter = t_a;
      enter_axis = i;
    }
    t_exit = std::min(t_exit, t_b);
  }
  if (enter_axis < 0 || t_enter > t_exit || t_enter <= 0.0 || t_enter > max_range_m) {
    return std::nullopt;
  }
  Vec3 n_box = Vec3::Zero();
  n_box[enter_axis] = d[enter_axis] > 0.0 ? -1.0 : 1.0;
  return RayHit{t_enter, r * n_box, SurfaceMaterial::kVehicle};
}

std::optional<RayHit> IntersectTrafficBox(const TrafficBox& box, const Vec3& origin_world,
                                          const Vec3& unit_direction_world, double max_range_m) {
  return IntersectTrafficBox(PoseTrafficBox(box), origin_world, unit_direction_world, max_range_m);
}

bool MayMeetBox(const PosedTrafficBox& box, const Vec3& origin_world,
                const Vec3& unit_direction_world, double max_range_m) {
  // The ray's closest approach to the centre, over r in [0, max_range_m].
  const Vec3 v = box.centre_world - origin_world;
  const double along = std::clamp(v.dot(unit_direction_world), 0.0, max_range_m);
  const double reach = box.radius_m + kBallSlackM;
  return (v - along * unit_direction_world).squaredNorm() <= reach * reach;
}

}  // namespace statebench::sensors
