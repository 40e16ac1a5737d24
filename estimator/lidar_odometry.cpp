#include "estimator/lidar_odometry.hpp"

#include <cmath>

namespace statebench::est {

LidarOdometry::LidarOdometry(const LidarOdometryOptions& options)
    : options_(options),
      map_({.voxel_size_m = options.voxel_size_m,
            .max_points_per_voxel = options.max_points_per_voxel,
            .max_range_m = options.max_range_m}) {}

double LidarOdometry::AdaptiveThreshold() const {
  if (model_error_count_ == 0) return options_.initial_threshold_m;
  return std::sqrt(model_error_sse_ / static_cast<double>(model_error_count_));
}

void LidarOdometry::UpdateThreshold(const SE3& predicted, const SE3& estimated) {
  const SE3 deviation = predicted.Inverse() * estimated;
  const double angle = so3::Log(deviation.rotation()).norm();
  const double model_error =
      deviation.translation().norm() + 2.0 * options_.max_range_m * std::sin(angle / 2.0);
  if (model_error > options_.min_motion_m) {
    model_error_sse_ += model_error * model_error;
    ++model_error_count_;
  }
}

std::vector<Vec3> LidarOdometry::Downsampled(const std::vector<TimedPoint>& timed,
                                             const SweepMotion& sweep,
                                             std::vector<Vec3>* source) const {
  std::vector<Vec3> frame = VoxelDownsample(DeskewPoints(timed, sweep),
                                            options_.map_downsample_factor * options_.voxel_size_m);
  *source = VoxelDownsample(frame, options_.register_downsample_factor * options_.voxel_size_m);
  return frame;
}

LidarOdometryResult LidarOdometry::RegisterScan(const LidarScan& scan,
                                                const std::optional<LidarMotionPrior>& prior) {
  LidarOdometryResult result;
  result.stamp_ns = scan.header.stamp_ns;
  result.prev_stamp_ns = last_stamp_ns_;
  result.T_world_lidar = T_world_lidar_;
  LidarOdometryDiagnostics& diag = result.diagnostics;
  auto reject = [&](std::string reason) {
    result.reject_reason = std::move(reason);
    return result;
  };
  if (!scan.points || scan.points->empty()) return reject("empty scan");
  if (initialized_ && scan.header.stamp_ns <= last_stamp_ns_) {
    return reject("stamp not after the previous scan");
  }

  // Filter.
  LidarFilterStats stats;
  const std::vector<TimedPoint> timed = FilterScanPoints(
      *scan.points, {.min_range_m = options_.min_range_m, .max_range_m = options_.max_range_m},
      &stats);
  diag.points_in = stats.points_in;
  diag.non_finite = stats.non_finite;
  diag.out_of_range = stats.out_of_range;
  diag.points_kept = stats.kept;

  // Predict the motion since the last accepted scan and within this sweep.
  const double dt_s = initialized_ ? ToSeconds(scan.header.stamp_ns - last_stamp_ns_) : 0.0;
  SE3 predicted_delta;
  SweepMotion sweep = StaticSweepMotion();
  if (prior) {
    predicted_delta = prior->T_prev_curr;
    sweep = prior->sweep;
  } else if (initialized_ && has_twist_) {
    predicted_delta = SE3::Exp(twist_ * dt_s);
    const Vec6 twist = twist_;
    sweep = [twist](double t_s) { return SE3::Exp(t_s * twist); };
  }

  // Deskew and downsample.
  std::vector<Vec3> source;
  std::vector<Vec3> frame = Downsampled(timed, sweep, &source);
  diag.points_registered = source.size();
  if (source.size() < options_.min_points) {
    return reject("too few points (" + std::to_string(source.size()) + " < " +
                  std::to_string(options_.min_points) +
                  " after filtering: " + std::to_string(stats.non_finite) + " non-finite, " +
                  std::to_string(stats.out_of_range) + " out of range)");
  }

  if (!initialized_) {
    map_.Update(frame, T_world_lidar_);
    if (!prior) first_scan_points_ = timed;
    initialized_ = true;
    last_stamp_ns_ = scan.header.stamp_ns;
    result.accepted = true;
    result.first_scan = true;
    result.prev_stamp_ns = scan.header.stamp_ns;
    return result;
  }

  // Register against the local map.
  const double sigma = AdaptiveThreshold();
  diag.threshold_m = 3.0 * sigma;
  const SE3 T_world_predicted = T_world_lidar_ * predicted_delta;
  IcpResult icp =
      RegisterScanToMap(source, map_, T_world_predicted, 3.0 * sigma, sigma / 3.0, options_.icp);
  if (icp.ok && !first_scan_points_.empty()) {
    // Start-up (see header): deskew both first scans with the motion just found, register again.
    const SE3 first_delta = T_world_lidar_.Inverse() * icp.T_map_scan;
    sweep = ConstantVelocitySweepMotion(first_delta, dt_s);
    std::vector<Vec3> first_source;
    const std::vector<Vec3> first_frame = Downsampled(first_scan_points_, sweep, &first_source);
    first_scan_points_.clear();
    map_.Clear();
    map_.Update(first_frame, T_world_lidar_);
    frame = Downsampled(timed, sweep, &source);
    icp = RegisterScanToMap(source, map_, icp.T_map_scan, 3.0 * sigma, sigma / 3.0, options_.icp);
  }
  diag.iterations = icp.iterations;
  diag.correspondences = icp.correspondences;
  if (!icp.ok) return reject("registration failed: " + icp.failure);
  diag.degenerate = icp.degenerate;
  diag.degenerate_directions = icp.degenerate_directions;
  diag.information_eigenvalues = icp.scaled_eigenvalues;
  diag.weakest_direction = icp.scaled_eigenvectors.col(0);
  diag.residual_sigma_m = icp.residual_sigma_m;

  // The ICP covariance is of the right perturbation of T_world_lidar; with the previous pose
  // held fixed it is also the right perturbation of T_prev_curr = T_world_prev^-1 T_world_curr.
  const SE3 delta = T_world_lidar_.Inverse() * icp.T_map_scan;
  UpdateThreshold(predicted_delta, delta);
  T_world_lidar_ = icp.T_map_scan;
  map_.Update(frame, T_world_lidar_);
  const Vec6 log_delta = delta.Log();
  twist_ = last_dt_s_ > 0.0 ? Vec6((log_delta + last_log_delta_) / (dt_s + last_dt_s_))
                            : Vec6(log_delta / dt_s);
  has_twist_ = true;
  last_log_delta_ = log_delta;
  last_dt_s_ = dt_s;
  last_stamp_ns_ = scan.header.stamp_ns;

  result.accepted = true;
  result.T_prev_curr = delta;
  result.covariance = icp.covariance;
  result.T_world_lidar = T_world_lidar_;
  return result;
}

}  // namespace statebench::est
