#include "estimator/body_velocity_front_end.hpp"

#include <algorithm>
#include <cmath>

namespace statebench::est {

Claim BodyVelocityFrontEnd::Claims(const Measurement& m) const {
  if (!std::holds_alternative<BodyVelocity>(m)) return Claim::kOtherKind;
  const EstimatorSensor* s = setup_.Find(HeaderOf(m).sensor_id);
  return s != nullptr && s->kind == SensorKind::kBodyVelocity ? Claim::kTaken
                                                              : Claim::kUnknownSensor;
}

void BodyVelocityFrontEnd::Process(const Measurement& measurement) {
  const BodyVelocity& v = std::get<BodyVelocity>(measurement);
  const std::string& id = v.header.sensor_id;
  const EstimatorSensor& sensor = *setup_.Find(id);
  if (!ctx_.initialized) {
    // A setup without GNSS starts from the odometry (state_initializer.hpp).
    if (!ctx_.initializer.local().enabled) {
      return ctx_.Reject(id, v.header.stamp_ns, RejectReason::kNotInitialized);
    }
    OdometryVelocity o;
    o.t_ns = v.header.stamp_ns;
    o.v_frame = v.velocity;
    o.variance = v.covariance.diagonal().head<3>();
    o.p_imu_point = sensor.T_imu_sensor.translation();
    o.q_imu_frame = sensor.T_imu_sensor.rotation();
    if (!(o.variance.minCoeff() < kUnmeasuredVariance)) {
      return ctx_.Reject(id, v.header.stamp_ns, RejectReason::kInvalidCovariance);
    }
    ctx_.initializer.AddVelocity(o);
    return ctx_.Accept(id, v.header.stamp_ns);
  }
  BodyVelocityMeasurement m;
  m.v_frame = v.velocity;
  m.p_imu_point = sensor.T_imu_sensor.translation();
  m.q_imu_frame = sensor.T_imu_sensor.rotation();
  Vec3 information = Vec3::Zero();  // 1 / sigma per measured component
  for (int i = 0; i < 3; ++i) {
    const double variance = v.covariance(i, i);
    if (variance < kUnmeasuredVariance) {
      information[i] = 1.0 / std::max(std::sqrt(variance), kMinSigmaMps);
    }
  }
  if (information.isZero()) return ctx_.Reject(id, v.header.stamp_ns, RejectReason::kInvalidCovariance);
  m.sqrt_information = information.asDiagonal();
  if (ctx_.smoother.AddBodyVelocity(v.header.stamp_ns, m, RobustKernel{}) == AddResult::kTooOld) {
    return ctx_.Reject(id, v.header.stamp_ns, RejectReason::kTooOld);
  }
  ctx_.Accept(id, v.header.stamp_ns);
  ctx_.Count(id, "body_velocity_factors");
}

}  // namespace statebench::est
