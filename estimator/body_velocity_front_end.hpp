// Body-velocity front end: generic velocity odometry of a sensor frame (wheel odometry of a
// differential or skid-steer robot, radar, a visual odometry's twist) as a velocity factor of
// the sensor point at its own stamp. Each velocity component is weighted by its own variance;
// a component whose variance is at least kUnmeasuredVariance (ROS drivers write 1e3-1e6 for
// what they do not measure) carries no information. The angular velocity is not used: the IMU
// measures it better. Before the first state of a setup without GNSS, the samples go to the
// initialiser (a moving start in a local frame, or the proof of a standstill).
//
// Wheel odometry reads exactly zero when the wheels stand (no encoder tick): two consecutive
// samples whose measured components are all below zero_velocity.max_encoder_speed_mps (and
// whose angular rate about z, when measured, too), with the IMU quiet (the zero-velocity test
// over the rolling window ending with the newer sample, or over the span when it is longer:
// imu_still_window.hpp, so the low band serves an engine running) and its mean rate over the
// span within kMaxStillRateRadps of the estimated gyro
// bias (not a steady turn on the spot), prove a standstill over that span: the mean gyro is
// then a measurement of the gyro bias (zero_rate_factor.hpp, Huber kernel), counted as
// `zero_rate_factors`. Without an absolute heading it is what keeps the gyro's z bias, hence
// the yaw, from drifting.
#pragma once

#include <optional>
#include <vector>

#include "estimator/front_end.hpp"
#include "estimator/imu_still_window.hpp"

namespace statebench::est {

// Whether wheel odometry v reads zero: every measured component (variance below
// BodyVelocityFrontEnd::kUnmeasuredVariance), and the yaw rate if measured, within
// max_speed_mps (the yaw rate: a wheel speed difference of max_speed_mps over a 1 m track); false
// when nothing is measured.
bool BodyVelocityReadsZero(const BodyVelocity& v, double max_speed_mps);

class BodyVelocityFrontEnd final : public MeasurementFrontEnd {
 public:
  static constexpr double kUnmeasuredVariance = 1e2;  // (m/s)^2
  static constexpr double kMinSigmaMps = 1e-3;        // floor of a reported sigma
  static constexpr double kMaxStillRateRadps = 0.02;  // |mean gyro - bias| of a standstill

  // `setup` and `options` must outlive the front end.
  BodyVelocityFrontEnd(const EstimatorSensorSetup& setup, const FactorGraphOptions& options,
                       FrontEndContext& ctx);

  Claim Claims(const Measurement& m) const override;
  void Process(const Measurement& m) override;
  void OnImu(const ImuSample& sample) override;
  void OnRestart() override;

 private:
  // The zero-rate factor over the IMU samples since the previous sample of sensor `id`.
  void AddZeroRate(const std::string& id, TimeNs t_ns);

  const EstimatorSensorSetup& setup_;
  const FactorGraphOptions& options_;
  FrontEndContext& ctx_;
  std::optional<TimeNs> zero_since_ns_;  // the previous sample read zero, at this stamp
  std::vector<ImuSample> recent_imu_;    // released samples after zero_since_ns_
  ImuStillWindow still_window_;          // the newest released samples, for the still test
};

}  // namespace statebench::est
