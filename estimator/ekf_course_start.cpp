#include "estimator/ekf_course_start.hpp"

#include <algorithm>
#include <cmath>

namespace statebench::est {

void EkfCourseStart::AddForwardAccel(TimeNs t_ns, double accel_x_mps2) {
  if (!std::isfinite(accel_x_mps2)) return;
  if (!t_ref_ns_) {
    t_ref_ns_ = t_ns;
    accel_.push_back({t_ns, 0.0, 0.0});
    return;
  }
  const AccelIntegral& last = accel_.back();
  if (t_ns <= last.t_ns) return;
  // The sample's force held over the interval since the previous sample.
  const double dt = ToSeconds(t_ns - last.t_ns);
  const double t_mid = ToSeconds(last.t_ns - *t_ref_ns_) + 0.5 * dt;
  accel_.push_back({t_ns, last.a + accel_x_mps2 * dt, last.ta + t_mid * accel_x_mps2 * dt});
  const TimeNs keep_from = t_ns - FromSeconds(kHistoryS + 1.0);
  while (accel_.size() > 2 && accel_[1].t_ns < keep_from) accel_.pop_front();
}

EkfCourseStart::AccelIntegral EkfCourseStart::IntegralAt(TimeNs t_ns) const {
  const auto it = std::upper_bound(accel_.begin(), accel_.end(), t_ns,
                                   [](TimeNs t, const AccelIntegral& s) { return t < s.t_ns; });
  if (it == accel_.begin()) return {t_ns, 0.0, 0.0};
  return *std::prev(it);
}

std::optional<EkfCourseStart::Course> EkfCourseStart::AddFix(TimeNs t_ns, const Vec3& p_enu,
                                                            const Mat3& covariance,
                                                            double min_distance_m,
                                                            double max_yaw_sigma_rad) {
  const double var_h = covariance.topLeftCorner<2, 2>().eigenvalues().real().maxCoeff();
  while (!fixes_.empty() && t_ns - fixes_.front().t_ns > FromSeconds(kHistoryS)) {
    fixes_.pop_front();
  }
  longest_chord_m_ = 0.0;
  needed_m_ = 0.0;
  std::optional<Course> course;
  for (auto it = fixes_.rbegin(); it != fixes_.rend(); ++it) {
    if (it->t_ns >= t_ns) continue;
    const Vec2 chord = (p_enu - it->p_enu).head<2>();
    const double length = chord.norm();
    const double pair_var_h = std::max(var_h, it->var_h);
    const double needed =
        std::max(min_distance_m, std::sqrt(2.0 * pair_var_h) / max_yaw_sigma_rad);
    if (length >= longest_chord_m_) {
      longest_chord_m_ = length;
      needed_m_ = needed;
    }
    if (length < needed) continue;
    // Of the chords long enough, the one whose speed is the most precise: a short one has the
    // fixes' noise over a short time, a long one the force's error over a long time.
    const double dt = ToSeconds(t_ns - it->t_ns);
    const double accel_share = 0.5 * kAccelErrorMps2 * dt;
    const double speed_variance = 2.0 * pair_var_h / (dt * dt) + accel_share * accel_share;
    if (course && !(speed_variance < course->speed_variance)) continue;
    const AccelIntegral a0 = IntegralAt(it->t_ns);
    const AccelIntegral a1 = IntegralAt(t_ns);
    const double t0 = t_ref_ns_ ? ToSeconds(it->t_ns - *t_ref_ns_) : 0.0;
    const double gained = ((a1.ta - a0.ta) - t0 * (a1.a - a0.a)) / dt;
    Course c;
    c.yaw_rad = std::atan2(chord.y(), chord.x());
    c.yaw_variance = 2.0 * pair_var_h / (length * length);
    c.speed_mps = std::max(0.0, length / dt + gained);
    c.speed_variance = speed_variance;
    course = c;
  }
  fixes_.push_back({t_ns, p_enu, var_h});
  return course;
}

std::optional<EkfCourseStart::Course> EkfCourseStart::FromVelocity(const Vec2& v_enu,
                                                                  double sigma_h,
                                                                  const Vec3& p_body_antenna,
                                                                  double yaw_rate_radps,
                                                                  double min_speed_mps) {
  const double speed = v_enu.norm();
  if (!std::isfinite(speed) || !(sigma_h >= 0.0) ||
      speed < std::max(min_speed_mps, 10.0 * sigma_h)) {
    return std::nullopt;
  }
  const double lateral = yaw_rate_radps * p_body_antenna.x();
  if (!(std::abs(lateral) < speed)) return std::nullopt;
  const double vx = std::sqrt(speed * speed - lateral * lateral) + yaw_rate_radps * p_body_antenna.y();
  Course c;
  c.yaw_rad = std::atan2(v_enu.y(), v_enu.x()) -
              std::atan2(lateral, vx - yaw_rate_radps * p_body_antenna.y());
  c.yaw_variance = sigma_h * sigma_h / (speed * speed);
  c.speed_mps = vx;
  c.speed_variance = sigma_h * sigma_h;
  return c;
}

void EkfCourseStart::Reset() {
  fixes_.clear();
  longest_chord_m_ = needed_m_ = 0.0;
}

}  // namespace statebench::est
