// The EKF's start without a GNSS antenna, in a local frame: the factor graph's initialiser
// (state_initializer.hpp, LocalStart) gives the first state from a still period or from the
// odometry while moving, with the IMU at the origin and the vehicle's forward axis along x; the
// planar filter takes its yaw, velocity, yaw rate and gyro bias from it.
#include <cmath>
#include <string>

#include "estimator/body_velocity_front_end.hpp"
#include "estimator/ekf_filter_impl.hpp"

namespace statebench::est {

void EkfSingleTrackEstimator::Impl::ResetLocalStart() {
  LocalStart local;
  local.enabled = true;
  for (const EstimatorSensor& s : setup.sensors) {
    local.has_odometry |=
        s.kind == SensorKind::kBodyVelocity || s.kind == SensorKind::kSpeedEncoder;
  }
  local_start.emplace(InitializationOptions{}, setup.imu_noise.value_or(ImuNoise{}),
                      setup.T_body_imu.rotation().conjugate() * Vec3::UnitX(), local);
}

void EkfSingleTrackEstimator::Impl::FeedLocalStart(const std::string& id, const SensorInfo& info,
                                                   const Measurement& m) {
  const double unmeasured = BodyVelocityFrontEnd::kUnmeasuredVariance;
  if (const auto* v = std::get_if<BodyVelocity>(&m)) {
    const Vec3 variance = v->covariance.diagonal().head<3>();
    if (!(variance.minCoeff() < unmeasured)) {
      return Reject(id, v->header.stamp_ns, RejectReason::kInvalidCovariance);
    }
    local_start->AddVelocity(
        MakeOdometryVelocity(v->header.stamp_ns, v->velocity, variance, info.T_imu_sensor));
    return Accept(id, v->header.stamp_ns);
  }
  if (const auto* speed = std::get_if<VehicleSpeed>(&m)) {
    // The body-x velocity of the encoder's wheel (the filter's speed model, whatever the
    // sensor's rotation in the setup).
    const SE3 T_imu_wheel = setup.T_body_imu.Inverse() * SE3(Quat::Identity(), info.p_body_sensor);
    local_start->AddVelocity(MakeOdometryVelocity(
        speed->header.stamp_ns, Vec3(speed->speed_mps, 0.0, 0.0),
        Vec3(options.speed_sigma_mps * options.speed_sigma_mps, unmeasured, unmeasured),
        T_imu_wheel));
  }
}

void EkfSingleTrackEstimator::Impl::TryStartLocal(const ImuSample& sample, double gyro_z_body) {
  local_start->AddImu(sample);
  if (const std::optional<InitialState> first = local_start->TryInitialize()) {
    InitializeFrom(*first, gyro_z_body);
  }
}

void EkfSingleTrackEstimator::Impl::InitializeFrom(const InitialState& first, double gyro_z_body) {
  const NavState& s = first.state;
  const Mat3 R_world_imu = s.q_world_imu.toRotationMatrix();
  const Mat3 R_world_body = R_world_imu * R_body_imu.transpose();
  const double psi = std::atan2(R_world_body(1, 0), R_world_body(0, 0));  // 0 in a local start
  const Mat3 Rz = ekf::YawRotation(psi);
  const Vec3 lever_world = Rz * p_body_imu;
  const double bg = (R_body_imu * s.gyro_bias).z();
  const double r = gyro_z_body - bg;
  const Vec3 v_imu_body = Rz.transpose() * s.v_world;  // the planar body frame
  x = VecN::Zero();
  x[ekf::kX] = s.p_world.x() - lever_world.x();
  x[ekf::kY] = s.p_world.y() - lever_world.y();
  x[ekf::kPsi] = psi;
  // The IMU's velocity moved to the body origin: v_imu = v + r e_z x p_body_imu.
  x[ekf::kVx] = v_imu_body.x() + r * p_body_imu.y();
  x[ekf::kVy] = v_imu_body.y() - r * p_body_imu.x();
  x[ekf::kR] = r;
  x[ekf::kBg] = bg;
  // The planar model has no pitch: the body-x component of the specific force at rest (gravity
  // along a grade, a mount tilt the setup does not know, the accelerometer's bias) is what its
  // longitudinal accelerometer bias stands for.
  x[ekf::kBa] = kGravity * (R_world_body.transpose() * Vec3::UnitZ()).x();

  const Mat15& C = first.covariance;
  P = MatN::Zero();
  P.topLeftCorner<2, 2>() = C.block<2, 2>(kPositionIndex, kPositionIndex);
  const Mat3 rotation_world =
      R_world_imu * C.block<3, 3>(kRotationIndex, kRotationIndex) * R_world_imu.transpose();
  P(ekf::kPsi, ekf::kPsi) = rotation_world(2, 2);
  const Mat3 velocity_body = Rz.transpose() * C.block<3, 3>(kVelocityIndex, kVelocityIndex) * Rz;
  P.block<2, 2>(ekf::kVx, ekf::kVx) = velocity_body.topLeftCorner<2, 2>();
  P(ekf::kR, ekf::kR) = 0.1 * 0.1;  // as the GNSS start: the gyro measures it at once
  const Mat3 gyro_bias_body =
      R_body_imu * C.block<3, 3>(kGyroBiasIndex, kGyroBiasIndex) * R_body_imu.transpose();
  P(ekf::kBg, ekf::kBg) = gyro_bias_body(2, 2);
  P(ekf::kBa, ekf::kBa) = options.init_accel_bias_sigma_mps2 * options.init_accel_bias_sigma_mps2;
  z = s.p_world.z() - lever_world.z();
  Pz = C(kPositionIndex + 2, kPositionIndex + 2);
  t_ns = s.t_ns;
  initialized = true;
  initialized_ns = t_ns;
  diag.Initialized(t_ns, first.method);
}

}  // namespace statebench::est
