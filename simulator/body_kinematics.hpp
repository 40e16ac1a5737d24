// Exact 3D kinematics of the body frame from the planar vehicle state, its time derivative and
// the terrain, without any finite difference.
//
// Geometry: the body origin is p = (x, y, h(x, y)). The body z axis is the terrain normal
// n = m / |m|, m = (-h_x, -h_y, 1). The body x axis is the tangent of the road above the
// heading, t / |t| with t = (cos yaw, sin yaw, grad h . (cos yaw, sin yaw)) (so `yaw` is the
// Z-Y-X yaw of the body), and y = z x x. Pitch therefore follows the grade and roll the cross
// slope.
//
// Time derivatives: with v, a the horizontal velocity and acceleration,
//   v_z = grad h . v,   a_z = grad h . a + v^T H v,
//   d/dt grad h = H v,  d2/dt2 grad h = H' v + H a,  H'_ij = sum_k h_ijk v_k,
// and for a unit vector n = m / l (l = |m|): n' = (m' - n l') / l, l' = n . m',
//   n'' = (m'' - 2 n' l' - n l'') / l,  l'' = n' . m' + n . m''.
// The angular rate in the body frame follows from R^T R' = [omega]x with R = [x y z]:
//   omega = (-y . z', x . z', y . x'),   alpha = omega' = (-(y' . z' + y . z''),
//   x' . z' + x . z'', y' . x' + y . x'').
#pragma once

#include "core/truth.hpp"
#include "simulator/terrain.hpp"
#include "simulator/vehicle_state.hpp"

namespace statebench::sim {

// Pose, velocity, acceleration, angular rate and angular acceleration of the body frame.
// `x_dot` is the time derivative of `x` (VehicleModel::Derivative).
FrameKinematics BodyKinematics(const Terrain& terrain, const VehicleState& x,
                               const VehicleState& x_dot);

}  // namespace statebench::sim
