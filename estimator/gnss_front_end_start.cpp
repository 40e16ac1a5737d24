// GnssFrontEnd at the start (gnss_front_end.hpp): a start made of a receiver's fixes carries
// that receiver's slow error.
//
// A GNSS start (static average, moving chord fit) measures the antenna positions, each the
// position plus the receiver's slowly varying error e plus white noise; its fit removes the white
// noise, not e, which is nearly the same over the start's few seconds. So the start's position
// p0 is really a measurement of p0 + e0, its error -(e0 + the fit's), and e0 is the very state
// the smoother estimates with a stationary prior. Given as a prior on p0 alone, independent of
// e0's prior, the start would count the same slow error twice: the smoother would believe p0
// known apart from e0 and the position's covariance would lose e's variance from then on,
// wherever nothing else tells position from slow error (a full batch, which carries the start's
// prior through the whole run: its position ANEES 5.2 for 3 on the synthetic drive of
// FactorGraphBatch.ASlowReceiverError*, 3.3 with the start as below).
//
// Instead the start is given as what it is: the smoother's first state gets the start's prior
// with the position released (InitialState::SmootherPrior: its variance raised by 100 m, leaving
// its correlations with the other states near 0), and the start's position and covariance become
// a fix on the first state's IMU position plus the error states (as any fix of the receiver:
// gnss_error_state_factor.hpp). The joint of (p0, e0) is then exact: p0 + e0 as the start
// measured it, e0 as its prior says, p0's variance theirs summed. What is lost: the start's
// correlations between the position and the velocity or attitude (a moving start's chord fit
// ties them), which the first fixes restore within the window.
//
// Only for a setup with one GNSS antenna whose slow error is estimated: with two (a dual-antenna
// start averages both, each antenna with its own error states) the start's error would be a
// mixture; those keep the plain prior.
#include "estimator/gnss_front_end.hpp"

namespace statebench::est {

GnssFrontEnd::SlowError GnssFrontEnd::SlowErrorOf(const GnssAntenna& antenna) const {
  const MeasurementGateOptions& g = options_.gnss;
  if (antenna.DescribesCorrelatedError()) {
    return {Vec3(antenna.correlated_error_sigma_m, antenna.correlated_error_sigma_m,
                 antenna.correlated_error_vertical_sigma_m),
            antenna.correlated_error_tau_s};
  }
  return {Vec3(g.correlated_error_sigma_m, g.correlated_error_sigma_m,
               g.correlated_error_vertical_sigma_m),
          g.correlated_error_tau_s};
}

const GnssAntenna* GnssFrontEnd::StartErrorAntenna() const {
  if (setup_.antennas.size() != 1) return nullptr;
  const GnssAntenna& antenna = setup_.antennas.front();
  return options_.gnss.EstimatesCorrelatedErrorOf(antenna) ? &antenna : nullptr;
}

void GnssFrontEnd::RefineInitialState(const ImuSample& /*sample*/, InitialState* init) const {
  if (init->local_frame) return;  // not made of fixes
  const GnssAntenna* antenna = StartErrorAntenna();
  if (antenna == nullptr) return;
  init->position_slow_error = SlowErrorOf(*antenna).sigma.cwiseAbs2().asDiagonal();
}

void GnssFrontEnd::AddStartAsFix(const InitialState& init) {
  if (init.position_slow_error.isZero(0.0)) return;
  const GnssAntenna* antenna = StartErrorAntenna();
  if (antenna == nullptr) return;
  GnssPositionEnu start;
  start.header.sensor_id = antenna->id;
  start.header.stamp_ns = init.state.t_ns;
  start.p_enu = init.state.p_world;
  start.covariance = init.covariance.block<3, 3>(kPositionIndex, kPositionIndex);
  ctx_.smoother.AddGnss(start, Vec3::Zero(), std::nullopt, ErrorStateOf(antenna->id));
}

}  // namespace statebench::est
