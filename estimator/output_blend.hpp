// Continuity of the IMU-rate output across solves (FactorGraphOptions::output_blend).
//
// Between solves the output is the newest solved state (the anchor) carried through the IMU
// samples (imu_rate_output.hpp). A solve moves the anchor: its state carried to the newest
// sample, x_new(t_s), differs from what the old anchor gave there, x_out(t_s), and an output
// switched to it at once would jump by the whole correction between two 100 Hz samples (on a
// real car's log p99 0.24-0.34 m). Instead the output keeps the offset and ramps it out:
//
//   d = x_out(t_s) [-] x_new(t_s)                                 at the solve, t_s
//   x_out(t) = x_best(t) [+] w(t) d,   w(t) = max(0, 1 - (t - t_s) / T)   for t >= t_s
//   T = min(max_s, max(|d_p| / position_rate, |d_theta| / rotation_rate))
//   T_p = max(T, |d_p| / max_position_rate)          (the position's own w(t) ramps over T_p)
//
// with x_best(t) the newest anchor carried to t, [+]/[-] in the core/state.hpp error ordering on
// rotation (right perturbation), position and velocity (the biases are the anchor's). At t_s the
// output is x_out(t_s), unchanged, so the output moves by its own motion there; afterwards the
// correction comes in at position_rate (m/s) and rotation_rate (rad/s), i.e. at most
// position_rate x dt per sample, except that no correction takes longer than max_s (a large
// one, e.g. at the end of a GNSS outage, then comes in over max_s) unless its position would then
// come in faster than max_position_rate: a position correction of tens of metres (a drifted GNSS
// outage whose error a turn or a stop reveals) slides in at max_position_rate, never more than
// max_position_rate x dt per sample, instead of 0.1-0.4 m per sample over max_s. Rotation and
// velocity still come in within T (a velocity offset kept over T_p would show a stopped vehicle
// moving). That bound costs accuracy only there: the output's position stays off by the part
// still ramping out (for a correction D, T_p - T = D / max_position_rate - max_s more seconds).
// The routine corrections of
// each solve (centimetres) are in within a few samples, so the output lags the best estimate
// by little; a solve that lands while an offset is still ramping out measures its own offset
// from the output shown, so nothing is lost or counted twice.
//
// Why a rate and not a fixed blend time: an exponential blend with time constant tau keeps an
// offset of ~ c tau / solve_interval behind a stream of corrections c in one direction (an IMU
// prediction that drifts between solves). Either way the output lags the corrections of the
// first seconds after a start, while the estimate converges from its first guess by metres
// (docs/estimator-config.md, "Continuous output").
//
// Covariance: the output's error is the best estimate's error plus the known offset,
// e_out = e_best + b with b = w(t) d (w_p(t) on the position), so its second moment is
// P_best + b b^T, which is what the output reports. If P_best is consistent, E[e_out^T (P_best + b b^T)^-1 e_out] is still the
// dimension: the blend leaves the expected NEES as it was, and the inflation is exactly the
// rank-one square of the offset still shown (zero once it is ramped out).
#pragma once

#include <cstdint>
#include <optional>

#include "core/eigen_types.hpp"
#include "core/state.hpp"
#include "estimator/imu_propagation.hpp"

namespace statebench::est {

// On by default: a correction comes in at the rates below within 1 s, or at 3 m/s when it is
// larger than 3 m, except in the first 10 s after a start, where it takes at most 0.1 s
// (measured on setup 2: blending the start's metre-sized corrections over 1 s costs accuracy;
// docs/estimator-config.md, "Continuous output").
struct OutputBlendOptions {
  double max_s = 1.0;               // the longest a correction takes; 0: the output jumps
  double position_rate_mps = 1.0;   // 1 cm per 100 Hz sample
  double rotation_rate_radps = 0.1;  // 1 mrad per 100 Hz sample
  // A position correction never comes in faster than this, even if it then takes longer than
  // max_s (3 cm per 100 Hz sample: with the few centimetres of the output's own motion error in
  // a GNSS outage, under issue 14's 5 cm step). 0: no bound beyond max_s. Not applied in the
  // start period below.
  double max_position_rate_mps = 3.0;
  // For this long after a (re)start the estimate converges from its first guess by metres, and
  // an output that lags those corrections is less accurate: a correction then takes at most
  // start_max_s (0: it jumps in).
  double after_start_s = 10.0;
  double start_max_s = 0.1;
};

class OutputBlend {
 public:
  explicit OutputBlend(const OutputBlendOptions& options) : options_(options) {}

  // A solve landed: `shown` is what the output was at t_s = best.t_ns with the old anchor (after
  // Apply), `best` the new anchor carried to t_s.
  void Rebase(const NavState& shown, const NavState& best);
  // No output to be continuous with (a first state, a restart, a change of frame) at t_ns:
  // corrections jump in until after_start_s later.
  void Start(TimeNs t_ns) {
    offset_.reset();
    start_ns_ = t_ns;
  }
  void Reset() { offset_.reset(); }

  // The output at best.t_ns: the best estimate there with the offset still shown and its
  // covariance widened by it. Stamps before the last solve are returned as they are.
  PropagatedState Apply(const PropagatedState& best) const;

  // The offset [rotation, position, velocity] still shown at t_ns (zero without one).
  Vec9 OffsetAt(TimeNs t_ns) const;

 private:
  struct Offset {
    TimeNs t_ns = 0;
    TimeNs duration_ns = 0;           // T of rotation and velocity
    TimeNs position_duration_ns = 0;  // T of the position (>= duration_ns: max_position_rate)
    Vec9 d = Vec9::Zero();
  };
  OutputBlendOptions options_;
  std::optional<Offset> offset_;
  TimeNs start_ns_ = INT64_MIN;
};

}  // namespace statebench::est
