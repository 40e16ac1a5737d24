// The centre line the ego drove: the shapes of the lanes it traversed (internal junction lanes
// included), in order, concatenated into one 3D polyline with its arc length s (3D, metres).
//
// SUMO places a vehicle at lane position p (0..lane length) on the lane's shape at shape
// distance p * shape_length / lane_length (lane lengths of junction lanes and of edges with a
// custom length differ from their shape length). DrivenLane::ArcLength applies the same factor,
// so the front bumper SUMO reports lies on this polyline at s = ArcLength(p).
#pragma once

#include <string>
#include <vector>

#include "core/eigen_types.hpp"

namespace statebench::sim {

struct DrivenLane {
  std::string lane_id;
  double s_begin_m = 0.0;      // arc length of the lane's first shape point
  double s_end_m = 0.0;        // arc length of its last shape point
  double lane_length_m = 0.0;  // SUMO's lane length

  // Arc length of lane position `lane_pos_m`.
  double ArcLength(double lane_pos_m) const {
    return s_begin_m + lane_pos_m * (s_end_m - s_begin_m) / lane_length_m;
  }
  bool operator==(const DrivenLane&) const = default;
};

class DrivenPath {
 public:
  // Appends a traversed lane. Its first point is dropped when it repeats the current last point
  // (consecutive lanes share their junction point); zero-length segments are dropped.
  void AppendLane(const std::string& lane_id, const std::vector<Vec3>& shape, double lane_length_m);

  const std::vector<Vec3>& points() const { return points_; }
  const std::vector<double>& arc_lengths() const { return s_; }  // s of each point, s[0] = 0
  const std::vector<DrivenLane>& lanes() const { return lanes_; }
  double length_m() const { return s_.empty() ? 0.0 : s_.back(); }
  bool empty() const { return lanes_.empty(); }

  // A path from the parts another path returned (points, arc lengths, lanes), for the stage
  // cache (sumo_result_io.hpp). Throws std::invalid_argument when they do not fit together.
  static DrivenPath Restore(std::vector<Vec3> points, std::vector<double> arc_lengths,
                            std::vector<DrivenLane> lanes);

  // Point at arc length s (clamped to [0, length]).
  Vec3 PointAt(double s_m) const;

  bool operator==(const DrivenPath&) const = default;

 private:
  std::vector<Vec3> points_;
  std::vector<double> s_;
  std::vector<DrivenLane> lanes_;
};

}  // namespace statebench::sim
