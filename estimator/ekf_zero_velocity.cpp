// The EKF's zero-velocity update without a speed input (ekf_filter_impl.hpp, UpdateZeroVelocity).
#include <cmath>
#include <optional>

#include "estimator/ekf_filter_impl.hpp"
#include "estimator/zero_velocity_evidence.hpp"

namespace statebench::est {

void EkfSingleTrackEstimator::Impl::UpdateZeroVelocity(TimeNs t_ns) {
  const ZeroVelocityOptions z;  // the factor graph's defaults
  if (has_speed_input || t_ns < next_zero_velocity_ns) return;
  const std::optional<ImuWindowStatistics> window = still_imu.Statistics(z);
  if (!window || !window->Quiet(z)) return;
  // Doppler only: without a speed input the filter's speed sigma grows without bound in a GNSS
  // outage, and "within 3 sigmas of zero" then holds while cruising (setup 3: one false update at
  // 6.9 m/s, 40 s into its outage, that moved its end error from 176 to 217 m).
  const std::optional<double> sigma = ZeroVelocitySigmaWithoutEncoder(
      z, doppler.Mean(t_ns - FromSeconds(z.doppler_window_s), t_ns), [] { return false; });
  if (!sigma) return;
  const double ax = (R_body_imu * window->mean_accel).x() - x[ekf::kBa];
  if (!(std::abs(ax) < z.max_acceleration_mps2)) return;
  next_zero_velocity_ns = t_ns + FromSeconds(1.0 / z.rate_hz);
  Eigen::Matrix<double, 2, kN> H = Eigen::Matrix<double, 2, kN>::Zero();
  H(0, ekf::kVx) = 1.0;
  H(1, ekf::kVy) = 1.0;
  const Vec2 y(-x[ekf::kVx], -x[ekf::kVy]);
  Update<2>(y, H, Mat2::Identity() * (*sigma * *sigma));
  ++diag.sensors[setup.imu_id].events["zero_velocity_updates"];
}

}  // namespace statebench::est
