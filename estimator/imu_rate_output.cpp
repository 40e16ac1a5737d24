#include "estimator/imu_rate_output.hpp"

#include <algorithm>

namespace statebench::est {
namespace {

// Latest element with stamp <= t_ns, or end if none.
template <typename It, typename Stamp>
It LatestAtOrBefore(It begin, It end, TimeNs t_ns, Stamp stamp) {
  auto it =
      std::upper_bound(begin, end, t_ns, [&](TimeNs t, const auto& x) { return t < stamp(x); });
  return it == begin ? end : std::prev(it);
}

}  // namespace

void ImuRateOutput::AddImu(const ImuSample& sample) {
  imu_.push_back(sample);
  if (running_) running_->Integrate(sample);
  last_after_anchor_.reset();
}

ImuPreintegration ImuRateOutput::Preintegrate(const NavState& from, TimeNs t_ns) const {
  return ImuPreintegration::FromSamples(std::span<const ImuSample>(imu_), from.t_ns, t_ns, noise_,
                                        ImuBias{from.gyro_bias, from.accel_bias});
}

void ImuRateOutput::SetAnchor(const PropagatedState& anchor) {
  anchor_ = anchor;
  anchors_.push_back(anchor);
  running_ = Preintegrate(anchor.state, imu_.back().header.stamp_ns);
  cursor_.reset();
  last_after_anchor_.reset();
}

bool ImuRateOutput::IsSampleStamp(TimeNs t_ns) const {
  const auto it = std::lower_bound(
      imu_.begin(), imu_.end(), t_ns,
      [](const ImuSample& s, TimeNs t) { return s.header.stamp_ns < t; });
  return it != imu_.end() && it->header.stamp_ns == t_ns;
}

const ImuPreintegration& ImuRateOutput::FromAnchorTo(TimeNs t_ns,
                                                     const ImuPreintegration* shared) const {
  const NavState& anchor = anchor_->state;
  if (shared != nullptr && shared->end_ns() == t_ns &&
      shared->StartsAs(anchor.t_ns, noise_, ImuBias{anchor.gyro_bias, anchor.accel_bias}) &&
      shared->IntegratesSamplesOf(imu_)) {
    return *shared;
  }
  // Extending is the same arithmetic as integrating from the anchor only from a node that
  // FromSamples also makes: a sample stamp, or the anchor itself.
  const bool extendable = cursor_ && cursor_->end_ns() <= t_ns && IsSampleStamp(t_ns) &&
                          (cursor_->end_ns() == anchor.t_ns || IsSampleStamp(cursor_->end_ns()));
  if (!extendable) {
    cursor_ = Preintegrate(anchor, t_ns);
    return *cursor_;
  }
  auto it = std::upper_bound(imu_.begin(), imu_.end(), cursor_->end_ns(),
                             [](TimeNs t, const ImuSample& s) { return t < s.header.stamp_ns; });
  for (; it != imu_.end() && it->header.stamp_ns <= t_ns; ++it) cursor_->Integrate(*it);
  return *cursor_;
}

NavState ImuRateOutput::Carry(const NavState& from, TimeNs t_ns) const {
  return t_ns == from.t_ns ? from : Preintegrate(from, t_ns).Predict(from);
}

template <typename Propagated>
std::optional<Propagated> ImuRateOutput::AfterAnchorWith(
    TimeNs t_ns, const ImuPreintegration* shared,
    Propagated (*propagate)(const NavState&, const Mat15&, const ImuPreintegration&)) const {
  if (!anchor_ || t_ns < anchor_->state.t_ns || t_ns > imu_.back().header.stamp_ns) {
    return std::nullopt;
  }
  if (t_ns == running_->end_ns()) return propagate(anchor_->state, anchor_->covariance, *running_);
  return propagate(anchor_->state, anchor_->covariance, FromAnchorTo(t_ns, shared));
}

std::optional<PropagatedState> ImuRateOutput::AfterAnchor(TimeNs t_ns,
                                                          const ImuPreintegration* shared) const {
  if (last_after_anchor_ && last_after_anchor_->state.t_ns == t_ns) return last_after_anchor_;
  last_after_anchor_ = AfterAnchorWith(t_ns, shared, &Propagate);
  return last_after_anchor_;
}

std::optional<PropagatedVelocity> ImuRateOutput::VelocityAfterAnchor(
    TimeNs t_ns, const ImuPreintegration* shared) const {
  return AfterAnchorWith(t_ns, shared, &PropagateVelocity);
}

std::optional<NavState> ImuRateOutput::MeanAfterAnchor(TimeNs t_ns,
                                                      const ImuPreintegration* shared) const {
  if (!anchor_ || t_ns < anchor_->state.t_ns || t_ns > imu_.back().header.stamp_ns) {
    return std::nullopt;
  }
  // Propagate's mean: the anchor itself over an empty interval, else the prediction.
  const ImuPreintegration& pim =
      t_ns == running_->end_ns() ? *running_ : FromAnchorTo(t_ns, shared);
  return pim.empty() ? anchor_->state : pim.Predict(anchor_->state);
}

template <typename Propagated>
std::optional<Propagated> ImuRateOutput::InWindowWith(
    TimeNs t_ns, std::span<const NavState> window,
    Propagated (*propagate)(const NavState&, const Mat15&, const ImuPreintegration&)) const {
  if (anchors_.empty() || imu_.empty() || t_ns < imu_.front().header.stamp_ns) return std::nullopt;
  const auto from = LatestAtOrBefore(window.begin(), window.end(), t_ns,
                                     [](const NavState& s) { return s.t_ns; });
  if (from == window.end()) return std::nullopt;
  auto cov = LatestAtOrBefore(anchors_.begin(), anchors_.end(), t_ns,
                              [](const PropagatedState& s) { return s.state.t_ns; });
  // Before the first anchor held, its covariance as it is (propagated over an empty interval).
  Propagated out =
      cov == anchors_.end()
          ? propagate(anchors_.front().state, anchors_.front().covariance,
                      ImuPreintegration(noise_, ImuBias{}))
          : propagate(cov->state, cov->covariance, Preintegrate(cov->state, t_ns));
  out.state = Carry(*from, t_ns);
  return out;
}

std::optional<PropagatedState> ImuRateOutput::InWindow(TimeNs t_ns,
                                                       std::span<const NavState> window) const {
  return InWindowWith(t_ns, window, &Propagate);
}

std::optional<PropagatedVelocity> ImuRateOutput::VelocityInWindow(
    TimeNs t_ns, std::span<const NavState> window) const {
  return InWindowWith(t_ns, window, &PropagateVelocity);
}

std::optional<NavState> ImuRateOutput::MeanAt(TimeNs t_ns,
                                              std::span<const NavState> window) const {
  if (!anchor_ || imu_.empty() || t_ns > imu_.back().header.stamp_ns ||
      t_ns < imu_.front().header.stamp_ns) {
    return std::nullopt;
  }
  if (t_ns >= anchor_->state.t_ns) return Carry(anchor_->state, t_ns);
  if (anchors_.empty()) return std::nullopt;
  const auto from = LatestAtOrBefore(window.begin(), window.end(), t_ns,
                                     [](const NavState& s) { return s.t_ns; });
  if (from == window.end()) return std::nullopt;
  return Carry(*from, t_ns);
}

void ImuRateOutput::Forget(TimeNs keep_ns) {
  while (anchors_.size() > 1 && anchors_[1].state.t_ns <= keep_ns) anchors_.pop_front();
  if (!anchors_.empty()) keep_ns = std::min(keep_ns, anchors_.front().state.t_ns);
  // Erase in chunks: the vector must stay contiguous, erasing one sample at a time is O(n).
  if (imu_.size() > 64 && imu_[32].header.stamp_ns < keep_ns) {
    std::erase_if(imu_, [&](const ImuSample& s) { return s.header.stamp_ns < keep_ns; });
  }
}

}  // namespace statebench::est
