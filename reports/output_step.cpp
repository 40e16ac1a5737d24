#include "reports/output_step.hpp"

#include <cmath>

#include "core/so3.hpp"

namespace statebench::reports {
namespace {

double YawOf(const Quat& q) { return so3::ToRollPitchYaw(q).z(); }

StepStatistics StepStatisticsOf(const RunningStatistics& s) {
  StepStatistics out;
  out.count = s.count();
  out.p50 = s.Median();
  out.p99 = s.Quantile(0.99);
  out.max = s.max();
  return out;
}

}  // namespace

OutputStepErrors StepAgainstReference(const NavState& previous, const NavState& current,
                                      const ReferenceState& previous_reference,
                                      const ReferenceState& current_reference) {
  const SE3& a = previous_reference.T_world_frame;
  const SE3& b = current_reference.T_world_frame;
  OutputStepErrors e;
  e.position_m = ((current.p_world - previous.p_world) - (b.translation() - a.translation())).norm();
  const double estimated = YawOf(current.q_world_imu) - YawOf(previous.q_world_imu);
  const double reference = YawOf(b.rotation()) - YawOf(a.rotation());
  e.yaw_rad = std::abs(so3::WrapAngle(estimated - reference));
  return e;
}

OutputStepErrors StepAgainstOwnMotion(const NavState& previous, const NavState& current,
                                      const Vec3& previous_omega_imu, const Vec3& omega_imu) {
  const double dt = ToSeconds(current.t_ns - previous.t_ns);
  OutputStepErrors e;
  e.position_m =
      (current.p_world - previous.p_world - 0.5 * (previous.v_world + current.v_world) * dt)
          .norm();
  const Vec3 rate = 0.5 * (previous_omega_imu + omega_imu) - current.gyro_bias;
  const Quat predicted = previous.q_world_imu * so3::Exp<double>(rate * dt);
  e.yaw_rad = std::abs(so3::WrapAngle(YawOf(current.q_world_imu) - YawOf(predicted)));
  return e;
}

void OutputStepStatistics::Add(const OutputStepErrors& e) {
  if (std::isfinite(e.position_m)) position_m_.Add(e.position_m);
  if (std::isfinite(e.yaw_rad)) yaw_rad_.Add(e.yaw_rad);
}

OutputSteps OutputStepStatistics::Summary() const {
  return {StepStatisticsOf(position_m_), StepStatisticsOf(yaw_rad_)};
}

void OwnMotionStepMeter::Add(const NavState& estimate, const Vec3& omega_imu) {
  const bool finite = estimate.p_world.allFinite() && estimate.v_world.allFinite() &&
                      estimate.q_world_imu.coeffs().allFinite() && omega_imu.allFinite();
  if (!finite) return Break();
  if (previous_ && estimate.t_ns > previous_->state.t_ns) {
    statistics_.Add(
        StepAgainstOwnMotion(previous_->state, estimate, previous_->omega_imu, omega_imu));
  }
  previous_ = Previous{estimate, omega_imu};
}

}  // namespace statebench::reports
