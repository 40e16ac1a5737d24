// Where a local frame lies in ENU. A setup with a GNSS antenna whose factor graph started in a
// local frame (state_initializer.hpp: the yaw is not observable before the vehicle drove)
// collects, for each fix, the antenna's position in the local frame (the estimate at the fix's
// stamp through the lever arm) and the fix in ENU. Both frames have z up (the local frame's tilt
// is observed from gravity), so they differ by a rotation about the vertical and a translation:
//   p_enu = Rz(psi) p_local + t.
// Horizontal part, closed form (2D Procrustes): with the centroids a (local) and b (ENU) and the
// centred points d_i = p_local_i - a, e_i = p_enu_i - b (horizontal),
//   psi = atan2(sum d_i x e_i, sum d_i . e_i),  t_xy = b - R(psi) a;
// vertical: t_z = mean(z_enu - z_local).
// Uncertainty per fix and horizontal axis: sigma^2 = max(the fixes' mean reported horizontal
// variance, the fit's residual variance over its 2N - 3 degrees of freedom): a receiver that
// reports too small a covariance shows it in the residuals. Then
//   sigma_psi^2 = sigma^2 / sum |d_i|^2,  sigma_b^2 = sigma^2 / N per axis (at the centroid),
// and vertically the larger of the mean reported vertical variance and the residuals' over N.
// The local track's own drift over the fixes' span (wheel odometry: under 1 % of the distance)
// is not modelled.
#pragma once

#include <deque>
#include <optional>

#include "core/eigen_types.hpp"
#include "core/time.hpp"
#include "estimator/imu_propagation.hpp"

namespace statebench::est {

class EnuAlignment {
 public:
  struct Result {
    double yaw_rad = 0.0;  // psi
    Vec3 translation = Vec3::Zero();
    double yaw_sigma_rad = 0.0;
    double sigma_h_m = 0.0;              // per fix and axis, as used (reported or from residuals)
    double residual_sigma_h_m = 0.0;     // from the residuals alone
    Vec3 centroid_enu = Vec3::Zero();    // b (and the mean height)
    Vec3 centroid_sigma = Vec3::Zero();  // of b per axis (x, y) and of t_z
    int fixes = 0;
    double span_m = 0.0;  // largest distance of a fix from the centroid, local frame

    // The state moved into ENU, its covariance with the alignment's uncertainty added (yaw about
    // the vertical, its sigma at least min_yaw_sigma_rad; the centroid's position; first order).
    PropagatedState Apply(const PropagatedState& local, double min_yaw_sigma_rad = 0.0) const;
  };

  // Fixes older than this before the newest one are forgotten (the local track drifts).
  static constexpr double kHistoryS = 120.0;
  static constexpr int kMinFixes = 10;

  // One fix: the antenna's position in the local frame, the fix in ENU with its covariance.
  void Add(TimeNs t_ns, const Vec3& p_local, const Vec3& p_enu, const Mat3& covariance_enu);
  void Clear() { pairs_.clear(); }
  int size() const { return static_cast<int>(pairs_.size()); }
  // The alignment of the fixes held; nullopt below kMinFixes or without horizontal spread.
  std::optional<Result> Solve() const;

 private:
  struct Pair {
    TimeNs t_ns = 0;
    Vec3 p_local = Vec3::Zero(), p_enu = Vec3::Zero();
    double variance_h = 0.0, variance_v = 0.0;
  };
  std::deque<Pair> pairs_;
};

}  // namespace statebench::est
