#include "simulator/path_tracker.hpp"

#include <algorithm>
#include <cmath>

namespace statebench::sim {

double PathTracker::Lookahead(double u_mps) const {
  return std::clamp(options_.lookahead_min_m + options_.lookahead_time_s * std::abs(u_mps),
                    options_.lookahead_min_m, options_.lookahead_max_m);
}

double PathTracker::SteerCommand(const VehicleModel& model, const Path& path, const VehicleState& x,
                                 const PathProjection& origin) const {
  const double c = std::cos(x.yaw_rad);
  const double s = std::sin(x.yaw_rad);
  const double x_ref = model.ReferencePointX();
  const Vec2 reference = Vec2(x.x_m, x.y_m) + x_ref * Vec2(c, s);
  const Vec2 goal = path.PositionAtRaw(origin.raw_s_m + x_ref + Lookahead(x.u_mps));
  const Vec2 d = goal - reference;
  const double lateral = -s * d.x() + c * d.y();
  const double kappa = 2.0 * lateral / std::max(d.squaredNorm(), 1e-6);
  const double limit = model.params().max_steering_angle_rad;
  return std::clamp(model.SteerForCurvature(kappa), -limit, limit);
}

}  // namespace statebench::sim
