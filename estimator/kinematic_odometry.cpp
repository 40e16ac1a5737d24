#include "estimator/kinematic_odometry.hpp"

#include <cmath>

#include "core/error.hpp"
#include "estimator/relative_pose_factor.hpp"

namespace statebench::est {
namespace {

constexpr std::size_t kSteeringKept = 64;
constexpr double kMinVariance = 1e-10;  // keeps a standstill period's information finite

Mat2 Rot2(double a) {
  Mat2 r;
  r << std::cos(a), -std::sin(a), std::sin(a), std::cos(a);
  return r;
}

}  // namespace

KinematicOdometry::KinematicOdometry(const KinematicFactorOptions& options, double wheelbase_m)
    : options_(options), wheelbase_m_(wheelbase_m) {
  if (!(wheelbase_m > 0.0) || !std::isfinite(wheelbase_m)) {
    throw InputError("kinematic odometry: the wheelbase (steering to speed encoder distance) "
                     "must be positive");
  }
}

void KinematicOdometry::Reset() {
  last_speed_ns_.reset();
  period_start_ns_.reset();
}

void KinematicOdometry::AddSteering(TimeNs t_ns, double angle_rad) {
  if (!std::isfinite(angle_rad)) return;
  if (!steering_.empty() && t_ns <= steering_.back().first) return;
  steering_.emplace_back(t_ns, angle_rad);
  if (steering_.size() > kSteeringKept) steering_.pop_front();
}

void KinematicOdometry::StartPeriod(TimeNs t_ns) {
  period_start_ns_ = t_ns;
  state_.setZero();
  P_.setZero();
  J_scale_.setZero();
  J_steer_.setZero();
  distance_m_ = 0.0;
}

double KinematicOdometry::SteeringOver(TimeNs t0_ns, TimeNs t1_ns) const {
  double sum = 0.0;
  int n = 0;
  double before = 0.0;
  bool has_before = false;
  for (const auto& [t, angle] : steering_) {
    if (t >= t0_ns && t <= t1_ns) {
      sum += angle;
      ++n;
    } else if (t < t0_ns) {
      before = angle;
      has_before = true;
    }
  }
  if (n > 0) return sum / n;
  return has_before ? before : 0.0;
}

std::optional<KinematicMotion> KinematicOdometry::AddSpeed(TimeNs t_ns, double raw_speed_mps) {
  if (!std::isfinite(raw_speed_mps)) return std::nullopt;
  const double speed_mps = speed_scale_ * raw_speed_mps;
  if (!last_speed_ns_ || t_ns <= *last_speed_ns_ ||
      ToSeconds(t_ns - *last_speed_ns_) > options_.max_gap_s) {
    // (Re)start: this sample only opens the next interval.
    last_speed_ns_ = t_ns;
    StartPeriod(t_ns);
    return std::nullopt;
  }
  const double dt = ToSeconds(t_ns - *last_speed_ns_);
  const double delta = SteeringOver(*last_speed_ns_, t_ns);
  last_speed_ns_ = t_ns;

  const double l = wheelbase_m_;
  const double ratio = options_.rear_steering_ratio;
  const double delta_r = -ratio * delta;
  const double tr = std::tan(delta_r);
  const double kappa = (std::tan(delta) - tr) / l;  // yaw per metre along x
  const double sec2 = 1.0 / (std::cos(delta) * std::cos(delta));
  const double sec2_r = 1.0 / (std::cos(delta_r) * std::cos(delta_r));
  const double dkappa_ddelta = (sec2 + ratio * sec2_r) / l;
  const double dtr_ddelta = -ratio * sec2_r;

  const double d = speed_mps * dt;
  const double a = state_.z() + 0.5 * kappa * d;  // midpoint heading
  const Vec2 u = Rot2(a) * Vec2(1.0, tr);           // displacement per metre
  const Vec2 u_perp(-u.y(), u.x());                  // d u / d a
  const Vec2 lateral = Rot2(a) * Vec2(0.0, 1.0);

  Mat3 F = Mat3::Identity();
  F.block<2, 1>(0, 2) = d * u_perp;
  Vec3 G_d;  // d(state')/d(d)
  G_d << u + 0.5 * kappa * d * u_perp, kappa;
  Vec3 G_delta;  // d(state')/d(delta)
  G_delta << d * u_perp * (0.5 * d * dkappa_ddelta) + d * Rot2(a) * Vec2(0.0, dtr_ddelta),
      d * dkappa_ddelta;

  state_.head<2>() += d * u;
  state_.z() += kappa * d;
  const double sigma_d = options_.speed_sigma_mps * dt;
  // Tyre slip: side slip at the rear axle and yaw-rate departure, both ~ lateral acceleration.
  const double slip_rad = options_.slip_per_lateral_accel * std::abs(speed_mps * speed_mps * kappa);
  const double sigma_lat = (options_.lateral_sigma_mps + std::abs(speed_mps) * slip_rad) * dt;
  const double sigma_yaw = std::abs(d) * slip_rad / l;
  P_ = F * P_ * F.transpose() + sigma_d * sigma_d * G_d * G_d.transpose();
  P_.topLeftCorner<2, 2>() += sigma_lat * sigma_lat * lateral * lateral.transpose();
  P_(2, 2) += sigma_yaw * sigma_yaw;
  J_scale_ = F * J_scale_ + d * G_d;
  J_steer_ = F * J_steer_ + G_delta;
  distance_m_ += std::abs(d);

  if (ToSeconds(t_ns - *period_start_ns_) + 1e-9 < options_.period_s) return std::nullopt;
  KinematicMotion out = Emit(t_ns);
  StartPeriod(t_ns);
  return out;
}

KinematicMotion KinematicOdometry::Emit(TimeNs t_ns) {
  KinematicMotion m;
  m.t1_ns = *period_start_ns_;
  m.t2_ns = t_ns;
  m.distance_m = distance_m_;
  const double yaw = state_.z();
  m.T_r1_r2 = SE3(Quat(Eigen::AngleAxisd(yaw, Vec3::UnitZ())),
                  Vec3(state_.x(), state_.y(), 0.0));
  Mat3 C = P_ + options_.speed_scale_sigma * options_.speed_scale_sigma * J_scale_ *
                    J_scale_.transpose() +
           options_.steering_sigma_rad * options_.steering_sigma_rad * J_steer_ *
               J_steer_.transpose();
  C += kMinVariance * Mat3::Identity();
  m.covariance_xy_yaw = C;
  // The residual's translation is expressed in the frame at t2: rho = R(yaw)^T dt.
  Mat3 A = Mat3::Identity();
  A.topLeftCorner<2, 2>() = Rot2(yaw).transpose();
  const Mat3 C_res = A * C * A.transpose();
  const Mat3 info3 = C_res.inverse();
  Mat6 info = Mat6::Zero();
  const int idx[3] = {0, 1, 5};  // rho_x, rho_y, phi_z
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) info(idx[i], idx[j]) = info3(i, j);
  }
  const double sigma_z = std::max(options_.vertical_sigma_mps * ToSeconds(m.t2_ns - m.t1_ns),
                                  std::sqrt(kMinVariance));
  info(2, 2) = 1.0 / (sigma_z * sigma_z);
  m.sqrt_information = SqrtOfInformation(info);
  return m;
}

}  // namespace statebench::est
