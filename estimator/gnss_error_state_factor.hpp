// A GNSS receiver's slowly varying error as a state: the fix is the antenna plus an ENU offset
// e (three scalar globals of the window, e_east, e_north, e_up), so a factor r = S (h(x) - z)
// becomes
//   r = S (h(x) + e - z) = r_base + S e,   dr/de_k = S e_k  (the k-th column of S).
// The error itself is a first-order Gauss-Markov process (sliding_window_smoother.hpp,
// AddGlobal with a correlation time): constant within the window, decaying and diffusing as
// states leave it. Wraps a GNSS position factor (GnssPropagatedPositionFactor or
// GnssTimeOffsetFactor); its parameter blocks come first, then the three globals.
#pragma once

#include <ceres/cost_function.h>

#include <memory>

#include "core/eigen_types.hpp"

namespace statebench::est {

class GnssErrorStateFactor final : public ceres::CostFunction {
 public:
  // base: r = S (predicted antenna - fix), three residuals; S its square-root information.
  GnssErrorStateFactor(std::unique_ptr<ceres::CostFunction> base, const Mat3& sqrt_information);

  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override;

 private:
  const std::unique_ptr<ceres::CostFunction> base_;
  const Mat3 sqrt_information_;
  int num_base_blocks_ = 0;
};

}  // namespace statebench::est
