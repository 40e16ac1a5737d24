#include "reports/trajectory_metrics.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>

#include "core/so3.hpp"

namespace statebench::reports {
namespace {

double Rms(const std::vector<double>& e) {
  if (e.empty()) return 0.0;
  double s = 0.0;
  for (const double v : e) s += v * v;
  return std::sqrt(s / static_cast<double>(e.size()));
}

// Relative error of the estimated motion between two instants against the reference's.
SE3 RelativeError(const SE3& ref_i, const SE3& ref_j, const SE3& est_i, const SE3& est_j) {
  return (ref_i.Inverse() * ref_j).Inverse() * (est_i.Inverse() * est_j);
}

double RotationAngle(const Quat& q) { return so3::Log<double>(q).norm(); }

}  // namespace

std::vector<ReferenceState> ReferenceFromTruth(const std::vector<TruthSample>& truth,
                                               const SE3& T_body_frame) {
  std::vector<ReferenceState> out;
  out.reserve(truth.size());
  for (const TruthSample& s : truth) {
    const FrameKinematics k = s.body.AtMount(T_body_frame);
    ReferenceState r;
    r.t_ns = s.t_ns;
    r.T_world_frame = k.T_world_frame;
    r.v_world = k.v_world;
    r.distance_m = out.empty() ? 0.0
                               : out.back().distance_m +
                                     (r.T_world_frame.translation() -
                                      out.back().T_world_frame.translation())
                                         .norm();
    out.push_back(r);
  }
  return out;
}

ErrorStatistics ComputeStatistics(std::vector<double> errors) {
  ErrorStatistics s;
  s.count = errors.size();
  if (errors.empty()) return s;
  const double n = static_cast<double>(errors.size());
  s.rmse = Rms(errors);
  s.mean = std::accumulate(errors.begin(), errors.end(), 0.0) / n;
  double var = 0.0;
  for (const double e : errors) var += (e - s.mean) * (e - s.mean);
  s.std = std::sqrt(var / n);
  s.max = *std::max_element(errors.begin(), errors.end());
  std::sort(errors.begin(), errors.end());
  const std::size_t m = errors.size() / 2;
  s.median = errors.size() % 2 ? errors[m] : 0.5 * (errors[m - 1] + errors[m]);
  return s;
}

std::optional<ReferenceState> InterpolateReference(const std::vector<ReferenceState>& reference,
                                                   TimeNs t_ns) {
  if (reference.empty() || t_ns < reference.front().t_ns || t_ns > reference.back().t_ns) {
    return std::nullopt;
  }
  const auto it = std::lower_bound(reference.begin(), reference.end(), t_ns,
                                   [](const ReferenceState& r, TimeNs t) { return r.t_ns < t; });
  if (it->t_ns == t_ns) return *it;
  const ReferenceState& b = *it;
  const ReferenceState& a = *(it - 1);
  const double alpha = static_cast<double>(t_ns - a.t_ns) / static_cast<double>(b.t_ns - a.t_ns);
  ReferenceState r;
  r.t_ns = t_ns;
  r.T_world_frame = SE3::Interpolate(a.T_world_frame, b.T_world_frame, alpha);
  r.v_world = (1.0 - alpha) * a.v_world + alpha * b.v_world;
  r.distance_m = (1.0 - alpha) * a.distance_m + alpha * b.distance_m;
  return r;
}

TrajectoryMetrics ComputeTrajectoryMetrics(const std::vector<StateEstimate>& estimates,
                                           const std::vector<ReferenceState>& reference,
                                           const MetricsOptions& options) {
  TrajectoryMetrics m;
  // Pair every usable estimate with the reference at its stamp.
  std::vector<const StateEstimate*> est;
  std::vector<ReferenceState> ref;
  for (const StateEstimate& e : estimates) {
    if (e.state.t_ns < options.skip_before_ns) {
      ++m.skipped;
      continue;
    }
    const auto r = InterpolateReference(reference, e.state.t_ns);
    if (!r) {
      ++m.skipped;
      continue;
    }
    est.push_back(&e);
    ref.push_back(*r);
  }
  m.compared = est.size();
  if (est.empty()) return m;
  m.distance_m = ref.back().distance_m - ref.front().distance_m;

  std::vector<double> ex, ey, ez, eroll, epitch, eyaw, evlong, evlat, epos, evel, erot;
  double nees_pose_sum = 0.0, nees_pos_sum = 0.0;
  for (std::size_t i = 0; i < est.size(); ++i) {
    const NavState& s = est[i]->state;
    const ReferenceState& r = ref[i];
    const Vec3 dp = s.p_world - r.T_world_frame.translation();
    ex.push_back(dp.x());
    ey.push_back(dp.y());
    ez.push_back(dp.z());
    epos.push_back(dp.norm());
    const Vec3 rpy_e = so3::ToRollPitchYaw(s.q_world_imu);
    const Vec3 rpy_r = so3::ToRollPitchYaw(r.T_world_frame.rotation());
    eroll.push_back(so3::WrapAngle(rpy_e.x() - rpy_r.x()));
    epitch.push_back(so3::WrapAngle(rpy_e.y() - rpy_r.y()));
    eyaw.push_back(so3::WrapAngle(rpy_e.z() - rpy_r.z()));
    const Vec3 v_est = s.q_world_imu.conjugate() * s.v_world;
    const Vec3 v_ref = r.T_world_frame.rotation().conjugate() * r.v_world;
    evlong.push_back(v_est.x() - v_ref.x());
    evlat.push_back(v_est.y() - v_ref.y());
    evel.push_back((s.v_world - r.v_world).norm());
    const Vec3 dtheta = so3::Log<double>(s.q_world_imu.conjugate() * r.T_world_frame.rotation());
    erot.push_back(dtheta.norm());

    Vec6 e6;
    e6 << dtheta, -dp;
    const Mat6 p6 = est[i]->covariance.topLeftCorner<6, 6>();
    const Eigen::LDLT<Mat6> ldlt(p6);
    const Eigen::LDLT<Mat3> ldlt3(p6.bottomRightCorner<3, 3>());
    if (ldlt.info() == Eigen::Success && ldlt.isPositive() && p6.allFinite() &&
        p6.diagonal().minCoeff() > 0.0) {
      const double nees = e6.dot(ldlt.solve(e6));
      const double nees_pos = dp.dot(ldlt3.solve(dp));
      if (std::isfinite(nees) && std::isfinite(nees_pos)) {
        nees_pose_sum += nees;
        nees_pos_sum += nees_pos;
        ++m.nees_count;
      }
    }
  }
  m.rmse_x_m = Rms(ex);
  m.rmse_y_m = Rms(ey);
  m.rmse_z_m = Rms(ez);
  m.rmse_roll_rad = Rms(eroll);
  m.rmse_pitch_rad = Rms(epitch);
  m.rmse_yaw_rad = Rms(eyaw);
  m.rmse_v_longitudinal_mps = Rms(evlong);
  m.rmse_v_lateral_mps = Rms(evlat);
  m.rmse_position_m = Rms(epos);
  m.rmse_velocity_mps = Rms(evel);
  m.ape_translation_m = ComputeStatistics(epos);
  m.ape_rotation_rad = ComputeStatistics(erot);
  if (m.nees_count > 0) {
    m.mean_pose_nees = nees_pose_sum / static_cast<double>(m.nees_count);
    m.mean_position_nees = nees_pos_sum / static_cast<double>(m.nees_count);
  }

  // Relative errors over travelled distance.
  auto relative = [&](double length_m, std::size_t i, std::size_t* j) {
    const double target = ref[i].distance_m + length_m;
    const auto it = std::lower_bound(ref.begin() + static_cast<std::ptrdiff_t>(i), ref.end(),
                                     target, [](const ReferenceState& r, double d) {
                                       return r.distance_m < d;
                                     });
    if (it == ref.end()) return false;
    *j = static_cast<std::size_t>(it - ref.begin());
    return true;
  };
  auto est_pose = [&](std::size_t k) { return SE3(est[k]->state.q_world_imu, est[k]->state.p_world); };
  std::vector<double> rpe_t, rpe_r;
  for (std::size_t i = 0; i < ref.size(); ++i) {
    std::size_t j = 0;
    if (options.rpe_delta_m <= 0.0 || !relative(options.rpe_delta_m, i, &j)) break;
    const SE3 e = RelativeError(ref[i].T_world_frame, ref[j].T_world_frame, est_pose(i), est_pose(j));
    rpe_t.push_back(e.translation().norm());
    rpe_r.push_back(RotationAngle(e.rotation()));
  }
  m.rpe_translation_m = ComputeStatistics(rpe_t);
  m.rpe_rotation_rad = ComputeStatistics(rpe_r);

  double kitti_t = 0.0, kitti_r = 0.0;
  double next_start = ref.front().distance_m;
  for (std::size_t i = 0; i < ref.size(); ++i) {
    if (ref[i].distance_m < next_start) continue;
    next_start = ref[i].distance_m + options.kitti_start_step_m;
    for (const double length : options.kitti_lengths_m) {
      std::size_t j = 0;
      if (!relative(length, i, &j)) break;
      const SE3 e =
          RelativeError(ref[i].T_world_frame, ref[j].T_world_frame, est_pose(i), est_pose(j));
      kitti_t += e.translation().norm() / length;
      kitti_r += RotationAngle(e.rotation()) / length;
      ++m.kitti_segments;
    }
  }
  if (m.kitti_segments > 0) {
    m.kitti_translation_percent = 100.0 * kitti_t / static_cast<double>(m.kitti_segments);
    m.kitti_rotation_deg_per_m = kitti_r / static_cast<double>(m.kitti_segments) * 180.0 / M_PI;
  }

  for (const OutageWindow& w : options.outages) {
    OutageDrift d;
    d.window = w;
    std::vector<double> wx, wy;
    std::optional<std::size_t> first, last;
    for (std::size_t i = 0; i < est.size(); ++i) {
      const TimeNs t = est[i]->state.t_ns;
      if (t < w.begin_ns || t > w.end_ns) continue;
      if (!first) first = i;
      last = i;
      wx.push_back(ex[i]);
      wy.push_back(ey[i]);
      d.max_error_m = std::max(d.max_error_m, epos[i]);
    }
    if (last) {
      d.distance_m = ref[*last].distance_m - ref[*first].distance_m;
      d.error_end_m = epos[*last];
      d.error_end_world = Vec3(ex[*last], ey[*last], ez[*last]);
      d.drift_per_metre = d.distance_m > 0.0 ? d.error_end_m / d.distance_m : 0.0;
      d.x = ComputeStatistics(wx);
      d.y = ComputeStatistics(wy);
    }
    m.outages.push_back(d);
  }
  return m;
}

}  // namespace statebench::reports
