// The EKF's odometry updates: the speed encoder and body_velocity sensors, both through the
// velocity of a point of the vehicle (ekf_point_velocity.hpp).
#include <algorithm>
#include <cmath>
#include <string>

#include "estimator/body_velocity_front_end.hpp"
#include "estimator/ekf_filter_impl.hpp"
#include "estimator/ekf_point_velocity.hpp"
#include "estimator/imu_still_window.hpp"

namespace statebench::est {

void EkfSingleTrackEstimator::Impl::UpdatePointVelocity(const std::string& id, TimeNs stamp_ns,
                                                        const Mat3& R_body_sensor,
                                                        const Vec3& p_body_point,
                                                        const Vec3& measured,
                                                        const Vec3& variance) {
  using Row = Eigen::Matrix<double, 1, kN>;
  using One = Eigen::Matrix<double, 1, 1>;
  const auto measured_component = [&](int i) {
    return variance[i] < BodyVelocityFrontEnd::kUnmeasuredVariance;
  };
  // Gate every measured component on the prior.
  const ekf::PointVelocity prior = ekf::PredictPointVelocity(x, R_body_sensor, p_body_point);
  const auto last = last_accepted_speed_ns.find(id);
  const TimeNs last_accepted_ns =
      last == last_accepted_speed_ns.end() ? initialized_ns : last->second;
  for (int i = 0; i < 3; ++i) {
    if (!measured_component(i)) continue;
    const One y(measured[i] - prior.v_sensor[i]);
    const Row H = prior.H.row(i);
    const One R(variance[i]);
    if (!Gate(Mahalanobis<1>(y, H, R), options.speed_gate_chi2, stamp_ns, last_accepted_ns)) {
      return Reject(id, stamp_ns, RejectReason::kMahalanobisGate);
    }
  }
  for (int i = 0; i < 3; ++i) {
    if (!measured_component(i)) continue;
    const ekf::PointVelocity p =
        i == 0 ? prior : ekf::PredictPointVelocity(x, R_body_sensor, p_body_point);
    const One y(measured[i] - p.v_sensor[i]);
    const Row H = p.H.row(i);
    const One R(variance[i]);
    Update<1>(y, H, R);
  }
  last_accepted_speed_ns[id] = stamp_ns;
  Accept(id, stamp_ns);
}

void EkfSingleTrackEstimator::Impl::UpdateSpeed(const std::string& id, const SensorInfo& info,
                                                const VehicleSpeed& m) {
  const double unmeasured = BodyVelocityFrontEnd::kUnmeasuredVariance;
  UpdatePointVelocity(
      id, m.header.stamp_ns, Mat3::Identity(), info.p_body_sensor, Vec3(m.speed_mps, 0.0, 0.0),
      Vec3(options.speed_sigma_mps * options.speed_sigma_mps, unmeasured, unmeasured));
}

void EkfSingleTrackEstimator::Impl::UpdateBodyVelocity(const std::string& id,
                                                       const SensorInfo& info,
                                                       const BodyVelocity& m) {
  Vec3 variance = m.covariance.diagonal().head<3>();
  const double floor = BodyVelocityFrontEnd::kMinSigmaMps * BodyVelocityFrontEnd::kMinSigmaMps;
  variance = variance.cwiseMax(floor);
  if (!(variance.minCoeff() < BodyVelocityFrontEnd::kUnmeasuredVariance)) {
    return Reject(id, m.header.stamp_ns, RejectReason::kInvalidCovariance);
  }
  UpdatePointVelocity(id, m.header.stamp_ns, info.R_body_sensor, info.p_body_sensor, m.velocity,
                      variance);
  UpdateStandstill(id, m);
}

void EkfSingleTrackEstimator::Impl::UpdateStandstill(const std::string& id, const BodyVelocity& m) {
  // The factor graph's default still test, low band included (imu_still_window.hpp).
  const ZeroVelocityOptions thresholds;
  const bool zero = BodyVelocityReadsZero(m, thresholds.max_encoder_speed_mps);
  if (zero && odometry_zero_since_ns && standstill_imu.size() >= 3) {
    const std::optional<ImuWindowStatistics> still =
        StillSpanStatistics(standstill_imu, still_imu, thresholds);
    Vec3 mean_gyro = Vec3::Zero();  // over the span since the previous sample: no sample twice
    for (const ImuSample& s : standstill_imu) mean_gyro += s.gyro;
    mean_gyro /= static_cast<double>(standstill_imu.size());
    const double mean_rate = (R_body_imu * mean_gyro).z();
    if (still && still->Quiet(thresholds) &&
        std::abs(mean_rate - x[ekf::kBg]) <= BodyVelocityFrontEnd::kMaxStillRateRadps) {
      Eigen::Matrix<double, 1, kN> H = Eigen::Matrix<double, 1, kN>::Zero();
      H(0, ekf::kBg) = 1.0;
      const double n = static_cast<double>(standstill_imu.size());
      const Eigen::Matrix<double, 1, 1> y(mean_rate - x[ekf::kBg]);
      const Eigen::Matrix<double, 1, 1> R(options.gyro_sigma_radps * options.gyro_sigma_radps / n);
      Update<1>(y, H, R);
      ++diag.sensors[id].events["zero_rate_updates"];
    }
  }
  standstill_imu.clear();
  if (zero) {
    odometry_zero_since_ns = m.header.stamp_ns;
  } else {
    odometry_zero_since_ns.reset();
  }
}

}  // namespace statebench::est
