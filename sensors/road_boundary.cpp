#include "sensors/road_boundary.hpp"

#include <algorithm>
#include <cmath>

namespace statebench::sensors {

double BoundaryRun::Length() const {
  return samples.empty() ? 0.0 : samples.back().s_m + 0.5 * samples.back().ds_m;
}

const BoundarySample& BoundaryRun::At(double s) const {
  // First sample whose stretch ends after s.
  const auto it = std::lower_bound(
      samples.begin(), samples.end(), s,
      [](const BoundarySample& b, double value) { return b.s_m + 0.5 * b.ds_m <= value; });
  return it == samples.end() ? samples.back() : *it;
}

Vec2 BoundaryRun::PointAt(double s) const {
  const BoundarySample& b = At(s);
  return b.p_edge + (s - b.s_m) * b.tangent;
}

std::vector<BoundaryRun> FindOuterBoundaries(const RoadGeometry& roads,
                                             const RoadClearance& clearance, double step_m,
                                             double probe_m, double min_length_m) {
  std::vector<BoundaryRun> runs;
  BoundaryRun current;
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
        const double ds = length / n;
        for (int k = 0; k < n; ++k) {
          const double u = (k + 0.5) / n;
          const Vec2 p_edge = a + u * (b - a) + 0.5 * lane.width_m * outward;
          if (clearance.OnRoad(p_edge + probe_m * outward)) {
            close_run();
          } else {
            current.samples.push_back({p_edge, tangent, outward, current.Length() + 0.5 * ds, ds});
          }
        }
      }
      close_run();
    }
  }
  return runs;
}

}  // namespace statebench::sensors
