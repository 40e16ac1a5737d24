// Traffic as the lidar sees it during one sweep: every vehicle's motion over [t0, t1], indexed in
// a Bullet btDbvt by its swept bounding box, and intersected exactly at each ray's own firing
// time (no re-posing of shared objects, so rays of one sweep can be cast from many threads).
#pragma once

#include <limits>
#include <memory>
#include <optional>
#include <vector>

#include "core/eigen_types.hpp"
#include "core/time.hpp"
#include "sensors/ray_hit.hpp"
#include "sensors/traffic_timeline.hpp"

namespace statebench::sensors {

class TrafficWindow {
 public:
  // Only vehicles whose swept box meets `region` (e.g. the sensor's reach during the sweep) are
  // indexed; the default region holds everything.
  TrafficWindow(const TrafficTimeline& traffic, TimeNs t0_ns, TimeNs t1_ns,
                const Eigen::AlignedBox3d& region =
                    Eigen::AlignedBox3d(Vec3::Constant(-std::numeric_limits<double>::infinity()),
                                        Vec3::Constant(std::numeric_limits<double>::infinity())));
  ~TrafficWindow();
  TrafficWindow(const TrafficWindow&) = delete;
  TrafficWindow& operator=(const TrafficWindow&) = delete;

  // Closest vehicle box hit by origin + r * direction, 0 < r <= max_range_m, with every vehicle at
  // its pose at t_ns (t_ns in [t0, t1]). A ray starting inside a box ignores that box.
  // Thread-safe.
  std::optional<RayHit> Cast(const Vec3& origin_world, const Vec3& unit_direction_world,
                             double max_range_m, TimeNs t_ns) const;

  std::size_t vehicle_count() const { return motions_.size(); }

 private:
  struct Tree;
  std::vector<TrafficMotion> motions_;
  std::unique_ptr<Tree> tree_;
};

// Exact ray / oriented box intersection (slab method in the box frame). Returns the entry range
// and the outward normal of the entry face; nullopt when missed, behind the origin, beyond
// max_range_m, or when the origin is inside the box.
std::optional<RayHit> IntersectTrafficBox(const TrafficBox& box, const Vec3& origin_world,
                                          const Vec3& unit_direction_world, double max_range_m);

}  // namespace statebench::sensors
