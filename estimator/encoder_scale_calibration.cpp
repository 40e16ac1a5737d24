#include "estimator/encoder_scale_calibration.hpp"

#include <algorithm>
#include <cmath>

#include "core/so3.hpp"

namespace statebench::est {
namespace {

constexpr double kMinSpeedMps = 1.0;  // spans slower than this are not compared
constexpr TimeNs kSpeedsKeptNs = 5 * kNsPerSecond;

// Raw encoder distance over [t0, t1]: each sample covers (previous stamp, its stamp], counted
// pro rata where it overlaps.
double EncoderDistanceOver(const std::deque<std::pair<TimeNs, double>>& speeds, TimeNs t0,
                           TimeNs t1) {
  double d = 0.0;
  for (std::size_t k = 1; k < speeds.size(); ++k) {
    const TimeNs a = std::max(speeds[k - 1].first, t0);
    const TimeNs b = std::min(speeds[k].first, t1);
    if (b > a) d += speeds[k].second * ToSeconds(b - a);
  }
  return d;
}

}  // namespace

EncoderScaleCalibration::EncoderScaleCalibration(const SE3& T_imu_axle, double window_m,
                                                 double min_distance_m)
    : T_imu_axle_(T_imu_axle), window_m_(window_m), min_distance_m_(min_distance_m) {}

void EncoderScaleCalibration::AddSpeed(TimeNs t_ns, double raw_speed_mps) {
  if (!std::isfinite(raw_speed_mps) || (!speeds_.empty() && t_ns <= speeds_.back().first)) return;
  speeds_.emplace_back(t_ns, raw_speed_mps);
  while (!speeds_.empty() && t_ns - speeds_.front().first > kSpeedsKeptNs) speeds_.pop_front();
}

double EncoderScaleCalibration::EncoderDistance(TimeNs t0_ns, TimeNs t1_ns) const {
  return EncoderDistanceOver(speeds_, t0_ns, t1_ns);
}

void EncoderScaleCalibration::AddSmoothedStates(const std::vector<NavState>& states) {
  for (const NavState& b : states) {
    if (!last_state_ || b.t_ns <= last_state_->t_ns) {
      last_state_ = b;
      continue;
    }
    const NavState& a = *last_state_;
    const double dt = ToSeconds(b.t_ns - a.t_ns);
    const Vec3 omega = so3::Log<double>(a.q_world_imu.conjugate() * b.q_world_imu) / dt;
    const Quat q_mid = so3::Interpolate(a.q_world_imu, b.q_world_imu, 0.5);
    const Vec3 v_imu = q_mid.conjugate() * (0.5 * (a.v_world + b.v_world));
    const Vec3 v_axle =
        T_imu_axle_.rotation().conjugate() * (v_imu + omega.cross(T_imu_axle_.translation()));
    const double smoothed = v_axle.x() * dt;
    const double encoder = EncoderDistance(a.t_ns, b.t_ns);
    last_state_ = b;
    if (std::abs(encoder) < kMinSpeedMps * dt || !std::isfinite(smoothed)) continue;
    spans_.push_back({smoothed, encoder});
    sum_smoothed_m_ += smoothed;
    sum_encoder_m_ += encoder;
    while (!spans_.empty() && sum_encoder_m_ - spans_.front().encoder_m > window_m_) {
      sum_smoothed_m_ -= spans_.front().smoothed_m;
      sum_encoder_m_ -= spans_.front().encoder_m;
      spans_.pop_front();
    }
  }
}

std::optional<double> EncoderScaleCalibration::scale() const {
  if (sum_encoder_m_ < min_distance_m_) return std::nullopt;
  const double s = sum_smoothed_m_ / sum_encoder_m_;
  if (!std::isfinite(s) || s < 0.8 || s > 1.2) return std::nullopt;  // not a radius error
  return s;
}

}  // namespace statebench::est
