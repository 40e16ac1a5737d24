// Traffic as the lidar sees it during one sweep: every vehicle's motion over [t0, t1] with the
// ball that holds it throughout, intersected exactly at each ray's own firing time (no re-posing
// of shared objects, so rays of one sweep can be cast from many threads).
//
// The sweep's rays come in fans (a lidar column: one origin, one firing time): PoseFor keeps the
// vehicles whose ball the fan may reach and poses them at the column's time, once; Cast then
// tests each ray of the fan against those few boxes (a ball test, then the exact slab test).
#pragma once

#include <limits>
#include <optional>
#include <vector>

#include "core/eigen_types.hpp"
#include "core/time.hpp"
#include "sensors/posed_traffic_box.hpp"
#include "sensors/ray_fan.hpp"
#include "sensors/ray_hit.hpp"
#include "sensors/traffic_timeline.hpp"

namespace statebench::sensors {

class TrafficWindow {
 public:
  // Only vehicles whose swept box meets `region` (e.g. the sensor's reach during the sweep) are
  // kept; the default region holds everything.
  TrafficWindow(const TrafficTimeline& traffic, TimeNs t0_ns, TimeNs t1_ns,
                const Eigen::AlignedBox3d& region =
                    Eigen::AlignedBox3d(Vec3::Constant(-std::numeric_limits<double>::infinity()),
                                        Vec3::Constant(std::numeric_limits<double>::infinity())));

  // The vehicles present at t_ns (in [t0, t1]) that a ray of `fan_world` from origin_world may
  // meet within max_range_m, posed at t_ns, in the window's vehicle order (*out is replaced).
  void PoseFor(const RayFan& fan_world, const Vec3& origin_world, double max_range_m, TimeNs t_ns,
               std::vector<PosedTrafficBox>* out) const;

  // Closest of the posed boxes hit by origin + r * direction, 0 < r <= max_range_m (the first
  // in order on equal ranges). A ray starting inside a box ignores that box. Thread-safe.
  static std::optional<RayHit> Cast(const std::vector<PosedTrafficBox>& posed,
                                    const Vec3& origin_world, const Vec3& unit_direction_world,
                                    double max_range_m);

  // The same for one ray with every vehicle at its pose at t_ns.
  std::optional<RayHit> Cast(const Vec3& origin_world, const Vec3& unit_direction_world,
                             double max_range_m, TimeNs t_ns) const;

  std::size_t vehicle_count() const { return motions_.size(); }

 private:
  // A vehicle of motions_ and the ball that holds it during the window.
  struct SweptBall {
    std::size_t motion;
    Vec3 centre_world;
    double radius_m;
  };
  std::vector<TrafficMotion> motions_;
  std::vector<SweptBall> balls_;  // the vehicles meeting the region, in motions_ order
};

}  // namespace statebench::sensors
