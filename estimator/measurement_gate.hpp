// Innovation tests for GNSS positions and dual-antenna headings against a predicted state with
// its covariance, and the heading of a baseline between two simultaneous fixes.
//
// GNSS antenna position, predicted h(x) = p + R l (l = p_imu_antenna), innovation y = z - h(x):
//   H = [-R [l]x, I, 0, 0, 0]   (core/state.hpp ordering, right rotation perturbation)
//   d^2 = y^T (H P H^T + C_fix)^-1 y
// GNSS antenna velocity, predicted h(x) = v + R (w x l), w = gyro_raw - b_g, u = w x l:
//   H = [-R [u]x, 0, I, R [l]x, 0]
// Heading of the body baseline b_imu (main -> aux), b = R b_imu in ENU:
//   yaw = atan2(b_y, b_x),  pitch = atan2(-b_z, |b_xy|)      (so3::ToRollPitchYaw convention)
//   d yaw / d b   = (-b_y, b_x, 0) / |b_xy|^2
//   d pitch / d b = (b_z b_x / |b_xy|, b_z b_y / |b_xy|, -|b_xy|) / |b|^2
//   d b / d theta = -R [b_imu]x
// The innovation of the yaw is wrapped to (-pi, pi].
#pragma once

#include "core/eigen_types.hpp"
#include "core/measurements.hpp"
#include "estimator/gnss_enu.hpp"
#include "estimator/imu_propagation.hpp"

namespace statebench::est {

// Square root of the largest eigenvalue of a symmetric covariance.
double LargestSigma(const Mat3& covariance);

// How a GNSS fix is used, by its reported ENU covariance: discarded when its horizontal sigma
// (the largest eigenvalue of the horizontal block; the paper's threshold max_sigma) is above
// max_sigma; horizontally only when its vertical sigma is above
// max_vertical_sigma or its vertical variance is not a positive number (a receiver that does
// not know its height, a 2D fix: its horizontal part is still worth having); else in full (also
// when the horizontal block is not finite: the fix's validation, GnssFixToEnu, refuses it).
enum class GnssFixUse { kFull, kHorizontalOnly, kDiscarded };
GnssFixUse FixUse(const Mat3& covariance, double max_sigma, double max_vertical_sigma);

// A vertical variance that carries no information: (1 km)^2.
inline constexpr double kUnusedVerticalVariance = 1e6;

// The covariance with its vertical row and column replaced by kUnusedVerticalVariance and no
// correlation: the fix's height no longer counts.
Mat3 WithoutVertical(const Mat3& covariance);

// Squared Mahalanobis distance of a fix (antenna at p_imu_antenna) from the prediction.
double GnssMahalanobisSquared(const PropagatedState& predicted, const Vec3& p_imu_antenna,
                              const Vec3& p_enu, const Mat3& covariance_enu);

// Squared Mahalanobis distance of an antenna velocity (ENU, diagonal variances), with the raw
// gyro at its stamp.
double GnssVelocityMahalanobisSquared(const PropagatedState& predicted, const Vec3& p_imu_antenna,
                                      const Vec3& gyro_raw, const GnssVelocity& velocity);

// Squared Mahalanobis distance of a heading (yaw, and pitch if its sigma is positive).
double HeadingMahalanobisSquared(const PropagatedState& predicted, const Vec3& baseline_imu,
                                 const DualAntennaHeading& heading);

// Yaw and pitch of p_aux - p_main with sigmas propagated from the two fix covariances (taken
// independent). Header: the main fix's, with sensor_id replaced by heading_id.
DualAntennaHeading HeadingFromFixes(const GnssPositionEnu& main, const GnssPositionEnu& aux,
                                    const std::string& heading_id);

}  // namespace statebench::est
