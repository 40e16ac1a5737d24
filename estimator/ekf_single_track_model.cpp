#include "estimator/ekf_single_track_model.hpp"

#include <algorithm>
#include <cmath>

namespace statebench::est::ekf {

VecN SingleTrackModel::Derivative(const VecN& s, double ax, double delta) const {
  const SingleTrackParams& v = options_.vehicle;
  const double c = std::cos(s[kPsi]), sn = std::sin(s[kPsi]);
  const double vx = s[kVx], vy = s[kVy], r = s[kR];
  VecN d = VecN::Zero();
  d[kX] = vx * c - vy * sn;
  d[kY] = vx * sn + vy * c;
  d[kPsi] = r;
  d[kVx] = ax - s[kBa] + r * vy + r * r * p_body_imu_.x();
  const double lf = v.cg_to_front_axle_m, lr = v.cg_to_rear_axle_m, L = v.Wheelbase();
  const double delta_f = delta, delta_r = -v.rear_steering_ratio * delta;
  // Reversing: kinematic only (the dynamic model's lateral modes are unstable for vx < 0).
  const double w = std::clamp((vx - options_.blend_low_speed_mps) /
                                  (options_.blend_high_speed_mps - options_.blend_low_speed_mps),
                              0.0, 1.0);
  double vy_dot = 0.0, r_dot = 0.0;
  if (!has_steering_) {
    d[kVy] = -vy / options_.kinematic_time_constant_s;
    d[kR] = 0.0;
    return d;
  }
  if (w > 0.0) {
    const double alpha_f = delta_f - (vy + lf * r) / vx;
    const double alpha_r = delta_r - (vy - lr * r) / vx;
    const double fy_f = v.cornering_stiffness_front_npr * alpha_f;
    const double fy_r = v.cornering_stiffness_rear_npr * alpha_r;
    vy_dot += w * ((fy_f + fy_r) / v.mass_kg - r * vx);
    r_dot += w * ((lf * fy_f - lr * fy_r) / v.yaw_inertia_kgm2);
  }
  if (w < 1.0) {
    const double tf = std::tan(delta_f), tr = std::tan(delta_r);
    const double vy_kin = vx * (lf * tr + lr * tf) / L;
    const double r_kin = vx * (tf - tr) / L;
    const double tau = options_.kinematic_time_constant_s;
    vy_dot += (1.0 - w) * (vy_kin - vy) / tau;
    r_dot += (1.0 - w) * (r_kin - r) / tau;
  }
  d[kVy] = vy_dot;
  d[kR] = r_dot;
  return d;
}

MatN SingleTrackModel::DerivativeJacobian(const VecN& s, double ax, double delta) const {
  MatN A;
  for (int i = 0; i < kN; ++i) {
    const double h = 1e-6 * std::max(1.0, std::abs(s[i]));
    VecN sp = s, sm = s;
    sp[i] += h;
    sm[i] -= h;
    A.col(i) = (Derivative(sp, ax, delta) - Derivative(sm, ax, delta)) / (2 * h);
  }
  return A;
}

}  // namespace statebench::est::ekf
