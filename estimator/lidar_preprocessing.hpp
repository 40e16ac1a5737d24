// Lidar scan preprocessing for the odometry: drop unusable points, deskew, downsample.
//
// Frames and times: a LidarScan's points are in the lidar frame at their own capture time
// t (seconds after the scan stamp). Deskewing expresses every point in the lidar frame at the
// scan stamp, p_stamp = T_stamp_t * p_t, where T_stamp_t is the lidar's motion from the stamp
// to time t given by a SweepMotion (constant velocity from the previous estimate, or the
// IMU-propagated motion the estimator provides).
#pragma once

#include <cstddef>
#include <functional>
#include <utility>
#include <vector>

#include "core/eigen_types.hpp"
#include "core/measurements.hpp"
#include "core/se3.hpp"

namespace statebench::est {

// T_stamp_t: pose of the lidar at t seconds after the stamp, relative to its pose at the stamp.
using SweepMotion = std::function<SE3(double t_s)>;

// Constant twist over the sweep: T_stamp_t = Exp(t / dt * Log(T_prev_curr)), where T_prev_curr
// is the lidar motion over the previous scan period dt_s (> 0).
SweepMotion ConstantVelocitySweepMotion(const SE3& T_prev_curr, double dt_s);
SweepMotion StaticSweepMotion();
// Poses tabulated at increasing times (the first at 0), interpolated on SE3 between them and held
// beyond the ends. `table` must not be empty.
SweepMotion TabulatedSweepMotion(std::vector<std::pair<double, SE3>> table);

struct TimedPoint {
  Vec3 p_lidar = Vec3::Zero();
  double t_s = 0.0;
};

struct LidarFilterOptions {
  double min_range_m = 1.0;  // drops returns from the vehicle itself
  double max_range_m = 100.0;
};

struct LidarFilterStats {
  std::size_t points_in = 0;
  std::size_t non_finite = 0;    // NaN/inf coordinate or time
  std::size_t out_of_range = 0;  // outside [min_range, max_range]
  std::size_t kept = 0;
};

std::vector<TimedPoint> FilterScanPoints(const std::vector<LidarPoint>& points,
                                         const LidarFilterOptions& options,
                                         LidarFilterStats* stats);

// Expresses every point in the lidar frame at the scan stamp.
std::vector<Vec3> DeskewPoints(const std::vector<TimedPoint>& points, const SweepMotion& motion);
// Drops the time stamps without motion compensation.
std::vector<Vec3> PositionsOf(const std::vector<TimedPoint>& points);

// Keeps the first point falling in each cubic voxel of the given size, in input order.
std::vector<Vec3> VoxelDownsample(const std::vector<Vec3>& points, double voxel_size_m);

}  // namespace statebench::est
