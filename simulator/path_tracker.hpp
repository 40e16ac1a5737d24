// Pure-pursuit path tracker with a speed-dependent lookahead.
//
// The pursuit point is the vehicle's kinematic reference point (VehicleModel::ReferencePointX:
// rear axle for front steering, centre for symmetric 4-wheel steering), which moves along its
// heading without lateral slip in the kinematic limit. The goal point lies on the path a
// lookahead distance L_d = clamp(L_min + T_la u, L_min, L_max) ahead of it (measured in SUMO
// arc length). The circle through both points tangent to the heading has curvature
//   kappa = 2 y_goal / |d|^2   (d the goal in the heading frame, y_goal its lateral part),
// exact on a circular path; the steering command realises kappa through the kinematic
// single-track relation and is clamped to the steering limit. The command is a continuous
// function of the state, so it can be evaluated inside each RK4 stage.
#pragma once

#include "simulator/path.hpp"
#include "simulator/vehicle_model.hpp"

namespace statebench::sim {

struct PathTrackerOptions {
  double lookahead_min_m = 3.0;
  double lookahead_time_s = 0.6;
  double lookahead_max_m = 25.0;
};

class PathTracker {
 public:
  explicit PathTracker(PathTrackerOptions options = {}) : options_(options) {}

  // Front steering command for the vehicle at `x`, whose body origin projects on the path at
  // `origin` (Path::Project of (x.x_m, x.y_m)).
  double SteerCommand(const VehicleModel& model, const Path& path, const VehicleState& x,
                      const PathProjection& origin) const;
  double Lookahead(double u_mps) const;

 private:
  PathTrackerOptions options_;
};

}  // namespace statebench::sim
