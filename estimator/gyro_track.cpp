#include "estimator/gyro_track.hpp"

#include <algorithm>

#include "core/so3.hpp"

namespace statebench::est {

void GyroTrack::Add(TimeNs t_ns, const Vec3& gyro_radps) {
  if (!samples_.empty() && t_ns <= samples_.back().t_ns) return;
  samples_.push_back({t_ns, gyro_radps});
}

std::optional<Quat> GyroTrack::Rotation(TimeNs t0, TimeNs t1) const {
  if (samples_.empty() || t0 > t1 || t0 < samples_.front().t_ns || t1 > samples_.back().t_ns) {
    return std::nullopt;
  }
  // The sample at or before t0, then each interval up to t1.
  auto it = std::upper_bound(samples_.begin(), samples_.end(), t0,
                             [](TimeNs t, const Sample& s) { return t < s.t_ns; });
  --it;
  Quat q = Quat::Identity();
  TimeNs t = t0;
  while (t < t1) {
    const auto next = std::next(it);
    const TimeNs until = next == samples_.end() ? t1 : std::min(t1, next->t_ns);
    q = q * so3::Exp(Vec3(it->gyro * ToSeconds(until - t)));
    t = until;
    if (next == samples_.end()) break;
    it = next;
  }
  return q.normalized();
}

void GyroTrack::DropBefore(TimeNs t_ns) {
  // Keep the sample at or before t_ns: it holds the rate from t_ns on.
  while (samples_.size() > 1 && samples_[1].t_ns <= t_ns) samples_.pop_front();
}

}  // namespace statebench::est
