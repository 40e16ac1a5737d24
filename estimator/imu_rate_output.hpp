// The estimator's output at any stamp between smoother updates: the newest smoothed state (the
// anchor) and its covariance carried through the buffered raw IMU samples (imu_propagation.hpp).
//
// For the newest sample a running preintegration from the anchor is extended sample by sample,
// so the 100 Hz output costs one 15x15 propagation per sample. Stamps between the anchor and the
// newest sample (the front ends' predictions at released measurements, in increasing order) are
// served by a second preintegration from the anchor, the cursor, extended sample by sample as
// the running one is: the same integration steps as ImuPreintegration::FromSamples from the
// anchor, so the same bits, without integrating from the anchor again for every stamp. For stamps inside the smoother's
// window the caller passes the smoothed states: the mean is the latest smoothed state at or
// before the stamp carried to it; the covariance is that of the latest earlier anchor carried to
// the stamp (a filtered covariance: an upper bound of the smoothed one).
#pragma once

#include <deque>
#include <optional>
#include <span>
#include <vector>

#include "core/measurements.hpp"
#include "core/state.hpp"
#include "estimator/imu_noise.hpp"
#include "estimator/imu_preintegration.hpp"
#include "estimator/imu_propagation.hpp"

namespace statebench::est {

class ImuRateOutput {
 public:
  explicit ImuRateOutput(const ImuNoise& noise) : noise_(noise) {}
  // The noise of propagations from now on (imu_noise_monitor.hpp).
  void SetNoise(const ImuNoise& noise) {
    noise_ = noise;
    last_after_anchor_.reset();
  }

  // An accepted raw sample; stamps must increase.
  void AddImu(const ImuSample& sample);
  // After each update. The anchor's stamp must lie within the samples held.
  void SetAnchor(const PropagatedState& anchor);

  bool has_anchor() const { return anchor_.has_value(); }
  const std::vector<ImuSample>& samples() const { return imu_; }

  // Mean and covariance at t_ns in [anchor, newest sample]; nullopt outside.
  // `shared`, when given, is another preintegration of the same stream (the smoother's from its
  // newest state): used instead of integrating when it is the anchor's to t_ns from the very
  // samples held here (ImuPreintegration::IntegratesSamplesOf), bit for bit the same answer.
  std::optional<PropagatedState> AfterAnchor(TimeNs t_ns,
                                             const ImuPreintegration* shared = nullptr) const;
  // AfterAnchor's mean alone (the same bits; no covariance propagated).
  std::optional<NavState> MeanAfterAnchor(TimeNs t_ns,
                                          const ImuPreintegration* shared = nullptr) const;
  // At t_ns before the anchor, from the smoothed window states (oldest first); nullopt if t_ns
  // is before the first of them or the samples held.
  std::optional<PropagatedState> InWindow(TimeNs t_ns, std::span<const NavState> window) const;
  // AfterAnchor and InWindow with the velocity block of the covariance alone (the same bits;
  // PropagateVelocity).
  std::optional<PropagatedVelocity> VelocityAfterAnchor(
      TimeNs t_ns, const ImuPreintegration* shared = nullptr) const;
  std::optional<PropagatedVelocity> VelocityInWindow(TimeNs t_ns,
                                                     std::span<const NavState> window) const;
  // The mean alone, as AfterAnchor or else InWindow give it (no covariance propagated).
  std::optional<NavState> MeanAt(TimeNs t_ns, std::span<const NavState> window) const;
  // Mean of `from` carried to t_ns >= from.t_ns (biases kept).
  NavState Carry(const NavState& from, TimeNs t_ns) const;

  // Forgets what no stamp from keep_ns on needs (older anchors and samples).
  void Forget(TimeNs keep_ns);

 private:
  ImuPreintegration Preintegrate(const NavState& from, TimeNs t_ns) const;
  // AfterAnchor and InWindow with `propagate` (Propagate or PropagateVelocity).
  template <typename Propagated>
  std::optional<Propagated> AfterAnchorWith(TimeNs t_ns, const ImuPreintegration* shared,
                                            Propagated (*propagate)(const NavState&, const Mat15&,
                                                                    const ImuPreintegration&)) const;
  template <typename Propagated>
  std::optional<Propagated> InWindowWith(TimeNs t_ns, std::span<const NavState> window,
                                         Propagated (*propagate)(const NavState&, const Mat15&,
                                                                 const ImuPreintegration&)) const;
  // The preintegration from the anchor to t_ns, through the cursor when t_ns is a sample stamp.
  // `shared` instead when it is that one (AfterAnchor).
  const ImuPreintegration& FromAnchorTo(TimeNs t_ns, const ImuPreintegration* shared) const;
  bool IsSampleStamp(TimeNs t_ns) const;

  ImuNoise noise_;
  std::vector<ImuSample> imu_;                // contiguous for ImuPreintegration::FromSamples
  std::optional<PropagatedState> anchor_;     // newest state of the last update
  std::optional<ImuPreintegration> running_;  // anchor -> newest sample
  // anchor -> a sample stamp (or the anchor itself); reset by SetAnchor. The estimator's
  // queries are const: this cache is the only state they change.
  mutable std::optional<ImuPreintegration> cursor_;
  std::deque<PropagatedState> anchors_;       // earlier anchors, for stamps inside the window
  // AfterAnchor's last answer, until the next sample, anchor or noise: the estimator asks for
  // the newest sample twice after an update (MoveAnchor's blend, then the output).
  mutable std::optional<PropagatedState> last_after_anchor_;
};

}  // namespace statebench::est
