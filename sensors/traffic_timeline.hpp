// Traffic boxes between SUMO steps. SUMO reports every vehicle once per step; a lidar column
// fires anywhere between two steps, so poses are interpolated:
//   - a vehicle in both frames k and k+1 moves linearly (centre, pitch) and along the shorter
//     arc (yaw) from frame k to frame k+1;
//   - a vehicle only in frame k stays at its frame-k pose until the midpoint of the step, one only
//     in frame k+1 appears at the midpoint at its frame-(k+1) pose;
//   - before the first frame and after the last the nearest frame is held.
#pragma once

#include <limits>
#include <string>
#include <vector>

#include "core/time.hpp"
#include "sensors/world_inputs.hpp"

namespace statebench::sensors {

// One vehicle over a time interval [t_begin_ns, t_end_ns): linear from box `a` at ta_ns to box
// `b` at tb_ns (a == b and ta == tb when held).
struct TrafficPiece {
  TimeNs t_begin_ns = std::numeric_limits<TimeNs>::min();
  TimeNs t_end_ns = std::numeric_limits<TimeNs>::max();
  TimeNs ta_ns = 0;
  TimeNs tb_ns = 0;
  TrafficBox a;
  TrafficBox b;

  TrafficBox At(TimeNs t_ns) const;
};

// The pieces of one vehicle, in time order.
struct TrafficMotion {
  std::string id;
  std::vector<TrafficPiece> pieces;

  // nullptr when the vehicle is absent at t_ns.
  const TrafficPiece* PieceAt(TimeNs t_ns) const;
};

class TrafficTimeline {
 public:
  TrafficTimeline() = default;
  // Frames must have strictly increasing times and unique ids per frame; throws InputError
  // naming the frame otherwise.
  explicit TrafficTimeline(std::vector<TrafficFrame> frames);

  bool empty() const { return frames_.empty(); }
  const std::vector<TrafficFrame>& frames() const { return frames_; }

  // Every vehicle present at t_ns with its interpolated pose, ordered by id.
  std::vector<TrafficBox> BoxesAt(TimeNs t_ns) const;

  // The motion of every vehicle present at some time in [t0_ns, t1_ns], ordered by id.
  std::vector<TrafficMotion> MotionsIn(TimeNs t0_ns, TimeNs t1_ns) const;

 private:
  std::vector<TrafficFrame> frames_;  // boxes sorted by id
};

}  // namespace statebench::sensors
