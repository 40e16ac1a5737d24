// Strapdown inertial integration on a flat, non-rotating earth (gravity kGravityWorld).
//
//   dq/dt = 1/2 q (x) (0, omega_body),   dv/dt = R(q) f_body + g,   dp/dt = v
//
// integrated with classic RK4. The rates come as samples (a gyro and an accelerometer reading,
// or exact truth); a step over [t, t + h] uses the rates at t, t + h/2 and t + h. For uniformly
// sampled rates the midpoint is a cubic (4-point) interpolation of the samples, so the scheme
// is 4th order in the sample interval. The quaternion is renormalised after each step.
#pragma once

#include <vector>

#include "core/eigen_types.hpp"

namespace statebench {

struct StrapdownState {
  Quat q_world_body = Quat::Identity();
  Vec3 p_world = Vec3::Zero();  // m
  Vec3 v_world = Vec3::Zero();  // m/s
};

struct InertialRates {
  Vec3 omega_body = Vec3::Zero();           // rad/s, angular rate in the body frame
  Vec3 specific_force_body = Vec3::Zero();  // m/s^2, R^T (a - g)
};

// One RK4 step of length h_s from the rates at its start, middle and end.
StrapdownState StrapdownStep(const StrapdownState& x, const InertialRates& start,
                             const InertialRates& middle, const InertialRates& end, double h_s);

// Integrates rates sampled every dt_s from `initial` (the state at samples[0]); returns the
// state at every sample, out[0] = initial. Needs at least one sample.
std::vector<StrapdownState> IntegrateStrapdown(const StrapdownState& initial,
                                               const std::vector<InertialRates>& samples,
                                               double dt_s);

}  // namespace statebench
