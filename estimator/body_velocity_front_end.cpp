#include "estimator/body_velocity_front_end.hpp"

#include <algorithm>
#include <cmath>

#include "estimator/imu_window_statistics.hpp"

namespace statebench::est {

bool BodyVelocityReadsZero(const BodyVelocity& v, double max_speed_mps) {
  const double unmeasured = BodyVelocityFrontEnd::kUnmeasuredVariance;
  bool measured = false;
  for (int i = 0; i < 3; ++i) {
    if (!(v.covariance(i, i) < unmeasured)) continue;
    measured = true;
    if (std::abs(v.velocity[i]) > max_speed_mps) return false;
  }
  // A turn on the spot moves no point of the axle: the wheels' yaw rate, when measured, must be
  // zero too (to a wheel speed difference of max_speed_mps over a 1 m track).
  if (v.covariance(5, 5) < unmeasured && std::abs(v.angular_velocity.z()) > max_speed_mps) {
    return false;
  }
  return measured;
}

BodyVelocityFrontEnd::BodyVelocityFrontEnd(const EstimatorSensorSetup& setup,
                                           const FactorGraphOptions& options, FrontEndContext& ctx)
    : setup_(setup),
      options_(options),
      ctx_(ctx),
      still_window_(options.zero_velocity.window_s) {}

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
    // A setup without GNSS, or with GNSS that cannot start it yet, starts from the odometry in a
    // local frame (state_initializer.hpp).
    if (!ctx_.initializer.local().enabled) {
      return ctx_.Reject(id, v.header.stamp_ns, RejectReason::kNotInitialized);
    }
    const OdometryVelocity o = MakeOdometryVelocity(
        v.header.stamp_ns, v.velocity, v.covariance.diagonal().head<3>(), sensor.T_imu_sensor);
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
  if (!options_.zero_velocity.enabled) return;
  if (!BodyVelocityReadsZero(v, options_.zero_velocity.max_encoder_speed_mps)) {
    zero_since_ns_.reset();
    recent_imu_.clear();
    return;
  }
  if (zero_since_ns_) AddZeroRate(id, v.header.stamp_ns);
  zero_since_ns_ = v.header.stamp_ns;
  recent_imu_.clear();
}

void BodyVelocityFrontEnd::OnImu(const ImuSample& sample) {
  still_window_.Push(sample);
  if (zero_since_ns_ && sample.header.stamp_ns > *zero_since_ns_) recent_imu_.push_back(sample);
}

void BodyVelocityFrontEnd::OnRestart() {
  zero_since_ns_.reset();
  recent_imu_.clear();
  still_window_.Clear();
}

void BodyVelocityFrontEnd::AddZeroRate(const std::string& id, TimeNs t_ns) {
  const ZeroVelocityOptions& z = options_.zero_velocity;
  if (recent_imu_.size() < 3) return;
  const std::optional<ImuWindowStatistics> still =
      StillSpanStatistics(recent_imu_, still_window_, z);
  if (!still || !still->Quiet(z)) return;
  Vec3 mean_g = Vec3::Zero();  // over the span since the previous sample: no sample twice
  for (const ImuSample& s : recent_imu_) mean_g += s.gyro;
  mean_g /= static_cast<double>(recent_imu_.size());
  const std::optional<NavState> predicted = ctx_.PredictMeanAt(t_ns);
  if (!predicted || (mean_g - predicted->gyro_bias).norm() > kMaxStillRateRadps) return;
  const double span_s = ToSeconds(recent_imu_.back().header.stamp_ns - *zero_since_ns_);
  if (!(span_s > 0.0)) return;
  // The noise in use: the datasheet's, or the measured one above it (imu_noise_monitor.hpp).
  const double sigma = ctx_.imu_noise().gyro_noise_density / std::sqrt(span_s);
  if (ctx_.smoother.AddZeroRate(t_ns, mean_g, sigma, RobustKernel{}) != AddResult::kTooOld) {
    ctx_.Count(id, "zero_rate_factors");
  }
}

}  // namespace statebench::est
