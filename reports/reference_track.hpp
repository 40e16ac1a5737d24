// The reference trajectory of one frame (e.g. the IMU mount) built from truth samples as they
// come, with geodesic interpolation at any stamp it holds. What no estimate will ask for any more
// is dropped (DropBefore), so a long run keeps seconds of truth, not hours.
#pragma once

#include <cstddef>
#include <optional>
#include <vector>

#include "core/se3.hpp"
#include "core/truth.hpp"
#include "reports/trajectory_metrics.hpp"

namespace statebench::reports {

class ReferenceTrack {
 public:
  explicit ReferenceTrack(const SE3& T_body_frame) : T_body_frame_(T_body_frame) {}

  // Appends the frame's state at the sample (stamps increasing; a stamp not after the newest is
  // ignored) with the distance the frame has travelled since the first sample.
  void Add(const TruthSample& sample);

  // The reference at t_ns; nullopt when t_ns is outside the samples held.
  std::optional<ReferenceState> At(TimeNs t_ns) const;

  bool empty() const { return oldest_ == states_.size(); }
  std::size_t size() const { return states_.size() - oldest_; }
  TimeNs oldest_ns() const { return states_[oldest_].t_ns; }
  TimeNs newest_ns() const { return states_.back().t_ns; }

  // Forgets the samples before t_ns but the last one at or before it (interpolation needs it).
  void DropBefore(TimeNs t_ns);

 private:
  SE3 T_body_frame_;
  // The states held are states_[oldest_..]. Dropping only moves oldest_; the dropped front is
  // erased when the vector is full and it is at least half of it, so a long run reuses one
  // allocation (a deque allocated a node for nearly every state: ReferenceState is large).
  std::vector<ReferenceState> states_;
  std::size_t oldest_ = 0;
};

}  // namespace statebench::reports
