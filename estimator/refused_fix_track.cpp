#include "estimator/refused_fix_track.hpp"

#include <cmath>

namespace statebench::est {

void RefusedFixTrack::Refused(const GnssPositionEnu& fix) {
  fixes_.push_back(fix);
  if (fixes_.size() > kMinFixes) fixes_.pop_front();
}

bool RefusedFixTrack::Agrees() const {
  if (fixes_.size() < kMinFixes) return false;
  for (std::size_t k = 1; k < fixes_.size(); ++k) {
    const GnssPositionEnu& a = fixes_[k - 1];
    const GnssPositionEnu& b = fixes_[k];
    const double dt = std::abs(ToSeconds(b.header.stamp_ns - a.header.stamp_ns));
    const double noise = std::sqrt(a.covariance(0, 0) + a.covariance(1, 1) +
                                   b.covariance(0, 0) + b.covariance(1, 1));
    if (!((b.p_enu - a.p_enu).head<2>().norm() <= kMaxSpeedMps * dt + 4.0 * noise)) return false;
  }
  return true;
}

}  // namespace statebench::est
