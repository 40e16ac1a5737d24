// What a speed reading says about a standstill without a speed encoder, once the IMU is quiet
// (imu_still_window.hpp) and the measured acceleration low (each estimator tests that in its own
// model): shared by the factor graph's zero-velocity factor (motion_constraint_front_end.hpp) and
// the EKF's zero-velocity update (ZeroVelocityOptions).
#pragma once

#include <algorithm>
#include <cmath>
#include <optional>

#include "core/eigen_types.hpp"
#include "estimator/doppler_window.hpp"
#include "estimator/motion_factor_options.hpp"

namespace statebench::est {

// The estimated horizontal speed is within max_estimated_speed_mps + estimated_speed_sigmas x
// its sigma (along the estimated velocity; P_h its horizontal covariance, in any frame the
// velocity is in) of zero: in a GNSS outage the speed drifts away from a stop the IMU shows (a
// tilt error of 0.01 rad leaks 0.1 m/s^2 of gravity).
inline bool EstimatedSpeedNearZero(const Vec2& v_h, double v_z, const Mat2& P_h,
                                   const ZeroVelocityOptions& z) {
  const double speed = v_h.norm();
  double sigma = 0.0;
  if (speed > 0.0) {
    const Vec2 u = v_h / speed;
    sigma = std::sqrt(std::max(0.0, u.dot(P_h * u)));
  }
  return std::hypot(speed, v_z) < z.max_estimated_speed_mps + z.estimated_speed_sigmas * sigma;
}

// The zero-velocity sigma without an encoder, nullopt when the speed reading says the vehicle
// moves. With Doppler: its mean below max_doppler_speed_mps; the sigma is the creep the reading
// cannot rule out: that mean's own sigma when the mean agrees with zero within
// doppler_agreement_sigmas of it (within [sigma_mps, sigma_without_encoder_mps]), else
// sigma_without_encoder_mps. Without Doppler (none in the setup, or a GNSS outage):
// estimated_speed_near_zero() (called only then), sigma_without_encoder_mps.
template <typename EstimatedSpeedTest>
std::optional<double> ZeroVelocitySigmaWithoutEncoder(const ZeroVelocityOptions& z,
                                                      const std::optional<DopplerMean>& doppler,
                                                      const EstimatedSpeedTest& estimated_speed_near_zero) {
  if (!doppler) {
    if (!estimated_speed_near_zero()) return std::nullopt;
    return z.sigma_without_encoder_mps;
  }
  if (!(doppler->v_enu.norm() < z.max_doppler_speed_mps)) return std::nullopt;
  const double sigma = doppler->sigma_enu.maxCoeff();
  if (sigma > 0.0 &&
      doppler->v_enu.cwiseQuotient(doppler->sigma_enu).norm() < z.doppler_agreement_sigmas) {
    return std::min(std::max(sigma, z.sigma_mps), z.sigma_without_encoder_mps);
  }
  return z.sigma_without_encoder_mps;
}

}  // namespace statebench::est
