// The full-batch smoother's Gauss-Markov globals (a GNSS receiver's slowly varying error).
//
// The fixed-lag window holds one value of such a process and carries it through its
// Gauss-Markov step each time a state leaves (sliding_window_globals.cpp: the value is the
// process at the window's oldest state; the window spans about a second, much less than the
// correlation time). Every factor that ever used it references that one value, so a batch over
// the whole log, solved on those factors as they are, would make the process a constant over
// minutes: the fixes' slow error averaged as if it were a bias, the covariance as small as that
// average's.
//
// GaussMarkovSegments gives the batch the process instead: the chain's states are cut into
// segments (SegmentLength: a tenth of the correlation time, longer for a very long run), each
// with its own value of the process, the factors anchored in a segment are rewritten to use it,
// and consecutive values are tied by the process's step
//   x_{s+1} = rho x_s + w,  rho = exp(-dt / tau),  w ~ N(0, sigma^2 (1 - rho^2)),
// dt being the time between the segments' first states (GaussMarkovTransition). The newest
// segment keeps the live value (the window's), so the batch leaves it solved as the window's.
// The process's initial prior (the factor that created it, anchored where it was created) moves
// with its anchor into the first segment. Piecewise constant within a segment: the process's
// spread about a segment's mean is about sigma sqrt(L / (3 tau)) at length L << tau, 0.18 sigma
// at L = tau / 10.
#pragma once

#include <ceres/sized_cost_function.h>

#include <deque>
#include <memory>
#include <vector>

#include "core/time.hpp"
#include "estimator/chain_system.hpp"

namespace statebench::est {

// r = (x_next - rho x) / sqrt(sigma^2 (1 - rho^2)) on two scalar blocks (x, x_next).
class GaussMarkovTransition final : public ceres::SizedCostFunction<1, 1, 1> {
 public:
  // Throws InputError unless sigma > 0 and 0 <= rho < 1.
  GaussMarkovTransition(double sigma, double rho);
  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override;

 private:
  double rho_;
  double inv_sigma_w_;
};

// One Gauss-Markov global of the window as the batch sees it.
struct GaussMarkovGlobal {
  double* value = nullptr;  // the live value (the window's)
  double sigma = 0.0;       // stationary standard deviation
  double tau_s = 0.0;       // correlation time
};

class GaussMarkovSegments {
 public:
  // Segment length for a process of correlation time tau_s over a chain spanning span_s: a tenth
  // of tau, longer when the chain would otherwise need more than max_segments per process (each
  // segment is a global of the bordered solve, whose cost grows with their number squared).
  static double SegmentLength(double tau_s, double span_s, int max_segments);

  // Rewrites `chain` (times[k] is state k's stamp, oldest first) for each process of `processes`
  // whose factors it holds: the factors anchored in each segment but the newest use the
  // segment's value, the transitions are anchored at each segment's first state, and the new
  // values are appended to `globals` (which must already hold every process's live value). The
  // new values start at the process's mean, 0. The chain then points into this object: keep it
  // alive while the chain is used.
  GaussMarkovSegments(const std::vector<TimeNs>& times,
                      const std::vector<GaussMarkovGlobal>& processes, int max_segments,
                      std::vector<ChainState>* chain, std::vector<double*>* globals);

  GaussMarkovSegments(const GaussMarkovSegments&) = delete;
  GaussMarkovSegments& operator=(const GaussMarkovSegments&) = delete;

  // Segments per process of the constructor's list (0: its value is used by no factor of the
  // chain; 1: the chain is shorter than one segment and nothing was rewritten).
  const std::vector<int>& segments() const { return segments_; }

 private:
  std::vector<int> segments_;
  std::deque<double> values_;  // stable addresses
  std::deque<FactorRecord> records_;
  std::vector<std::unique_ptr<GaussMarkovTransition>> transitions_;
};

}  // namespace statebench::est
