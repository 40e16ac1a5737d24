// Planar motion of the rear-axle frame from the speed and steering encoders: the measurement of
// the kinematic factor (motion_factor_options.hpp, paper "Kinematic Factors").
//
// The speed encoder reports the mean speed V_x of its mount (rear-axle centre) along the body x
// axis over the interval since its previous sample, so each sample is a distance d = V_x dt.
// Over one interval, with front angle delta and rear angle delta_r = -ratio * delta:
//   lateral velocity  V_y = V_x tan(delta_r)                (0 for front steering)
//   yaw rate          w   = V_x (tan(delta) - tan(delta_r)) / l
// integrated with the midpoint heading psi_mid = psi + w dt / 2 in the frame of the period's
// start:  x += d cos(psi_mid) - d tan(delta_r) sin(psi_mid),  y += d sin(psi_mid) + ...,
// psi += w dt. delta is the mean of the steering samples of the interval (the latest one
// before it when none falls inside).
//
// Uncertainty of (x, y, psi), propagated per interval with F = d(state')/d(state):
//   white speed error sigma_v per sample; the wheel-radius (scale) and steering errors are
//   constant over a period, so their effects are accumulated as Jacobian columns and added as
//   rank-one terms at the end; side slip as a white lateral velocity. Vertical motion in the
//   rear-axle frame is given sigma_z = vertical_sigma * T; roll and pitch get no information.
//
// A motion is emitted every period_s of encoder time; a gap longer than max_gap_s (or a speed
// sample going backwards) restarts the integration.
#pragma once

#include <deque>
#include <optional>

#include "core/eigen_types.hpp"
#include "core/se3.hpp"
#include "core/time.hpp"
#include "estimator/motion_factor_options.hpp"

namespace statebench::est {

struct KinematicMotion {
  TimeNs t1_ns = 0;
  TimeNs t2_ns = 0;
  SE3 T_r1_r2;                          // rear-axle frame at t2 in the one at t1
  Mat6 sqrt_information = Mat6::Zero();  // (rho, phi) right perturbation, rear-axle frame
  Mat3 covariance_xy_yaw = Mat3::Zero();  // of (x, y, yaw) in the t1 frame
  double distance_m = 0.0;
};

class KinematicOdometry {
 public:
  // wheelbase_m > 0: distance between the steering (front axle) and speed (rear axle) mounts.
  KinematicOdometry(const KinematicFactorOptions& options, double wheelbase_m);

  void AddSteering(TimeNs t_ns, double angle_rad);
  // The mean speed of the interval ending at t_ns; returns a motion when a period completes.
  std::optional<KinematicMotion> AddSpeed(TimeNs t_ns, double speed_mps);
  void Reset();

  double wheelbase_m() const { return wheelbase_m_; }
  // Multiplies every later speed sample (wheel-radius calibration, EncoderScaleCalibration).
  void set_speed_scale(double scale) { speed_scale_ = scale; }
  double speed_scale() const { return speed_scale_; }

 private:
  double SteeringOver(TimeNs t0_ns, TimeNs t1_ns) const;
  void StartPeriod(TimeNs t_ns);  // zero motion and uncertainty from t_ns on
  KinematicMotion Emit(TimeNs t_ns);

  KinematicFactorOptions options_;
  double wheelbase_m_;
  std::deque<std::pair<TimeNs, double>> steering_;  // recent samples, oldest first
  std::optional<TimeNs> last_speed_ns_;
  std::optional<TimeNs> period_start_ns_;
  Vec3 state_ = Vec3::Zero();  // x, y, psi
  Mat3 P_ = Mat3::Zero();
  Vec3 J_scale_ = Vec3::Zero();
  Vec3 J_steer_ = Vec3::Zero();
  double distance_m_ = 0.0;
  double speed_scale_ = 1.0;
};

}  // namespace statebench::est
