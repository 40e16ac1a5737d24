#include "estimator/encoder_front_end.hpp"

#include <cmath>

#include "core/so3.hpp"
#include "estimator/body_velocity_front_end.hpp"
#include "estimator/motion_constraint_front_end.hpp"

namespace statebench::est {

EncoderFrontEnd::EncoderFrontEnd(const EstimatorSensorSetup& setup, const FactorPlan& plan,
                                 const FactorGraphOptions& options, FrontEndContext& ctx)
    : setup_(setup), plan_(plan), options_(options), ctx_(ctx) {
  if (plan.kinematic) {
    kinematic_.emplace(options.kinematic, plan.wheelbase_m);
    encoder_scale_.emplace(plan.T_imu_axle);
  }
}

Claim EncoderFrontEnd::Claims(const Measurement& m) const {
  SensorKind kind;
  if (std::holds_alternative<VehicleSpeed>(m)) {
    kind = SensorKind::kSpeedEncoder;
  } else if (std::holds_alternative<SteeringAngle>(m)) {
    kind = SensorKind::kSteeringEncoder;
  } else {
    return Claim::kOtherKind;
  }
  const EstimatorSensor* s = setup_.Find(HeaderOf(m).sensor_id);
  return s != nullptr && s->kind == kind ? Claim::kTaken : Claim::kUnknownSensor;
}

// Steering before speed: the speed sample closing an interval uses the steering of its stamp.
int EncoderFrontEnd::Pass(const Measurement& m) const {
  return std::holds_alternative<SteeringAngle>(m) ? 0 : 1;
}

void EncoderFrontEnd::Process(const Measurement& m) {
  if (const auto* a = std::get_if<SteeringAngle>(&m)) return ProcessSteering(*a);
  if (const auto* v = std::get_if<VehicleSpeed>(&m)) return ProcessSpeed(*v);
}

bool EncoderFrontEnd::KinematicActive(TimeNs t_ns) const {
  return kinematic_ && last_kinematic_ns_ != INT64_MIN &&
         t_ns - last_kinematic_ns_ < FromSeconds(0.5);
}

void EncoderFrontEnd::ProcessSteering(const SteeringAngle& a) {
  const std::string& id = a.header.sensor_id;
  if (!kinematic_ || plan_.steering == nullptr || id != plan_.steering->id) {
    return ctx_.Reject(id, a.header.stamp_ns, RejectReason::kDisabled);
  }
  kinematic_->AddSteering(a.header.stamp_ns, a.angle_rad);
  ctx_.Accept(id, a.header.stamp_ns);
}

void EncoderFrontEnd::ProcessSpeed(const VehicleSpeed& v) {
  const std::string& id = v.header.sensor_id;
  if (plan_.speed == nullptr || id != plan_.speed->id) {
    return ctx_.Reject(id, v.header.stamp_ns, RejectReason::kDisabled);
  }
  recent_speeds_.emplace_back(v.header.stamp_ns, v.speed_mps);
  while (recent_speeds_.front().first < v.header.stamp_ns - FromSeconds(1.0)) {
    recent_speeds_.pop_front();
  }
  if (!ctx_.initialized && ctx_.initializer.local().enabled) {
    // The velocity of the rear axle's centre, (V, 0, 0) in its frame: lateral and vertical are
    // not measured (the initialiser takes them as zero, loosely).
    const double unmeasured = BodyVelocityFrontEnd::kUnmeasuredVariance;
    ctx_.initializer.AddVelocity(MakeOdometryVelocity(
        v.header.stamp_ns, Vec3(v.speed_mps, 0.0, 0.0),
        Vec3(options_.kinematic.speed_sigma_mps * options_.kinematic.speed_sigma_mps, unmeasured,
             unmeasured),
        plan_.T_imu_axle));
  }
  if (encoder_scale_) encoder_scale_->AddSpeed(v.header.stamp_ns, v.speed_mps);
  if (!kinematic_) {
    // Still used to detect standstill for the zero-velocity factor.
    if (options_.zero_velocity.enabled) return ctx_.Accept(id, v.header.stamp_ns);
    return ctx_.Reject(id, v.header.stamp_ns, RejectReason::kDisabled);
  }
  if (!ctx_.initialized) {
    kinematic_->AddSpeed(v.header.stamp_ns, v.speed_mps);  // keeps the integration going
    return ctx_.Reject(id, v.header.stamp_ns, RejectReason::kNotInitialized);
  }
  const std::optional<KinematicMotion> motion =
      kinematic_->AddSpeed(v.header.stamp_ns, v.speed_mps);
  ctx_.Accept(id, v.header.stamp_ns);
  if (!motion) return;
  RelativePoseMeasurement m;
  m.T_s1_s2 = motion->T_r1_r2;
  m.T_imu_sensor = plan_.T_imu_axle;
  m.sqrt_information = motion->sqrt_information;
  RobustKernel kernel;  // Huber at 3 sigma: wheel slip
  // The axle frame is the vehicle frame of the non-holonomic constraint: the same IMU mount
  // correction, when estimated.
  const auto mount = ImuMountCorrection(options_.non_holonomic, setup_.imu_id, ctx_);
  if (ctx_.smoother.AddRelativePose(motion->t1_ns, motion->t2_ns, m, kernel, mount) ==
      AddResult::kTooOld) {
    return ctx_.Count(id, "kinematic_factor_too_old");
  }
  last_kinematic_ns_ = motion->t2_ns;
  ctx_.Count(id, "kinematic_factors");
}

// A moving initialisation takes the velocity from GNSS fixes differenced over a second or so
// (metres per second of error with single-point fixes). With a speed encoder the velocity in
// the IMU frame is known to centimetres per second: v_imu = R_imu_axle (V, 0, 0) -
// (w - b_g) x p_imu_axle, and v_world = R v_imu. Its world-frame covariance follows the
// orientation's: dv = -R [v_imu]x dtheta (right perturbation) plus the encoder's own error.
void EncoderFrontEnd::RefineInitialState(const ImuSample& s, InitialState* init) const {
  const std::optional<std::pair<TimeNs, double>> last_speed = this->last_speed();
  if (plan_.speed == nullptr || !last_speed ||
      std::abs(ToSeconds(s.header.stamp_ns - last_speed->first)) > 0.1) {
    return;
  }
  constexpr double kEncoderSigmaMps = 0.1;  // before the radius is calibrated, and slip
  const NavState& x = init->state;
  const Vec3 omega = s.gyro - x.gyro_bias;
  const Vec3 v_imu = plan_.T_imu_axle.rotation() * Vec3(last_speed->second, 0.0, 0.0) -
                     omega.cross(plan_.T_imu_axle.translation());
  const Mat3 R = x.q_world_imu.toRotationMatrix();
  const Mat3 J = -R * so3::Hat<double>(v_imu);
  Mat15& P = init->covariance;
  const Mat3 P_rot = P.block<3, 3>(0, 0);
  P.block<3, 15>(6, 0).setZero();
  P.block<15, 3>(0, 6).setZero();
  P.block<3, 3>(6, 6) =
      J * P_rot * J.transpose() + kEncoderSigmaMps * kEncoderSigmaMps * Mat3::Identity();
  P.block<3, 3>(6, 0) = J * P_rot;
  P.block<3, 3>(0, 6) = P.block<3, 3>(6, 0).transpose();
  init->state.v_world = R * v_imu;
  init->method += " + encoder speed";
}

void EncoderFrontEnd::OnMarginalized(std::span<const NavState> left) {
  if (!encoder_scale_ || !kinematic_) return;
  encoder_scale_->AddSmoothedStates(std::vector<NavState>(left.begin(), left.end()));
  if (const auto scale = encoder_scale_->scale()) kinematic_->set_speed_scale(*scale);
}

bool EncoderFrontEnd::ReadsZeroSince(TimeNs from_ns, double max_mps) const {
  if (recent_speeds_.empty() || recent_speeds_.front().first > from_ns) return false;
  for (auto it = recent_speeds_.rbegin(); it != recent_speeds_.rend(); ++it) {
    if (std::abs(it->second) > max_mps) return false;
    if (it->first <= from_ns) return true;
  }
  return true;
}

}  // namespace statebench::est
