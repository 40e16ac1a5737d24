#include "simulator/vehicle_simulation.hpp"

#include <cmath>

#include "core/error.hpp"
#include "simulator/body_kinematics.hpp"

namespace statebench::sim {

PathOptions PathOptionsFor(const VehicleParams& params) {
  const double d = params.max_steering_angle_rad;
  PathOptions options;
  options.max_curvature_1pm =
      0.7 * (std::tan(d) + std::tan(params.rear_steering_ratio * d)) / params.wheelbase_m();
  return options;
}

VehicleSimulation::VehicleSimulation(VehicleParams params, std::shared_ptr<const Path> path,
                                     std::shared_ptr<const Terrain> terrain,
                                     VehicleSimulationOptions options)
    : model_(std::move(params), std::move(terrain), options.model),
      path_(std::move(path)),
      tracker_(options.tracker),
      speed_(options.speed) {
  if (!path_) throw InputError("vehicle simulation: no path");
  Reset(0.0, 0.0);
}

void VehicleSimulation::Reset(double s_raw_m, double v_mps, TimeNs t_ns) {
  const RawToPath mapped = path_->FromRaw(s_raw_m);
  const PathPoint at = path_->At(mapped.s_m);
  state_ = VehicleState{};
  state_.x_m = at.position.x();
  state_.y_m = at.position.y();
  state_.yaw_rad = at.heading_rad;
  state_.u_mps = v_mps;
  state_.steer_rad = model_.SteerForCurvature(at.curvature_1pm);
  // No-slip lateral velocity and yaw rate of the kinematic model.
  const double l = model_.params().wheelbase_m();
  const double tf = std::tan(state_.steer_rad);
  const double tr = std::tan(model_.RearSteer(state_.steer_rad));
  state_.w_mps =
      v_mps * (model_.params().cg_to_rear_axle_m * tf + model_.params().cg_to_front_axle_m * tr) /
      l;
  state_.yaw_rate_radps = v_mps * (tf - tr) / l;
  // Force that holds the speed against resistance and slope.
  state_.force_n =
      model_.Resistance(v_mps) - model_.params().mass_kg * model_.SlopeGravity(state_).x();
  t_ns_ = t_ns;
  // Project near s: a route driven in loops overlaps itself, and a global search could pick
  // the same place on another lap.
  projection_ = path_->Project(at.position, path_->HintAt(mapped.s_m));
  reference_ = SpeedReference{mapped.s_m, v_mps * mapped.ds_draw, 0.0};
}

VehicleState VehicleSimulation::ClosedLoopDerivative(const VehicleState& x, double tau_s) const {
  const PathProjection origin = path_->Project(Vec2(x.x_m, x.y_m), projection_);
  SpeedReference ref;
  ref.s_m = reference_.s_m + tau_s * (reference_.v_mps + 0.5 * tau_s * reference_.a_mps2);
  ref.v_mps = reference_.v_mps + tau_s * reference_.a_mps2;
  ref.a_mps2 = reference_.a_mps2;
  const Vec2 gradient = model_.terrain().Evaluate(x.x_m, x.y_m, 1).gradient;
  VehicleCommand command;
  command.steer_rad = tracker_.SteerCommand(model_, *path_, x, origin);
  command.force_n = speed_.ForceCommand(model_, x, origin.s_m, ref,
                                        VehicleModel::SlopeGravity(x.yaw_rad, gradient).x());
  return model_.Derivative(x, command, gradient);
}

void VehicleSimulation::Step(double s_raw_ref_m, double v_ref_mps, double a_ref_mps2) {
  // SUMO's reference moved onto the smoothed path: s = S(s_raw), v = S' v_raw,
  // a = S'' v_raw^2 + S' a_raw.
  const RawToPath m = path_->FromRaw(s_raw_ref_m);
  reference_.s_m = m.s_m;
  reference_.v_mps = m.ds_draw * v_ref_mps;
  reference_.a_mps2 = m.d2s_draw2 * v_ref_mps * v_ref_mps + m.ds_draw * a_ref_mps2;

  const double h = ToSeconds(kStepNs);
  const VehicleState k1 = ClosedLoopDerivative(state_, 0.0);
  const VehicleState k2 = ClosedLoopDerivative(state_.Plus(k1, 0.5 * h), 0.5 * h);
  const VehicleState k3 = ClosedLoopDerivative(state_.Plus(k2, 0.5 * h), 0.5 * h);
  const VehicleState k4 = ClosedLoopDerivative(state_.Plus(k3, h), h);
  state_ = state_.Plus(k1, h / 6.0).Plus(k2, h / 3.0).Plus(k3, h / 3.0).Plus(k4, h / 6.0);
  t_ns_ += kStepNs;
  projection_ = path_->Project(Vec2(state_.x_m, state_.y_m), projection_);
  // The reference at the new time, for Truth() and the next step's warm start.
  reference_.s_m += h * (reference_.v_mps + 0.5 * h * reference_.a_mps2);
  reference_.v_mps += h * reference_.a_mps2;
}

TruthSample VehicleSimulation::Truth() const {
  const VehicleState x_dot = ClosedLoopDerivative(state_, 0.0);
  TruthSample truth;
  truth.t_ns = t_ns_;
  truth.body = BodyKinematics(model_.terrain(), state_, x_dot);
  truth.steering_front_rad = state_.steer_rad;
  truth.steering_rear_rad = model_.RearSteer(state_.steer_rad);
  // Wheel speed: velocity of the wheel's contact point (a body point) along the wheel's
  // rolling direction, over the rolling radius.
  const Vec3 v_body = truth.body.VelocityInFrame();
  const std::array<double, 4> angles = model_.WheelAngles(state_.steer_rad);
  for (int i = 0; i < 4; ++i) {
    const Vec3 v_contact = v_body + truth.body.omega_frame.cross(model_.WheelContacts()[i]);
    const Vec3 rolling(std::cos(angles[i]), std::sin(angles[i]), 0.0);
    truth.wheel_omega_radps[i] = v_contact.dot(rolling) / model_.params().wheel_radius_m;
  }
  // Side slip of the body origin; at standstill its limit for rolling off without slip,
  // atan(A) (vehicle_model.hpp), instead of the angle of a rounding-noise velocity.
  if (v_body.head<2>().norm() > 1e-6) {
    truth.sideslip_rad = std::atan2(v_body.y(), v_body.x());
  } else {
    const VehicleParams& p = model_.params();
    truth.sideslip_rad = std::atan((p.cg_to_rear_axle_m * std::tan(truth.steering_front_rad) +
                                    p.cg_to_front_axle_m * std::tan(truth.steering_rear_rad)) /
                                   p.wheelbase_m());
  }
  truth.distance_m = state_.distance_m;
  return truth;
}

}  // namespace statebench::sim
