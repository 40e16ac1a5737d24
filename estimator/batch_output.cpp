#include "estimator/batch_output.hpp"

#include <algorithm>
#include <span>

namespace statebench::est {

void BatchOutput::Add(SmootherBatch batch, bool local_frame) {
  if (batch.states.empty()) return;
  segments_.push_back({std::move(batch), local_frame});
}

std::optional<BatchOutput::At> BatchOutput::StateAt(TimeNs t_ns) const {
  // The latest segment that starts at or before t_ns.
  const auto seg_it = std::upper_bound(
      segments_.begin(), segments_.end(), t_ns,
      [](TimeNs t, const Segment& s) { return t < s.batch.states.front().t_ns; });
  if (seg_it == segments_.begin()) return std::nullopt;
  const Segment& seg = *std::prev(seg_it);
  const SmootherBatch& b = seg.batch;
  if (b.covariances.size() != b.states.size() || b.imu.empty() ||
      t_ns > b.imu.back().header.stamp_ns) {
    return std::nullopt;
  }
  const auto state_it =
      std::upper_bound(b.states.begin(), b.states.end(), t_ns,
                       [](TimeNs t, const NavState& s) { return t < s.t_ns; });
  const std::size_t k = static_cast<std::size_t>(std::prev(state_it) - b.states.begin());
  const NavState& x = b.states[k];
  At out;
  out.local_frame = seg.local_frame;
  if (x.t_ns == t_ns) {
    out.state = PropagatedState{x, b.covariances[k]};
    return out;
  }
  const ImuPreintegration pim =
      ImuPreintegration::FromSamples(std::span<const ImuSample>(b.imu), x.t_ns, t_ns, noise_,
                                     ImuBias{x.gyro_bias, x.accel_bias});
  out.state = Propagate(x, b.covariances[k], pim);
  return out;
}

}  // namespace statebench::est
