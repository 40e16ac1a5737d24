#include "reports/trajectory_metrics.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>

#include "reports/trajectory_scorer.hpp"

namespace statebench::reports {

ReferenceState ReferenceAt(const TruthSample& sample, const SE3& T_body_frame,
                           const ReferenceState* previous) {
  const FrameKinematics k = sample.body.AtMount(T_body_frame);
  ReferenceState r;
  r.t_ns = sample.t_ns;
  r.T_world_frame = k.T_world_frame;
  r.v_world = k.v_world;
  r.distance_m = previous == nullptr ? 0.0
                                     : previous->distance_m + (r.T_world_frame.translation() -
                                                               previous->T_world_frame.translation())
                                                                  .norm();
  return r;
}

std::vector<ReferenceState> ReferenceFromTruth(const std::vector<TruthSample>& truth,
                                               const SE3& T_body_frame) {
  std::vector<ReferenceState> out;
  out.reserve(truth.size());
  for (const TruthSample& s : truth) {
    out.push_back(ReferenceAt(s, T_body_frame, out.empty() ? nullptr : &out.back()));
  }
  return out;
}

ErrorStatistics ComputeStatistics(std::vector<double> errors) {
  ErrorStatistics s;
  s.count = errors.size();
  if (errors.empty()) return s;
  const double n = static_cast<double>(errors.size());
  double sum_sq = 0.0;
  for (const double v : errors) sum_sq += v * v;
  s.rmse = std::sqrt(sum_sq / n);
  s.mean = std::accumulate(errors.begin(), errors.end(), 0.0) / n;
  double var = 0.0;
  for (const double e : errors) var += (e - s.mean) * (e - s.mean);
  s.std = std::sqrt(var / n);
  s.max = *std::max_element(errors.begin(), errors.end());
  std::sort(errors.begin(), errors.end());
  const std::size_t m = errors.size() / 2;
  s.median = errors.size() % 2 ? errors[m] : 0.5 * (errors[m - 1] + errors[m]);
  return s;
}

std::optional<ReferenceState> InterpolateReference(const std::vector<ReferenceState>& reference,
                                                   TimeNs t_ns) {
  if (reference.empty() || t_ns < reference.front().t_ns || t_ns > reference.back().t_ns) {
    return std::nullopt;
  }
  const auto it = std::lower_bound(reference.begin(), reference.end(), t_ns,
                                   [](const ReferenceState& r, TimeNs t) { return r.t_ns < t; });
  if (it->t_ns == t_ns) return *it;
  return Interpolate(*(it - 1), *it, t_ns);
}

ReferenceState Interpolate(const ReferenceState& a, const ReferenceState& b, TimeNs t_ns) {
  const double alpha = static_cast<double>(t_ns - a.t_ns) / static_cast<double>(b.t_ns - a.t_ns);
  ReferenceState r;
  r.t_ns = t_ns;
  r.T_world_frame = SE3::Interpolate(a.T_world_frame, b.T_world_frame, alpha);
  r.v_world = (1.0 - alpha) * a.v_world + alpha * b.v_world;
  r.distance_m = (1.0 - alpha) * a.distance_m + alpha * b.distance_m;
  return r;
}

TrajectoryMetrics ComputeTrajectoryMetrics(const std::vector<StateEstimate>& estimates,
                                           const std::vector<ReferenceState>& reference,
                                           const MetricsOptions& options) {
  TrajectoryScorer scorer(options);
  for (const StateEstimate& e : estimates) {
    if (const auto r = InterpolateReference(reference, e.state.t_ns)) {
      scorer.Add(e, *r);
    } else {
      scorer.Skip();
    }
  }
  return scorer.Finish();
}

}  // namespace statebench::reports
