// Body-velocity front end: generic velocity odometry of a sensor frame (wheel odometry of a
// differential or skid-steer robot, radar, a visual odometry's twist) as a velocity factor of
// the sensor point at its own stamp. Each velocity component is weighted by its own variance;
// a component whose variance is at least kUnmeasuredVariance (ROS drivers write 1e3-1e6 for
// what they do not measure) carries no information. The angular velocity is not used: the IMU
// measures it better. Before the first state of a setup without GNSS, the samples go to the
// initialiser (a moving start in a local frame, or the proof of a standstill).
#pragma once

#include "estimator/front_end.hpp"

namespace statebench::est {

class BodyVelocityFrontEnd final : public MeasurementFrontEnd {
 public:
  static constexpr double kUnmeasuredVariance = 1e2;  // (m/s)^2
  static constexpr double kMinSigmaMps = 1e-3;        // floor of a reported sigma

  // `setup` must outlive the front end.
  BodyVelocityFrontEnd(const EstimatorSensorSetup& setup, FrontEndContext& ctx)
      : setup_(setup), ctx_(ctx) {}

  Claim Claims(const Measurement& m) const override;
  void Process(const Measurement& m) override;

 private:
  const EstimatorSensorSetup& setup_;
  FrontEndContext& ctx_;
};

}  // namespace statebench::est
