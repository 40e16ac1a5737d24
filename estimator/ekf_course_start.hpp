// The EKF's moving start from one GNSS antenna (EkfSingleTrackEstimator without a dual-antenna
// heading): the course is a chord from the newest fix to an earlier fix of the last kHistoryS
// far enough from it for the course precision asked (about sqrt(2) sigma_h / length); of those,
// the one that gives the most precise speed. The speed at the newest fix is the chord's mean
// speed plus what the IMU's longitudinal specific force added since the chord's midpoint:
//
//   v(t1) = |p1 - p0| / (t1 - t0) + 1 / (t1 - t0) * integral_t0^t1 (t - t0) a(t) dt,
//
// exact for a straight chord when a(t) is the longitudinal acceleration (the specific force also
// holds the grade's g sin(theta) and the accelerometer bias: their share is in the speed's
// variance, kAccelErrorMps2, which grows with the chord's duration; the fixes' noise shrinks
// with it). Using the chord's newest end matters after a standstill: a car
// parked with the receiver on sends fixes that scatter around one point; the log's first fix
// and the fixes when the car is moving are half a minute apart, and the mean speed over the
// chord is a fraction of the speed at its end.
#pragma once

#include <deque>
#include <optional>

#include "core/eigen_types.hpp"
#include "core/time.hpp"

namespace statebench::est {

class EkfCourseStart {
 public:
  // Uncertainty of the longitudinal acceleration the specific force stands for: a 4 % grade
  // (0.4 m/s^2) and a consumer accelerometer's bias.
  static constexpr double kAccelErrorMps2 = 0.5;
  // Fixes older than this (from the newest) are forgotten.
  static constexpr double kHistoryS = 60.0;

  struct Course {
    double yaw_rad = 0.0;  // of the chord
    double yaw_variance = 0.0;
    double speed_mps = 0.0;  // at the newest fix
    double speed_variance = 0.0;
  };

  // The body-x specific force (m/s^2) at each IMU sample, in stamp order.
  void AddForwardAccel(TimeNs t_ns, double accel_x_mps2);

  // A fix of the course antenna (ENU position and its adjusted covariance). The course once a
  // chord reaches max(min_distance_m, sqrt(2 var_h) / max_yaw_sigma_rad), var_h the larger
  // horizontal variance of its two fixes.
  std::optional<Course> AddFix(TimeNs t_ns, const Vec3& p_enu, const Mat3& covariance,
                               double min_distance_m, double max_yaw_sigma_rad);

  void Reset();

  bool has_fix() const { return !fixes_.empty(); }
  // The longest chord from the newest fix within the history, and the length it needed (for
  // "waiting for" messages).
  double longest_chord_m() const { return longest_chord_m_; }
  double needed_m() const { return needed_m_; }

 private:
  struct Fix {
    TimeNs t_ns = 0;
    Vec3 p_enu = Vec3::Zero();
    double var_h = 0.0;
  };
  // Running integrals of the specific force from the first sample: a(t) dt and
  // (t - t_ref) a(t) dt, at each sample's stamp.
  struct AccelIntegral {
    TimeNs t_ns = 0;
    double a = 0.0;
    double ta = 0.0;
  };
  // The integrals at t_ns (the latest sample at or before it; zeros before the first).
  AccelIntegral IntegralAt(TimeNs t_ns) const;

  std::deque<Fix> fixes_;
  std::deque<AccelIntegral> accel_;
  std::optional<TimeNs> t_ref_ns_;
  double longest_chord_m_ = 0.0;
  double needed_m_ = 0.0;
};

}  // namespace statebench::est
