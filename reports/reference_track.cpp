#include "reports/reference_track.hpp"

#include <algorithm>

namespace statebench::reports {

void ReferenceTrack::Add(const TruthSample& sample) {
  if (!states_.empty() && sample.t_ns <= states_.back().t_ns) return;
  states_.push_back(ReferenceAt(sample, T_body_frame_, states_.empty() ? nullptr : &states_.back()));
}

std::optional<ReferenceState> ReferenceTrack::At(TimeNs t_ns) const {
  if (states_.empty() || t_ns < states_.front().t_ns || t_ns > states_.back().t_ns) {
    return std::nullopt;
  }
  const auto it = std::lower_bound(states_.begin(), states_.end(), t_ns,
                                   [](const ReferenceState& r, TimeNs t) { return r.t_ns < t; });
  if (it->t_ns == t_ns) return *it;
  return Interpolate(*(it - 1), *it, t_ns);
}

void ReferenceTrack::DropBefore(TimeNs t_ns) {
  while (states_.size() > 1 && states_[1].t_ns <= t_ns) states_.pop_front();
}

}  // namespace statebench::reports
