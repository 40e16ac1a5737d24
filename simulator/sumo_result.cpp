#include "simulator/sumo_result.hpp"

#include <cmath>

namespace statebench::sim {

std::vector<std::vector<Vec3>> SumoResult::LaneShapes() const {
  std::vector<std::vector<Vec3>> shapes;
  shapes.reserve(lanes.size());
  for (const LaneGeometry& lane : lanes) shapes.push_back(lane.shape);
  return shapes;
}

std::vector<Vec3> SumoResult::LanePoints(double spacing_m) const {
  std::vector<Vec3> points;
  for (const LaneGeometry& lane : lanes) {
    for (std::size_t i = 0; i < lane.shape.size(); ++i) {
      points.push_back(lane.shape[i]);
      if (i + 1 == lane.shape.size()) break;
      const Vec3 d = lane.shape[i + 1] - lane.shape[i];
      const int n = static_cast<int>(std::ceil(d.norm() / spacing_m));
      for (int k = 1; k < n; ++k) points.push_back(lane.shape[i] + (double(k) / n) * d);
    }
  }
  return points;
}

}  // namespace statebench::sim
