// The metrics of trajectory_metrics.hpp accumulated one estimate at a time, so that scoring a
// run of any length takes the same memory: sums for the RMSEs and the NEES, RunningStatistics for
// the APE and RPE (exact count, mean, RMS, std and maximum; median within 0.05 %), and, for the
// relative errors, only the start states still waiting for their end (starts every
// rpe_start_step_m / kitti_start_step_m of travelled distance, so a vehicle standing still adds
// none). Outage windows keep the per-axis errors inside them (a window's length, not the run's).
#pragma once

#include <cstddef>
#include <deque>
#include <optional>
#include <utility>
#include <vector>

#include "core/running_statistics.hpp"
#include "core/state.hpp"
#include "reports/output_step.hpp"
#include "reports/trajectory_metrics.hpp"

namespace statebench::reports {

class TrajectoryScorer {
 public:
  explicit TrajectoryScorer(MetricsOptions options = {});

  // One estimate and the reference at its stamp; stamps increasing. Estimates before
  // options.skip_before_ns are counted as skipped, like Skip(). Of the covariance only the pose
  // block ([rotation, position], core/state.hpp) is used.
  void Add(const NavState& state, const Mat6& pose_covariance, const ReferenceState& reference);
  void Add(const StateEstimate& estimate, const ReferenceState& reference) {
    Add(estimate.state, estimate.covariance.topLeftCorner<6, 6>(), reference);
  }
  // An estimate that could not be compared (outside the reference span).
  void Skip() {
    ++metrics_.skipped;
    Break();
  }
  // An output epoch without an estimate: the next estimate does not follow the last one, the
  // pair is no output step.
  void Break() { previous_.reset(); }

  // The metrics of everything added (relative-error starts still open are closed as they stand).
  TrajectoryMetrics Finish();

 private:
  // A start of a relative error: the poses there and the lengths still to measure from it.
  struct RelativeStart {
    double distance_m = 0.0;
    SE3 T_ref, T_est;
    std::size_t next_length = 0;  // index into the lengths of its kind
  };
  struct OutageAccumulator {
    OutageDrift drift;
    bool any = false;
    double first_distance_m = 0.0;
    std::vector<double> x, y;
  };

  void AddRelative(double distance_m, const SE3& T_ref, const SE3& T_est);

  MetricsOptions options_;
  TrajectoryMetrics metrics_;
  double sum_x_ = 0, sum_y_ = 0, sum_z_ = 0, sum_roll_ = 0, sum_pitch_ = 0, sum_yaw_ = 0;
  double sum_vlong_ = 0, sum_vlat_ = 0, sum_vel_ = 0;
  double nees_pose_sum_ = 0.0, nees_position_sum_ = 0.0;
  double first_distance_m_ = 0.0, last_distance_m_ = 0.0;
  RunningStatistics ape_t_, ape_r_, rpe_t_, rpe_r_;
  std::deque<RelativeStart> rpe_starts_, kitti_starts_;
  double next_rpe_start_m_ = 0.0, next_kitti_start_m_ = 0.0;
  double kitti_t_ = 0.0, kitti_r_ = 0.0;
  std::vector<OutageAccumulator> outages_;
  // The last estimate and its reference, for the output step.
  std::optional<std::pair<NavState, ReferenceState>> previous_;
  OutputStepStatistics steps_;
};

}  // namespace statebench::reports
