// KISS-ICP-style lidar odometry (Vizzo et al., RA-L 2023), one relative motion per scan:
//   filter (range, NaN) -> deskew to the scan stamp -> downsample (0.5 v for the map, 1.5 v for
//   registration) -> predict (constant velocity, or the caller's IMU prediction) -> adaptive
//   correspondence threshold -> robust ICP against the local voxel map -> update the map.
//
// Frames: the odometry world is the lidar frame at the first accepted scan's stamp. Each accepted
// scan yields T_world_lidar at its stamp and the relative motion T_prev_curr from the previous
// accepted scan's stamp, with its covariance (right perturbation of T_prev_curr, (rho, phi),
// core/se3.hpp). Rejected scans (empty, too few points, ICP failure) leave the state untouched;
// the next accepted scan's relative motion then spans from the last accepted one.
//
// Start-up: nothing is known about the motion of the first sweep. Without a prior, the second
// scan is registered undeskewed against the undeskewed first one, both are then deskewed with
// the resulting constant velocity, the map is rebuilt and the second scan registered again.
//
// Adaptive threshold (KISS-ICP): after each registration the deviation between the prediction
// and the result is turned into a displacement bound |dt| + 2 r_max sin(|dphi| / 2); the
// deviations above min_motion are averaged in quadrature into sigma. Correspondences are kept
// within 3 sigma, and the Geman-McClure kernel scale is sigma / 3.
#pragma once

#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include "core/measurements.hpp"
#include "core/se3.hpp"
#include "core/time.hpp"
#include "estimator/icp_registration.hpp"
#include "estimator/lidar_preprocessing.hpp"
#include "estimator/voxel_hash_map.hpp"

namespace statebench::est {

struct LidarOdometryOptions {
  double min_range_m = 1.0;
  double max_range_m = 100.0;
  double voxel_size_m = 1.0;  // map voxel; KISS-ICP uses max_range / 100
  int max_points_per_voxel = 20;
  double map_downsample_factor = 0.5;       // map points: one per (factor * voxel) cube
  double register_downsample_factor = 1.5;  // registered points: one per (factor * voxel) cube
  double initial_threshold_m = 2.0;
  double min_motion_m = 0.1;
  std::size_t min_points = 100;  // after filtering and downsampling for registration
  IcpOptions icp;
};

// The caller's knowledge of the motion since the previous accepted scan (e.g. IMU-propagated).
struct LidarMotionPrior {
  SE3 T_prev_curr;    // lidar motion from the previous accepted stamp to this scan's stamp
  SweepMotion sweep;  // T_stamp_t within this sweep
};

struct LidarOdometryDiagnostics {
  std::size_t points_in = 0;
  std::size_t non_finite = 0;
  std::size_t out_of_range = 0;
  std::size_t points_kept = 0;        // after filtering
  std::size_t points_registered = 0;  // after the 1.5 v downsampling
  int iterations = 0;
  std::size_t correspondences = 0;
  bool degenerate = false;
  int degenerate_directions = 0;
  // Information of the registration (icp_registration.hpp): eigenvalues of the scaled Hessian
  // (point-equivalents), ascending, and the eigenvector of the smallest, (rho, L phi) in the
  // lidar frame.
  Vec6 information_eigenvalues = Vec6::Zero();
  Vec6 weakest_direction = Vec6::Zero();
  double threshold_m = 0.0;
  double residual_sigma_m = 0.0;
};

struct LidarOdometryResult {
  bool accepted = false;
  std::string reject_reason;  // empty when accepted
  bool first_scan = false;    // accepted, map initialised, no relative motion yet
  TimeNs stamp_ns = 0;
  TimeNs prev_stamp_ns = 0;
  SE3 T_prev_curr;
  Mat6 covariance = Mat6::Identity();
  SE3 T_world_lidar;
  LidarOdometryDiagnostics diagnostics;
};

class LidarOdometry {
 public:
  explicit LidarOdometry(const LidarOdometryOptions& options);

  LidarOdometryResult RegisterScan(const LidarScan& scan,
                                   const std::optional<LidarMotionPrior>& prior = std::nullopt);

  const SE3& T_world_lidar() const { return T_world_lidar_; }
  // The constant-velocity model's twist ((rho, phi) per second, lidar frame) once two scans were
  // registered, and the newest accepted stamp once one was.
  std::optional<Vec6> twist() const { return has_twist_ ? std::optional<Vec6>(twist_) : std::nullopt; }
  std::optional<TimeNs> last_stamp_ns() const {
    return initialized_ ? std::optional<TimeNs>(last_stamp_ns_) : std::nullopt;
  }
  const VoxelHashMap& local_map() const { return map_; }

 private:
  double AdaptiveThreshold() const;
  void UpdateThreshold(const SE3& predicted, const SE3& estimated);

  std::vector<Vec3> Downsampled(const std::vector<TimedPoint>& timed, const SweepMotion& sweep,
                                std::vector<Vec3>* source) const;

  LidarOdometryOptions options_;
  VoxelHashMap map_;
  bool initialized_ = false;
  TimeNs last_stamp_ns_ = 0;
  // Twist (v, omega) of the lidar averaged over the last two accepted scan periods. One period
  // alone feeds a deskew error back with gain -1 (an over-estimated motion deskews the next scan
  // into an under-estimate, and so on): the two-period average damps it.
  Vec6 twist_ = Vec6::Zero();
  bool has_twist_ = false;
  Vec6 last_log_delta_ = Vec6::Zero();
  double last_dt_s_ = 0.0;
  SE3 T_world_lidar_;
  // The first scan, kept until the second one gives a motion to deskew it with.
  std::vector<TimedPoint> first_scan_points_;
  double model_error_sse_ = 0.0;
  std::size_t model_error_count_ = 0;
};

}  // namespace statebench::est
