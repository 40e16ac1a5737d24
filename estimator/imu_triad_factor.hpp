// The preintegrated IMU factor with the IMU's triad errors as globals of the window: each axis's
// scale factor and the cross-axis coupling (misalignment) of the gyro and of the accelerometer.
//
// Sensor model (as a datasheet states it; sensors/imu_triad_errors.hpp draws it so): a triad
// measures y = (I + K) u + b + n, K small (scale factors on its diagonal, cross-axis terms
// off it: MEMS gyros 0.1-1 % and 0.1-0.5 %, shared/REFERENCE.md). To first order in K the true
// signal is u = y - b - K y: K acts like a bias that follows the measured signal. Over one
// interval between two states (0.1 s with the default keyframes) the signal changes little,
// so K y is taken at the interval's mean raw signal y_bar (trapezoid over the preintegration's
// nodes) and the factor is ImuFactor's with the bias of state i replaced by
//   b_eff = b_i + (K_g y_bar_gyro, K_a y_bar_accel).
// Its Jacobian w.r.t. an entry K_rc is the bias Jacobian's column r (gyro) or 3 + r (accel)
// times y_bar_c. The error of this mean is second order: K (y - y_bar) over the interval.
// What K does to a car: the yaw rate through the gyro's (x, z) and (y, z) terms turns roll and
// pitch by about K Delta-yaw over a turn (1 mrad per 90 deg at 1e-3 rad), and the z scale the yaw
// itself; gravity through the accelerometer's third column acts as an accelerometer bias.
//
// Parameter blocks: ImuFactor's seven (q_i, p_i, v_i, bias_i, q_j, p_j, v_j), then one scalar
// block per term, in the order given.
#pragma once

#include <ceres/cost_function.h>

#include <vector>

#include "core/eigen_types.hpp"
#include "estimator/imu_factor.hpp"
#include "estimator/imu_preintegration.hpp"

namespace statebench::est {

// One entry K_rc of a triad's error matrix (row == col: the axis's scale factor).
struct ImuTriadTerm {
  enum class Triad { kGyro, kAccel };
  Triad triad = Triad::kGyro;
  int row = 0;
  int col = 0;
};

// The nine entries of a triad's K: scale x, y, z, then the cross-axis terms row by row.
std::vector<ImuTriadTerm> AllTriadTerms(ImuTriadTerm::Triad triad);

// Mean raw (gyro, accel) over the preintegration's nodes (trapezoid in time).
Vec6 MeanRawSignal(const ImuPreintegration& pim);

class ImuTriadFactor final : public ceres::CostFunction {
 public:
  // Throws InputError as ImuFactor does, or on a row or column outside 0..2.
  ImuTriadFactor(ImuPreintegration preintegration, std::vector<ImuTriadTerm> terms);

  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override;

  const std::vector<ImuTriadTerm>& terms() const { return terms_; }
  const Vec6& mean_raw() const { return mean_raw_; }

 private:
  const ImuFactor imu_;
  const std::vector<ImuTriadTerm> terms_;
  const Vec6 mean_raw_;
};

}  // namespace statebench::est
