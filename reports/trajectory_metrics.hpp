// Accuracy and consistency of an estimated trajectory against ground truth.
//
// Definitions (docs/metrics.md):
// - Estimates are compared with the reference interpolated at their own stamps (SE3 geodesic,
//   linear velocity); estimates outside the reference's time span are skipped and counted.
// - RMSE per component: x, y, z (ENU, m); roll, pitch, yaw (R = Rz Ry Rx, differences wrapped to
//   (-pi, pi]); longitudinal and lateral velocity, each in its own frame (v_frame = R^T v_world).
// - APE as evo defines it, without alignment (GNSS-referenced runs): translation
//   |p_est - p_ref| and rotation angle of R_ref^T R_est, with rmse/mean/median/std/max.
// - RPE over a travelled distance delta: for pairs (i, j) with d_j - d_i >= delta (first such
//   j), E = (T_ref_i^-1 T_ref_j)^-1 (T_est_i^-1 T_est_j); translation |t(E)|, rotation angle(E);
//   starts i every `rpe_start_step_m` of travelled distance (the first compared estimate, then
//   the first one at least that far beyond the previous start).
// - KITTI relative error: the same relative error over segments of 100, 200, ..., 800 m,
//   starting every `kitti_start_step_m`; translation in % of the segment, rotation in deg/m,
//   averaged over all segments.
// - Outage drift: for each window [t0, t1], the position error at the last estimate <= t1, and
//   that error divided by the reference distance travelled in the window.
// - Medians of the APE and RPE within 0.05 % (core/running_statistics.hpp); every other figure
//   exact. Estimates with a non-finite mean are not compared (counted in `non_finite`).
// - NEES of the pose (6 dof): e = (Log(R_est^T R_ref), p_ref - p_est) against the estimate's
//   [rotation, position] covariance block (right rotation perturbation, core/state.hpp).
// - Output step: between consecutive estimates, the estimated motion minus the reference's
//   (position and yaw; reports/output_step.hpp): median, p99, max.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "core/se3.hpp"
#include "core/state.hpp"
#include "core/truth.hpp"

namespace statebench::reports {

// One reference state of the frame the estimator reports (the IMU).
struct ReferenceState {
  TimeNs t_ns = 0;
  SE3 T_world_frame;
  Vec3 v_world = Vec3::Zero();
  double distance_m = 0.0;  // travelled by the reference frame since the first sample
};

// The truth of the frame at T_body_frame (e.g. the IMU mount), with its own travelled distance.
std::vector<ReferenceState> ReferenceFromTruth(const std::vector<TruthSample>& truth,
                                               const SE3& T_body_frame);

// The reference of the frame at one truth sample; `previous` (the reference at the sample
// before, or nullptr for the first) gives the distance travelled.
ReferenceState ReferenceAt(const TruthSample& sample, const SE3& T_body_frame,
                           const ReferenceState* previous);

// Between two reference states, a.t_ns <= t_ns <= b.t_ns: SE3 geodesic, velocity and distance
// linear.
ReferenceState Interpolate(const ReferenceState& a, const ReferenceState& b, TimeNs t_ns);

struct ErrorStatistics {
  double rmse = 0.0;
  double mean = 0.0;
  double median = 0.0;
  double std = 0.0;
  double max = 0.0;
  std::size_t count = 0;
};
ErrorStatistics ComputeStatistics(std::vector<double> errors);

// Median, 99th percentile (within 0.05 %) and maximum of the steps between consecutive outputs.
struct StepStatistics {
  double p50 = 0.0;
  double p99 = 0.0;
  double max = 0.0;
  std::size_t count = 0;
};
struct OutputSteps {
  StepStatistics position_m;
  StepStatistics yaw_rad;
};

struct OutageWindow {
  TimeNs begin_ns = 0;
  TimeNs end_ns = 0;
};

struct OutageDrift {
  OutageWindow window;
  double distance_m = 0.0;        // reference distance travelled in the window
  double error_end_m = 0.0;       // |p_est - p_ref| at the end of the window
  Vec3 error_end_world = Vec3::Zero();
  double max_error_m = 0.0;       // worst |p_est - p_ref| inside the window
  double drift_per_metre = 0.0;   // error_end_m / distance_m
  ErrorStatistics x, y;           // per-axis errors inside the window
};

struct MetricsOptions {
  double rpe_delta_m = 10.0;
  double rpe_start_step_m = 1.0;
  std::vector<double> kitti_lengths_m = {100, 200, 300, 400, 500, 600, 700, 800};
  double kitti_start_step_m = 10.0;
  std::vector<OutageWindow> outages;
  TimeNs skip_before_ns = 0;  // ignore estimates before this stamp (initialisation)
};

struct TrajectoryMetrics {
  std::size_t compared = 0;
  std::size_t skipped = 0;  // outside the reference span, or before skip_before_ns
  std::size_t non_finite = 0;  // estimates with a NaN or infinite mean, not compared
  double rmse_x_m = 0.0, rmse_y_m = 0.0, rmse_z_m = 0.0;
  double rmse_roll_rad = 0.0, rmse_pitch_rad = 0.0, rmse_yaw_rad = 0.0;
  double rmse_v_longitudinal_mps = 0.0, rmse_v_lateral_mps = 0.0;
  double rmse_position_m = 0.0, rmse_velocity_mps = 0.0;
  ErrorStatistics ape_translation_m, ape_rotation_rad;
  ErrorStatistics rpe_translation_m, rpe_rotation_rad;
  double kitti_translation_percent = 0.0;
  double kitti_rotation_deg_per_m = 0.0;
  std::size_t kitti_segments = 0;
  std::vector<OutageDrift> outages;
  double mean_pose_nees = 0.0;  // 6-dof, averaged over compared estimates
  double mean_position_nees = 0.0;
  std::size_t nees_count = 0;   // estimates with a usable covariance
  double distance_m = 0.0;      // reference distance over the compared span
  OutputSteps output_step;      // against the reference (reports/output_step.hpp)
};

// All estimates at once (stamps increasing); the same figures as feeding TrajectoryScorer.
TrajectoryMetrics ComputeTrajectoryMetrics(const std::vector<StateEstimate>& estimates,
                                           const std::vector<ReferenceState>& reference,
                                           const MetricsOptions& options = {});

// Reference state at t (geodesic interpolation); nullopt outside the reference span.
std::optional<ReferenceState> InterpolateReference(const std::vector<ReferenceState>& reference,
                                                   TimeNs t_ns);

}  // namespace statebench::reports
