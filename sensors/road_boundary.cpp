#include "sensors/road_boundary.hpp"

#include <algorithm>
#include <cmath>

namespace statebench::sensors {

const BoundarySample& BoundaryRun::At(double s) const {
  const auto i = static_cast<long>(std::floor(s / step_m));
  const long last = static_cast<long>(samples.size()) - 1;
  return samples[static_cast<std::size_t>(std::clamp(i, 0L, last))];
}

std::vector<BoundaryRun> FindOuterBoundaries(const RoadGeometry& roads,
                                             const RoadClearance& clearance, double step_m,
                                             double probe_m, double min_length_m) {
  std::vector<BoundaryRun> runs;
  BoundaryRun current;
  current.step_m = step_m;
  const auto close_run = [&]() {
    if (current.Length() >= min_length_m) runs.push_back(current);
    current.samples.clear();
  };

  for (const LaneShape& lane : roads.lanes) {
    for (const double side : {1.0, -1.0}) {  // +1: left edge, -1: right edge
      for (std::size_t i = 0; i + 1 < lane.centre.size(); ++i) {
        const Vec2 a = lane.centre[i].head<2>();
        const Vec2 b = lane.centre[i + 1].head<2>();
        const double length = (b - a).norm();
        if (length < 1e-9) continue;
        const Vec2 tangent = (b - a) / length;
        const Vec2 outward = side * Vec2(-tangent.y(), tangent.x());
        const int n = std::max(1, static_cast<int>(std::round(length / step_m)));
        for (int k = 0; k < n; ++k) {
          const double u = (k + 0.5) / n;
          const Vec2 p_edge = a + u * (b - a) + 0.5 * lane.width_m * outward;
          if (clearance.OnRoad(p_edge + probe_m * outward)) {
            close_run();
          } else {
            current.samples.push_back({p_edge, tangent, outward});
          }
        }
      }
      close_run();
    }
  }
  return runs;
}

}  // namespace statebench::sensors
