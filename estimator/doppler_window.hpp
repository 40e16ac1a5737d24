// The receiver's recent horizontal Doppler velocities, a speed reading for the standstill tests
// (zero_velocity_evidence.hpp) that does not depend on the estimate: every reading counts,
// gated or not, so a wrong estimate cannot lock the test out. Shared by the factor graph's GNSS
// front end and the EKF.
#pragma once

#include <deque>
#include <optional>

#include "core/eigen_types.hpp"
#include "core/time.hpp"

namespace statebench::est {

// The mean horizontal (east, north) velocity of the readings in a span and the sigma of that
// mean per axis from the reported ones, sqrt(sum sigma_i^2) / n.
struct DopplerMean {
  Vec2 v_enu = Vec2::Zero();
  Vec2 sigma_enu = Vec2::Zero();
};

class DopplerWindow {
 public:
  static constexpr double kKeepS = 5.0;  // readings kept

  // Readings in stamp order.
  void Add(TimeNs t_ns, const Vec2& v_enu, const Vec2& sigma_enu) {
    readings_.push_back({t_ns, v_enu, sigma_enu});
    while (readings_.front().t_ns < t_ns - FromSeconds(kKeepS)) readings_.pop_front();
  }
  void Clear() { readings_.clear(); }

  // Of the readings stamped in [from_ns, to_ns]; nullopt without one.
  std::optional<DopplerMean> Mean(TimeNs from_ns, TimeNs to_ns) const {
    DopplerMean mean;
    Vec2 variance_sum = Vec2::Zero();
    int n = 0;
    for (const Reading& r : readings_) {
      if (r.t_ns < from_ns || r.t_ns > to_ns) continue;
      mean.v_enu += r.v_enu;
      variance_sum += r.sigma_enu.cwiseAbs2();
      ++n;
    }
    if (n == 0) return std::nullopt;
    mean.v_enu /= n;
    mean.sigma_enu = variance_sum.cwiseSqrt() / n;
    return mean;
  }

 private:
  struct Reading {
    TimeNs t_ns = 0;
    Vec2 v_enu, sigma_enu;
  };
  std::deque<Reading> readings_;  // oldest first
};

}  // namespace statebench::est
