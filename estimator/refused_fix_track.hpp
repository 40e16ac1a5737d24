// The GNSS fixes a Mahalanobis gate has refused in a row, and whether they follow one plausible
// path. When the gate has refused every fix for its reset time and the refused fixes agree with
// each other, the fixes are right and the estimate is wrong: the estimator is lost and starts
// over from the sensors (the factor graph's GnssFrontEnd and the EKF both use this test).
#pragma once

#include <cstddef>
#include <deque>

#include "estimator/gnss_enu.hpp"

namespace statebench::est {

class RefusedFixTrack {
 public:
  static constexpr std::size_t kMinFixes = 5;      // refused fixes that must agree
  static constexpr double kMaxSpeedMps = 70.0;     // fastest plausible motion between two

  // A fix the gate refused (the newest kMinFixes are kept).
  void Refused(const GnssPositionEnu& fix);
  // A fix was accepted: the run of refusals is over.
  void Clear() { fixes_.clear(); }
  // At least kMinFixes refused fixes, each reachable from the previous one at kMaxSpeedMps
  // within 4 sigma of their reported horizontal noise.
  bool Agrees() const;

 private:
  std::deque<GnssPositionEnu> fixes_;
};

}  // namespace statebench::est
