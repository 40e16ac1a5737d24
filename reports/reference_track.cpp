#include "reports/reference_track.hpp"

#include <algorithm>

namespace statebench::reports {

void ReferenceTrack::Add(const TruthSample& sample) {
  if (!empty() && sample.t_ns <= states_.back().t_ns) return;
  // Full: reclaim the dropped front when it is at least half of the storage (then the next
  // reclaim is at least half a storage of adds away, so each state is moved O(1) times),
  // else let the vector grow.
  if (states_.size() == states_.capacity() && oldest_ > 0 && 2 * oldest_ >= states_.size()) {
    states_.erase(states_.begin(), states_.begin() + static_cast<std::ptrdiff_t>(oldest_));
    oldest_ = 0;
  }
  const ReferenceState* previous = empty() ? nullptr : &states_.back();
  states_.push_back(ReferenceAt(sample, T_body_frame_, previous));
}

std::optional<ReferenceState> ReferenceTrack::At(TimeNs t_ns) const {
  if (empty() || t_ns < oldest_ns() || t_ns > newest_ns()) return std::nullopt;
  const auto first = states_.begin() + static_cast<std::ptrdiff_t>(oldest_);
  const auto it = std::lower_bound(first, states_.end(), t_ns,
                                   [](const ReferenceState& r, TimeNs t) { return r.t_ns < t; });
  if (it->t_ns == t_ns) return *it;
  return Interpolate(*(it - 1), *it, t_ns);
}

void ReferenceTrack::DropBefore(TimeNs t_ns) {
  while (size() > 1 && states_[oldest_ + 1].t_ns <= t_ns) ++oldest_;
}

}  // namespace statebench::reports
