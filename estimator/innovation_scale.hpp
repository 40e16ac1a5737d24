// How much larger a sensor's errors are than the covariance it reports, from the consistency of
// its innovations across measurements (receivers often report a covariance 2-5x too small:
// shared/REFERENCE.md). For a consistent n-dimensional measurement the squared Mahalanobis
// distance of its innovation, d2 = r^T (H P H^T + s R)^-1 r, is chi-square(n) with median m_n.
// Each batch of kBatch measurements, all with the scale s in force, gives the scale it implies,
//   k = s median(d2) / m_n
// (exact when H P H^T is small against R; larger otherwise, which then errs on the safe side).
// Gated measurements count, their d2 clipped at the gate: a gate that fed back only what it kept
// would hide the excess, and clipping leaves the median as it is while fewer than half are
// beyond the gate. The new scale is k when k > kMinScale, else 1 (each batch decides afresh: no
// ratchet), at most kMaxScale. Below kMinScale nothing changes: a variance under-reported by
// less than 2x loses under 5 % of its fixes to a chi-square(3) gate at 16.27 (beyond 8.1: 4.4 %),
// and a consistent sensor (the median of 50 chi-square(3) samples has a relative sigma of 0.16,
// so 2 is 4.3 sigma away) keeps s = 1, its factors exactly what they were. A batch whose median
// is at the gate (most of it refused) says the estimate went wrong, not the sensor's covariance:
// it changes nothing (the gate's lost logic answers it). The median, not the mean, so that
// outliers (multipath) do not move it.
#pragma once

#include <vector>

namespace statebench::est {

class InnovationScale {
 public:
  static constexpr int kBatch = 50;
  static constexpr double kMinScale = 2.0;
  static constexpr double kMaxScale = 100.0;

  // dimension: of the innovation (3 for a GNSS position); gate_chi2: the gate's threshold.
  InnovationScale(int dimension, double gate_chi2);

  // The factor by which the reported covariance is multiplied.
  double scale() const { return scale_; }
  // One measurement's d2, computed with scale() times the reported covariance. Returns whether the
  // scale changed.
  bool Add(double mahalanobis_squared);
  void Reset();

 private:
  double expected_median_;
  double gate_chi2_;
  double scale_ = 1.0;
  std::vector<double> batch_;
};

}  // namespace statebench::est
