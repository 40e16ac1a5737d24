#include "reports/trajectory_scorer.hpp"

#include <cmath>
#include <utility>

#include "core/so3.hpp"
#include "reports/epoch_errors.hpp"

namespace statebench::reports {
namespace {

// Relative error of the estimated motion between two instants against the reference's.
SE3 RelativeError(const SE3& ref_i, const SE3& ref_j, const SE3& est_i, const SE3& est_j) {
  return (ref_i.Inverse() * ref_j).Inverse() * (est_i.Inverse() * est_j);
}

double RotationAngle(const Quat& q) { return so3::Log<double>(q).norm(); }

double RootMean(double sum_sq, std::size_t n) {
  return n ? std::sqrt(sum_sq / static_cast<double>(n)) : 0.0;
}

ErrorStatistics ToErrorStatistics(const RunningStatistics& s) {
  ErrorStatistics e;
  e.count = s.count();
  e.rmse = s.rms();
  e.mean = s.mean();
  e.median = s.Median();
  e.std = s.std();
  e.max = s.max();
  return e;
}

}  // namespace

TrajectoryScorer::TrajectoryScorer(MetricsOptions options) : options_(std::move(options)) {
  for (const OutageWindow& w : options_.outages) {
    OutageAccumulator a;
    a.drift.window = w;
    outages_.push_back(a);
  }
}

void TrajectoryScorer::Add(const NavState& s, const Mat6& pose_covariance,
                           const ReferenceState& r) {
  if (s.t_ns < options_.skip_before_ns) return Skip();
  if (!s.p_world.allFinite() || !s.v_world.allFinite() || !s.q_world_imu.coeffs().allFinite()) {
    ++metrics_.non_finite;
    return Break();
  }
  if (previous_ && s.t_ns > previous_->first.t_ns) {
    steps_.Add(StepAgainstReference(previous_->first, s, previous_->second, r));
  }
  previous_.emplace(s, r);
  if (metrics_.compared == 0) {
    first_distance_m_ = r.distance_m;
    next_rpe_start_m_ = next_kitti_start_m_ = r.distance_m;
  }
  ++metrics_.compared;
  last_distance_m_ = r.distance_m;

  const PoseErrors e = ErrorsOf(s, r);
  const Vec3& dp = e.dp_world;
  sum_x_ += dp.x() * dp.x();
  sum_y_ += dp.y() * dp.y();
  sum_z_ += dp.z() * dp.z();
  sum_roll_ += e.drpy.x() * e.drpy.x();
  sum_pitch_ += e.drpy.y() * e.drpy.y();
  sum_yaw_ += e.drpy.z() * e.drpy.z();
  sum_vlong_ += e.dv_own_frame.x() * e.dv_own_frame.x();
  sum_vlat_ += e.dv_own_frame.y() * e.dv_own_frame.y();
  sum_vel_ += e.dv_world.squaredNorm();
  ape_t_.Add(dp.norm());
  ape_r_.Add(e.dtheta.norm());
  if (const auto nees = PoseNees(e, pose_covariance)) {
    nees_pose_sum_ += nees->first;
    nees_position_sum_ += nees->second;
    ++metrics_.nees_count;
  }

  for (OutageAccumulator& o : outages_) {
    if (s.t_ns < o.drift.window.begin_ns || s.t_ns > o.drift.window.end_ns) continue;
    if (!o.any) o.first_distance_m = r.distance_m;
    o.any = true;
    o.x.push_back(dp.x());
    o.y.push_back(dp.y());
    o.drift.max_error_m = std::max(o.drift.max_error_m, dp.norm());
    o.drift.error_end_m = dp.norm();
    o.drift.error_end_world = dp;
    o.drift.distance_m = r.distance_m - o.first_distance_m;
  }
  AddRelative(r.distance_m, r.T_world_frame, SE3(s.q_world_imu, s.p_world));
}

void TrajectoryScorer::AddRelative(double d, const SE3& T_ref, const SE3& T_est) {
  // Close what this state ends: the first state at least `length` beyond a start.
  const double delta = options_.rpe_delta_m;
  while (!rpe_starts_.empty() && d >= rpe_starts_.front().distance_m + delta) {
    const RelativeStart& a = rpe_starts_.front();
    const SE3 e = RelativeError(a.T_ref, T_ref, a.T_est, T_est);
    rpe_t_.Add(e.translation().norm());
    rpe_r_.Add(RotationAngle(e.rotation()));
    rpe_starts_.pop_front();
  }
  const std::vector<double>& lengths = options_.kitti_lengths_m;
  for (RelativeStart& a : kitti_starts_) {
    while (a.next_length < lengths.size() && d >= a.distance_m + lengths[a.next_length]) {
      const double length = lengths[a.next_length];
      const SE3 e = RelativeError(a.T_ref, T_ref, a.T_est, T_est);
      kitti_t_ += e.translation().norm() / length;
      kitti_r_ += RotationAngle(e.rotation()) / length;
      ++metrics_.kitti_segments;
      ++a.next_length;
    }
  }
  while (!kitti_starts_.empty() && kitti_starts_.front().next_length == lengths.size()) {
    kitti_starts_.pop_front();
  }
  // Open new starts every so many metres.
  if (delta > 0.0 && d >= next_rpe_start_m_) {
    rpe_starts_.push_back({d, T_ref, T_est, 0});
    next_rpe_start_m_ = d + options_.rpe_start_step_m;
  }
  if (!lengths.empty() && d >= next_kitti_start_m_) {
    kitti_starts_.push_back({d, T_ref, T_est, 0});
    next_kitti_start_m_ = d + options_.kitti_start_step_m;
  }
}

TrajectoryMetrics TrajectoryScorer::Finish() {
  TrajectoryMetrics m = metrics_;
  m.output_step = steps_.Summary();
  const std::size_t n = m.compared;
  if (n == 0) return m;
  m.distance_m = last_distance_m_ - first_distance_m_;
  m.rmse_x_m = RootMean(sum_x_, n);
  m.rmse_y_m = RootMean(sum_y_, n);
  m.rmse_z_m = RootMean(sum_z_, n);
  m.rmse_roll_rad = RootMean(sum_roll_, n);
  m.rmse_pitch_rad = RootMean(sum_pitch_, n);
  m.rmse_yaw_rad = RootMean(sum_yaw_, n);
  m.rmse_v_longitudinal_mps = RootMean(sum_vlong_, n);
  m.rmse_v_lateral_mps = RootMean(sum_vlat_, n);
  m.rmse_position_m = ape_t_.rms();
  m.rmse_velocity_mps = RootMean(sum_vel_, n);
  m.ape_translation_m = ToErrorStatistics(ape_t_);
  m.ape_rotation_rad = ToErrorStatistics(ape_r_);
  m.rpe_translation_m = ToErrorStatistics(rpe_t_);
  m.rpe_rotation_rad = ToErrorStatistics(rpe_r_);
  if (m.nees_count > 0) {
    m.mean_pose_nees = nees_pose_sum_ / static_cast<double>(m.nees_count);
    m.mean_position_nees = nees_position_sum_ / static_cast<double>(m.nees_count);
  }
  if (m.kitti_segments > 0) {
    m.kitti_translation_percent = 100.0 * kitti_t_ / static_cast<double>(m.kitti_segments);
    m.kitti_rotation_deg_per_m = kitti_r_ / static_cast<double>(m.kitti_segments) * 180.0 / M_PI;
  }
  for (const OutageAccumulator& o : outages_) {
    OutageDrift d = o.drift;
    if (o.any) {
      d.drift_per_metre = d.distance_m > 0.0 ? d.error_end_m / d.distance_m : 0.0;
      d.x = ComputeStatistics(o.x);
      d.y = ComputeStatistics(o.y);
    }
    m.outages.push_back(d);
  }
  return m;
}

}  // namespace statebench::reports
