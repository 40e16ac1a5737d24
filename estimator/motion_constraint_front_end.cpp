#include "estimator/motion_constraint_front_end.hpp"

#include <cmath>

#include "estimator/imu_window_statistics.hpp"
#include "estimator/zero_velocity_evidence.hpp"

namespace statebench::est {

MotionConstraintFrontEnd::MotionConstraintFrontEnd(const EstimatorSensorSetup& setup,
                                                   const FactorPlan& plan,
                                                   const FactorGraphOptions& options,
                                                   const EncoderFrontEnd& encoders,
                                                   const GnssFrontEnd& gnss, FrontEndContext& ctx)
    : imu_id_(setup.imu_id),
      plan_(plan),
      options_(options),
      encoders_(encoders),
      gnss_(gnss),
      ctx_(ctx),
      recent_imu_(options.zero_velocity.window_s) {}

void MotionConstraintFrontEnd::OnImu(const ImuSample& s) {
  recent_imu_.Push(s);
  if (!ctx_.initialized) return;
  const TimeNs t = s.header.stamp_ns;
  AddNonHolonomic(s);
  const ZeroVelocityOptions& z = options_.zero_velocity;
  if (!z.enabled || t < next_zupt_ns_) return;
  if (const std::optional<double> sigma = StandingStill(t)) {
    next_zupt_ns_ = t + FromSeconds(1.0 / z.rate_hz);
    ctx_.MeasureStillImu(recent_imu_.samples());
    BodyVelocityMeasurement m;
    m.sqrt_information = Mat3::Identity() / *sigma;
    if (ctx_.smoother.AddBodyVelocity(t, m, RobustKernel{}) != AddResult::kTooOld) {
      ctx_.Count(imu_id_, "zero_velocity_factors");
    }
  }
}

void MotionConstraintFrontEnd::AddNonHolonomic(const ImuSample& s) {
  const TimeNs t = s.header.stamp_ns;
  const NonHolonomicOptions& nhc = options_.non_holonomic;
  if (!nhc.enabled || t < next_nhc_ns_ || encoders_.KinematicActive(t)) return;
  next_nhc_ns_ = t + FromSeconds(1.0 / nhc.rate_hz);
  BodyVelocityMeasurement m;
  m.p_imu_point = plan_.T_imu_axle.translation();
  m.q_imu_frame = plan_.T_imu_axle.rotation();
  // Side slip grows with the lateral acceleration v * omega.
  double speed = 0.0;
  if (const auto x = ctx_.PredictMeanAt(t)) speed = x->v_world.norm();
  const double yaw_rate = (plan_.T_imu_axle.rotation().conjugate() * s.gyro).z();
  const double lateral_sigma =
      nhc.lateral_sigma_mps + nhc.slip_per_lateral_accel * speed * speed * std::abs(yaw_rate);
  m.sqrt_information = Vec3(0.0, 1.0 / lateral_sigma, 1.0 / nhc.vertical_sigma_mps).asDiagonal();
  if (ctx_.smoother.AddBodyVelocity(t, m, RobustKernel{},
                                    ImuMountCorrection(nhc, imu_id_, ctx_)) !=
      AddResult::kTooOld) {
    ctx_.Count(imu_id_, "non_holonomic_factors");
  }
}

std::optional<SlidingWindowSmoother::MountCorrection> ImuMountCorrection(
    const NonHolonomicOptions& nhc, const std::string& imu_id, FrontEndContext& ctx) {
  if (!nhc.estimate_mount) return std::nullopt;
  return ctx.MountGlobals(imu_id, nhc.mount_prior_sigma_deg * M_PI / 180.0,
                          nhc.mount_max_deg * M_PI / 180.0, /*with_roll=*/false);
}

// The IMU is quiet over the window and the speed encoder reads zero over it (without one, the
// Doppler velocity's mean is near zero, or without that the estimated speed is low).
std::optional<double> MotionConstraintFrontEnd::StandingStill(TimeNs t_ns) const {
  const ZeroVelocityOptions& z = options_.zero_velocity;
  const std::optional<ImuWindowStatistics> window = recent_imu_.Statistics(z);
  if (!window || !window->Quiet(z)) return std::nullopt;
  const Vec3& mean_a = window->mean_accel;
  if (encoders_.has_speed_encoder()) {
    // Zero over the whole window: between two ticks of a creeping wheel the encoder reads zero.
    const auto last = encoders_.last_speed();
    if (last && t_ns - last->first < FromSeconds(0.5) &&
        encoders_.ReadsZeroSince(t_ns - FromSeconds(z.window_s), z.max_encoder_speed_mps)) {
      return z.sigma_mps;
    }
    return std::nullopt;
  }
  const std::optional<NavState> x = ctx_.PredictMeanAt(t_ns);
  if (!x) return std::nullopt;
  // The covariance only where the test reads it (no Doppler).
  const std::optional<double> sigma = ZeroVelocitySigmaWithoutEncoder(
      z, gnss_.doppler().Mean(t_ns - FromSeconds(z.doppler_window_s), t_ns), [&] {
        const PropagatedVelocity p = *ctx_.PredictVelocityAt(t_ns);
        const Vec3& v = p.state.v_world;
        return EstimatedSpeedNearZero(v.head<2>(), v.z(),
                                      p.velocity_covariance.topLeftCorner<2, 2>(), z);
      });
  if (!sigma) return std::nullopt;
  const Vec3 acceleration = x->q_world_imu * (mean_a - x->accel_bias) + kGravityWorld;
  if (!(acceleration.norm() < z.max_acceleration_mps2)) return std::nullopt;
  return sigma;
}

}  // namespace statebench::est
