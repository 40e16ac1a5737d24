#include "estimator/lidar_preprocessing.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>

#include "estimator/voxel_index_table.hpp"

namespace statebench::est {

SweepMotion ConstantVelocitySweepMotion(const SE3& T_prev_curr, double dt_s) {
  const Vec6 twist = T_prev_curr.Log() / dt_s;  // (v, omega) in the lidar frame
  return [twist](double t_s) { return SE3::Exp(t_s * twist); };
}

SweepMotion StaticSweepMotion() {
  return [](double) { return SE3::Identity(); };
}

SweepMotion TabulatedSweepMotion(std::vector<std::pair<double, SE3>> table) {
  // SE3::Interpolate(T0, T1, a) = T0 Exp(a Log(T0^-1 T1)): the segments' logarithms are taken
  // once here instead of at every point time (the same expression, so the same bits), and the
  // segment is found by bisection (the first k with t <= t_k, as a forward scan finds it).
  std::vector<double> times;
  std::vector<Vec6> segment_logs;  // [k]: Log(T_{k-1}^-1 T_k), k >= 1
  times.reserve(table.size());
  segment_logs.reserve(table.size());
  for (std::size_t k = 0; k < table.size(); ++k) {
    times.push_back(table[k].first);
    segment_logs.push_back(k == 0 ? Vec6::Zero()
                                  : Vec6((table[k - 1].second.Inverse() * table[k].second).Log()));
  }
  return [table = std::move(table), times = std::move(times),
          segment_logs = std::move(segment_logs)](double ts) {
    if (ts <= times.front()) return table.front().second;
    if (!(ts <= times.back())) return table.back().second;  // NaN too, as the scan did
    const auto k = static_cast<std::size_t>(
        std::lower_bound(times.begin() + 1, times.end(), ts) - times.begin());
    const double a = (ts - times[k - 1]) / (times[k] - times[k - 1]);
    return table[k - 1].second * SE3::Exp(a * segment_logs[k]);
  };
}

std::vector<TimedPoint> FilterScanPoints(const std::vector<LidarPoint>& points,
                                         const LidarFilterOptions& options,
                                         LidarFilterStats* stats) {
  LidarFilterStats s;
  s.points_in = points.size();
  std::vector<TimedPoint> kept;
  kept.reserve(points.size());
  const double min2 = options.min_range_m * options.min_range_m;
  const double max2 = options.max_range_m * options.max_range_m;
  for (const LidarPoint& lp : points) {
    const Vec3 p(lp.x, lp.y, lp.z);
    if (!p.allFinite() || !std::isfinite(lp.t)) {
      ++s.non_finite;
      continue;
    }
    const double r2 = p.squaredNorm();
    if (r2 < min2 || r2 > max2) {
      ++s.out_of_range;
      continue;
    }
    kept.push_back({p, static_cast<double>(lp.t)});
  }
  s.kept = kept.size();
  if (stats != nullptr) *stats = s;
  return kept;
}

std::vector<Vec3> DeskewPoints(const std::vector<TimedPoint>& points, const SweepMotion& motion) {
  std::vector<Vec3> out;
  out.reserve(points.size());
  // Points of one firing share a time: evaluate the motion once per distinct consecutive time.
  double last_t = std::nan("");
  SE3 T_stamp_t;
  for (const TimedPoint& tp : points) {
    if (tp.t_s != last_t) {
      T_stamp_t = motion(tp.t_s);
      last_t = tp.t_s;
    }
    out.push_back(T_stamp_t * tp.p_lidar);
  }
  return out;
}

std::vector<Vec3> PositionsOf(const std::vector<TimedPoint>& points) {
  std::vector<Vec3> out;
  out.reserve(points.size());
  for (const TimedPoint& tp : points) out.push_back(tp.p_lidar);
  return out;
}

std::vector<Vec3> VoxelDownsample(const std::vector<Vec3>& points, double voxel_size_m) {
  // Room for a quarter of the points as voxels before the table doubles (the odometry's
  // downsamplings of the bench's scans keep 18 to 36 % of their points).
  VoxelIndexTable occupied(points.size() / 4);
  std::vector<Vec3> out;
  for (const Vec3& p : points) {
    const Vec3 s = p / voxel_size_m;
    // Farther than any int voxel index (garbage deskewed by a garbage pose; found by
    // fuzz_estimators): dropped, the cast would be undefined.
    if (!(s.cwiseAbs().maxCoeff() < 1e9)) continue;
    const VoxelKey key{FloorToInt(s.x()), FloorToInt(s.y()), FloorToInt(s.z())};
    const auto next = static_cast<std::uint32_t>(out.size());
    if (occupied.Insert(key, next) == next) out.push_back(p);
  }
  return out;
}

}  // namespace statebench::est
