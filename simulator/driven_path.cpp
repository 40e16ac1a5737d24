#include "simulator/driven_path.hpp"

#include <algorithm>
#include <stdexcept>

namespace statebench::sim {
namespace {

constexpr double kSamePointM = 1e-6;

}  // namespace

void DrivenPath::AppendLane(const std::string& lane_id, const std::vector<Vec3>& shape,
                            double lane_length_m) {
  if (shape.size() < 2 || !(lane_length_m > 0.0)) {
    throw std::invalid_argument("lane '" + lane_id + "' has no usable shape or length");
  }
  DrivenLane lane;
  lane.lane_id = lane_id;
  lane.lane_length_m = lane_length_m;
  for (std::size_t i = 0; i < shape.size(); ++i) {
    if (!points_.empty() && (shape[i] - points_.back()).norm() <= kSamePointM) {
      if (i == 0) lane.s_begin_m = s_.back();
      continue;
    }
    s_.push_back(points_.empty() ? 0.0 : s_.back() + (shape[i] - points_.back()).norm());
    points_.push_back(shape[i]);
    if (i == 0) lane.s_begin_m = s_.back();
  }
  lane.s_end_m = s_.back();
  lanes_.push_back(lane);
}

DrivenPath DrivenPath::Restore(std::vector<Vec3> points, std::vector<double> arc_lengths,
                               std::vector<DrivenLane> lanes) {
  if (points.size() != arc_lengths.size()) {
    throw std::invalid_argument("DrivenPath::Restore: points and arc lengths differ in number");
  }
  DrivenPath path;
  path.points_ = std::move(points);
  path.s_ = std::move(arc_lengths);
  path.lanes_ = std::move(lanes);
  return path;
}

Vec3 DrivenPath::PointAt(double s_m) const {
  if (points_.empty()) throw std::logic_error("DrivenPath::PointAt on an empty path");
  if (s_m <= 0.0) return points_.front();
  if (s_m >= s_.back()) return points_.back();
  const auto it = std::upper_bound(s_.begin(), s_.end(), s_m);
  const std::size_t i = static_cast<std::size_t>(it - s_.begin());  // s_[i-1] <= s < s_[i]
  const double f = (s_m - s_[i - 1]) / (s_[i] - s_[i - 1]);
  return points_[i - 1] + f * (points_[i] - points_[i - 1]);
}

}  // namespace statebench::sim
